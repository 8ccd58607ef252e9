#include "format/snapshot_codec.h"

#include <limits>

#include "format/checksum.h"
#include "format/limits.h"

namespace rts::replay {
namespace {

constexpr int64_t kMaxCounter = int64_t(1) << 62;
constexpr int64_t kInt32Min = std::numeric_limits<int32_t>::min(), kInt32Max = std::numeric_limits<int32_t>::max();

// Smallest encodings, to bound counts by the bytes left before allocating.
constexpr size_t kMinUnitBytes = 3;    // flags, hit points, reload
constexpr size_t kMinShotBytes = 38;   // id, team, shooter, ticks left, body (2), 4 doubles
constexpr size_t kMinGateBytes = 41;   // wantOpen, 5 doubles

std::string at(const std::string& where, const char* what, size_t i) { return where + " " + what + " " + std::to_string(i); }

CountersState decodeCounters(ByteReader& in, const ReplayConfig& c, const std::string& where) {
  CountersState s;
  s.shotsFired = in.zigzag(where + " shotsFired", 0, kMaxCounter);
  s.wallHits = in.zigzag(where + " wallHits", 0, kMaxCounter);
  s.unitHits = in.zigzag(where + " unitHits", 0, kMaxCounter);
  s.crossings = in.zigzag(where + " crossings", 0, kMaxCounter);
  s.losses[0] = in.zigzag(where + " losses[0]", 0, kMaxCounter);
  s.losses[1] = in.zigzag(where + " losses[1]", 0, kMaxCounter);
  if (c.doorwayCount > in.remaining() / 2) in.fail(where + " doorways", "the doorway counts cannot fit in the bytes left");
  s.doorwayCrossings.resize(c.doorwayCount);
  for (size_t d = 0; d < c.doorwayCount; ++d) {
    for (int t = 0; t < 2; ++t) {
      s.doorwayCrossings[d][size_t(t)] = uint32_t(in.varint(at(where, "doorway", d) + " crossings[" + std::to_string(t) + "]", 0, UINT32_MAX));
    }
  }
  if (c.roomCount > in.remaining()) in.fail(where + " rooms", "the room holders cannot fit in the bytes left");
  s.roomHolders.resize(c.roomCount);
  for (size_t r = 0; r < c.roomCount; ++r) {
    s.roomHolders[r] = int8_t(int(in.u8(at(where, "room", r) + " holder")) - 1);
    if (s.roomHolders[r] > 2) in.failAt(in.offset() - 1, at(where, "room", r) + " holder", "expected 0 to 3 (nobody, blue, red, contested)");
  }
  return s;
}

MotionState decodeMotion(ByteReader& in, const std::string& field) {
  MotionState m;
  m.px = in.finite(field + " position.x");
  m.py = in.finite(field + " position.y");
  m.vx = in.finite(field + " velocity.x");
  m.vy = in.finite(field + " velocity.y");
  return m;
}

void encodeMotion(ByteWriter& out, const MotionState& m) {
  out.f64(m.px);
  out.f64(m.py);
  out.f64(m.vx);
  out.f64(m.vy);
}

UnitState decodeUnit(ByteReader& in, const std::string& field) {
  UnitState s;
  const size_t flagsAt = in.offset();
  const uint8_t flags = in.u8(field + " flags");
  if (flags & ~3u) in.failAt(flagsAt, field + " flags", "unknown flag bits " + std::to_string(flags));
  s.alive = flags & 1;
  s.orderActive = flags & 2;
  if (s.orderActive && !s.alive) in.failAt(flagsAt, field + " flags", "a dead unit with an active order");
  s.hitPoints = int32_t(in.zigzag(field + " hitPoints", kInt32Min, kInt32Max));
  s.reloadTicks = int32_t(in.zigzag(field + " reloadTicks", kInt32Min, kInt32Max));
  if (s.alive) {
    s.bodyIndex = uint32_t(in.varint(field + " body index", 0, UINT32_MAX));
    s.bodyGeneration = uint32_t(in.varint(field + " body generation", 1, UINT32_MAX));
    s.motion = decodeMotion(in, field);
  }
  if (s.orderActive) {
    s.targetX = in.finite(field + " order.target.x");
    s.targetY = in.finite(field + " order.target.y");
  }
  return s;
}

ShotState decodeShot(ByteReader& in, const std::string& field) {
  ShotState s;
  s.id = uint32_t(in.varint(field + " id", 0, UINT32_MAX));
  s.team = in.u8(field + " team");
  if (s.team > 1) in.failAt(in.offset() - 1, field + " team", std::to_string(s.team) + ": expected 0 or 1");
  s.shooter = uint32_t(in.varint(field + " shooter", 0, UINT32_MAX));
  s.ticksLeft = int32_t(in.zigzag(field + " ticksLeft", kInt32Min, kInt32Max));
  s.bodyIndex = uint32_t(in.varint(field + " body index", 0, UINT32_MAX));
  s.bodyGeneration = uint32_t(in.varint(field + " body generation", 1, UINT32_MAX));
  s.motion = decodeMotion(in, field);
  return s;
}

GateBodyState decodeGate(ByteReader& in, const std::string& field) {
  GateBodyState s;
  s.wantOpen = in.flag(field + " wantOpen");
  s.openness = in.finite(field + " openness");
  s.motion = decodeMotion(in, field);
  return s;
}

}  // namespace

void encodeCounters(ByteWriter& out, const CountersState& s) {
  out.zigzag(s.shotsFired);
  out.zigzag(s.wallHits);
  out.zigzag(s.unitHits);
  out.zigzag(s.crossings);
  out.zigzag(s.losses[0]);
  out.zigzag(s.losses[1]);
  for (const auto& d : s.doorwayCrossings) {
    out.varint(d[0]);
    out.varint(d[1]);
  }
  for (int8_t h : s.roomHolders) out.u8(uint8_t(h + 1));
}

void encodeUnit(ByteWriter& out, const UnitState& s) {
  out.u8(uint8_t(s.alive) | uint8_t(s.orderActive && s.alive) << 1);
  out.zigzag(s.hitPoints);
  out.zigzag(s.reloadTicks);
  if (s.alive) {
    out.varint(s.bodyIndex);
    out.varint(s.bodyGeneration);
    encodeMotion(out, s.motion);
    if (s.orderActive) {
      out.f64(s.targetX);
      out.f64(s.targetY);
    }
  }
}

void encodeShot(ByteWriter& out, const ShotState& s) {
  out.varint(s.id);
  out.u8(s.team);
  out.varint(s.shooter);
  out.zigzag(s.ticksLeft);
  out.varint(s.bodyIndex);
  out.varint(s.bodyGeneration);
  encodeMotion(out, s.motion);
}

void encodeGate(ByteWriter& out, const GateBodyState& s) {
  out.u8(uint8_t(s.wantOpen));
  out.f64(s.openness);
  encodeMotion(out, s.motion);
}

void encodeSnapshot(ByteWriter& out, const Snapshot& s) {
  encodeCounters(out, s.counters);
  for (const UnitState& u : s.units) encodeUnit(out, u);
  out.varint(s.shots.size());
  for (const ShotState& sh : s.shots) encodeShot(out, sh);
  for (const GateBodyState& g : s.gates) encodeGate(out, g);
}

Snapshot decodeSnapshot(ByteReader& in, const ReplayConfig& c, const std::string& where) {
  Snapshot s;
  s.counters = decodeCounters(in, c, where + " counters");
  if (c.unitCount > in.remaining() / kMinUnitBytes) in.fail(where + " units", std::to_string(c.unitCount) + " units cannot fit in the bytes left");
  s.units.reserve(c.unitCount);
  for (size_t i = 0; i < c.unitCount; ++i) s.units.push_back(decodeUnit(in, at(where, "unit", i)));
  const size_t shots = in.count(where + " shot count", kMinShotBytes, UINT32_MAX);
  s.shots.reserve(shots);
  for (size_t i = 0; i < shots; ++i) {
    const size_t idAt = in.offset();
    s.shots.push_back(decodeShot(in, at(where, "shot", i)));
    if (i > 0 && s.shots[i].id <= s.shots[i - 1].id) in.failAt(idAt, at(where, "shot", i) + " id", "shot ids must ascend");
  }
  if (c.gateCount > in.remaining() / kMinGateBytes) in.fail(where + " gates", std::to_string(c.gateCount) + " gates cannot fit in the bytes left");
  s.gates.reserve(c.gateCount);
  for (size_t g = 0; g < c.gateCount; ++g) s.gates.push_back(decodeGate(in, at(where, "gate", g)));
  return s;
}

Digests digestsOf(const Snapshot& s) {
  Digests d;
  ByteWriter scratch;
  encodeCounters(scratch, s.counters);
  d.counters = digest16(scratch.data());
  d.units.reserve(s.units.size());
  for (const UnitState& u : s.units) {
    scratch.clear();
    encodeUnit(scratch, u);
    d.units.push_back(digest16(scratch.data()));
  }
  d.shots.reserve(s.shots.size());
  for (const ShotState& sh : s.shots) {
    scratch.clear();
    encodeShot(scratch, sh);
    d.shots.push_back({sh.id, digest16(scratch.data())});
  }
  d.gates.reserve(s.gates.size());
  for (const GateBodyState& g : s.gates) {
    scratch.clear();
    encodeGate(scratch, g);
    d.gates.push_back(digest16(scratch.data()));
  }
  return d;
}

}  // namespace rts::replay
