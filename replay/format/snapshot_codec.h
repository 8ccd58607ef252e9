// Body states in bytes: the keyframe encoding of each body, which is also what a body's digest hashes.
#pragma once

#include <string>

#include "format/byte_reader.h"
#include "format/byte_writer.h"
#include "format/replay.h"

namespace rts::replay {

void encodeCounters(ByteWriter& out, const CountersState& s);
void encodeUnit(ByteWriter& out, const UnitState& s);
void encodeShot(ByteWriter& out, const ShotState& s);
void encodeGate(ByteWriter& out, const GateBodyState& s);

/// The KEYF payload after its tick: counters, units, shots, gates.
void encodeSnapshot(ByteWriter& out, const Snapshot& s);
/// Reads what encodeSnapshot wrote, for a game of `config`'s sizes. `where` prefixes field names.
Snapshot decodeSnapshot(ByteReader& in, const ReplayConfig& config, const std::string& where);

/// The digest of every body of a snapshot.
Digests digestsOf(const Snapshot& s);

}  // namespace rts::replay
