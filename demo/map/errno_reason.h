// Why a file could not be opened, for the messages of the map, replay and script readers. Header-only,
// so the replay format's library, which links no demo code, shares it (as map/printable.h).
#pragma once

#include <cerrno>
#include <cstring>
#include <string>

namespace rts {

/// ": " and errno's description (": No such file or directory"), or "" when errno is 0. Clear errno
/// before the attempt and call this right after it fails: a stream does not promise to set errno.
inline std::string errnoReason() { return errno != 0 ? std::string(": ") + std::strerror(errno) : std::string(); }

}  // namespace rts
