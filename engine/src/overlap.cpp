// Geometry overlap tests and ray casts (being written).
#include "rattle/geometry.h"
