// rattle: a 2D collision engine with exact times of impact. This header includes the whole public API.
#pragma once

#include "rattle/geometry.h"
#include "rattle/time_of_impact.h"
#include "rattle/types.h"
#include "rattle/vec2.h"
#include "rattle/world.h"
