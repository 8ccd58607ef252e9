// Commands in bytes (FORMAT.md, "Commands"). The decoder checks every field against the game's sizes:
// unit ids below the unit count, a gate that exists, a finite target, a known type.
#pragma once

#include <string>

#include "format/byte_reader.h"
#include "format/byte_writer.h"
#include "format/replay.h"

namespace rts::replay {

void encodeCommand(ByteWriter& out, const Command& c);
/// `tick`: the tick the command is stamped with (its record's tick - 1).
Command decodeCommand(ByteReader& in, const ReplayConfig& config, uint32_t tick, const std::string& field);

}  // namespace rts::replay
