// The facts about a build that can change the engine's arithmetic, as a replay records them: the
// engine's version, the compiler and its version, the flags, the floating-point settings the compiler
// reports, the architecture, the standard library.
#pragma once

#include <string>
#include <vector>

#include "format/replay.h"

namespace rts::replay {

/// This build's facts (the flags as CMake configured them, the rest from the compiler's own macros).
std::vector<BuildFact> thisBuild();

/// One line per fact that differs, e.g. `compiler: recorded "GNU 12.2.0", this build "Clang 14.0.6"`.
/// Empty when the builds agree.
std::vector<std::string> buildDifferences(const std::vector<BuildFact>& recorded, const std::vector<BuildFact>& current);

}  // namespace rts::replay
