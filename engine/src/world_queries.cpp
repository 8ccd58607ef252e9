// World queries (being written).
#include "world_impl.h"
