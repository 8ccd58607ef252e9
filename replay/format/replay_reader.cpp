// The chunk sequence (FORMAT.md, "Chunks"): BILD MAPJ CONF INIT KEYF(0) { TICK [KEYF] } END!
#include "format/replay_reader.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>

#include "format/byte_reader.h"
#include "format/checksum.h"
#include "format/command_codec.h"
#include "format/limits.h"
#include "format/snapshot_codec.h"
#include "map/errno_reason.h"
#include "map/printable.h"

namespace rts::replay {
namespace {

constexpr size_t kMinCommandBytes = 3;  // type, team, a count or a gate

std::string tagText(std::string_view tag) {
  std::string out;
  for (char c : tag) out += (c >= 32 && c < 127 && c != '\'') ? c : '?';
  return "'" + out + "'";
}

class Parser {
 public:
  explicit Parser(std::string_view file) : file_(file) {}

  Replay run() {
    ByteReader head(file_, 0);
    const std::string_view magic = head.bytes("magic", std::min<size_t>(8, file_.size()));
    if (magic.size() < 8 || std::memcmp(magic.data(), kMagic, 8) != 0) {
      head.failAt(0, "magic", "not a rattle replay (a replay starts with the 8 bytes \"RATTLREP\")");
    }
    r_.version = head.u16("format version");
    if (r_.version != kFormatVersion) {
      head.failAt(8, "format version", "version " + std::to_string(r_.version) + "; this build reads version " +
                                           std::to_string(kFormatVersion) + " only");
    }
    size_t pos = 10;
    bool ended = false;
    while (!ended) {
      ByteReader frame(file_.substr(pos), pos);
      if (frame.atEnd()) frame.fail("chunk", "the file ends before the END! chunk (truncated?)");
      const std::string_view tag = frame.bytes("chunk tag", std::min<size_t>(4, frame.remaining()));
      if (tag.size() < 4) frame.failAt(pos, "chunk tag", "truncated chunk header");
      const size_t lengthAt = frame.offset();
      const uint32_t length = frame.u32("chunk " + tagText(tag) + " length");
      if (length > kMaxChunkBytes) {
        frame.failAt(lengthAt, "chunk " + tagText(tag) + " length", std::to_string(length) + " bytes; at most " + std::to_string(kMaxChunkBytes));
      }
      if (size_t(length) + 4 > frame.remaining()) {
        frame.failAt(pos, "chunk " + tagText(tag), "truncated: its payload and checksum need " + std::to_string(size_t(length) + 4) +
                                                       " bytes, " + std::to_string(frame.remaining()) + " left");
      }
      const std::string_view payload = frame.bytes("payload", length);
      const size_t crcAt = frame.offset();
      const uint32_t stored = frame.u32("chunk checksum");
      const uint32_t actual = crc32(file_.data() + pos, 8 + size_t(length));
      if (stored != actual) {
        frame.failAt(crcAt, "chunk " + tagText(tag) + " at byte " + std::to_string(pos) + " checksum",
                     "CRC-32 mismatch (stored " + hex32(stored) + ", computed " + hex32(actual) + "): the chunk is corrupted");
      }
      ByteReader in(payload, pos + 8);
      ended = chunk(tag, in, pos);
      pos += 12 + size_t(length);
    }
    if (pos != file_.size()) {
      ByteReader(file_, 0).failAt(pos, "end of file", std::to_string(file_.size() - pos) + " bytes after the END! chunk");
    }
    return std::move(r_);
  }

 private:
  enum class Expect { Build, Map, Config, Init, FirstKeyframe, Ticks };

  static std::string hex32(uint32_t v) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "%08x", v);
    return buf;
  }

  // Returns true after END!.
  bool chunk(std::string_view tag, ByteReader& in, size_t chunkAt) {
    auto is = [&](const char* t) { return tag == std::string_view(t, 4); };
    auto wrongPlace = [&](const char* expected) {
      in.failAt(chunkAt, "chunk " + tagText(tag), std::string("expected ") + expected + " here");
    };
    switch (expect_) {
      case Expect::Build:
        if (!is("BILD")) wrongPlace("the BILD chunk (build facts)");
        readBuild(in);
        expect_ = Expect::Map;
        return false;
      case Expect::Map:
        if (!is("MAPJ")) wrongPlace("the MAPJ chunk (the map)");
        readMap(in);
        expect_ = Expect::Config;
        return false;
      case Expect::Config:
        if (!is("CONF")) wrongPlace("the CONF chunk (the game's configuration)");
        readConfig(in);
        expect_ = Expect::Init;
        return false;
      case Expect::Init:
        if (!is("INIT")) wrongPlace("the INIT chunk (the state at tick 0)");
        r_.initialStateHash = in.u64("INIT stateHash");
        r_.initialWorldHash = in.u64("INIT worldHash");
        in.expectEnd("INIT");
        expect_ = Expect::FirstKeyframe;
        return false;
      case Expect::FirstKeyframe:
        if (!is("KEYF")) wrongPlace("the KEYF chunk of tick 0");
        readKeyframe(in, chunkAt);
        expect_ = Expect::Ticks;
        return false;
      case Expect::Ticks: break;
    }
    const uint32_t last = r_.tickCount();
    const bool keyframeDue = last > 0 && last % r_.config.keyframeEvery == 0 && r_.keyframes.back().tick != last;
    if (is("KEYF")) {
      if (extraKeyframe_) in.failAt(chunkAt, "chunk 'KEYF'", "a second keyframe for tick " + std::to_string(last));
      if (last == 0 || r_.keyframes.back().tick == last) in.failAt(chunkAt, "chunk 'KEYF'", "a keyframe with no TICK before it");
      readKeyframe(in, chunkAt);
      // One off the schedule is allowed only for the last tick: END! must follow.
      extraKeyframe_ = !keyframeDue;
      return false;
    }
    if (keyframeDue) in.failAt(chunkAt, "chunk " + tagText(tag), "tick " + std::to_string(last) + " has no keyframe (one is due every " +
                                                                       std::to_string(r_.config.keyframeEvery) + " ticks)");
    if (extraKeyframe_ && !is("END!")) {
      in.failAt(chunkAt, "chunk " + tagText(tag), "a keyframe off the schedule is allowed only at the last tick (expected END!)");
    }
    if (is("TICK")) {
      readTick(in);
      return false;
    }
    if (is("END!")) {
      readEnd(in, chunkAt);
      return true;
    }
    in.failAt(chunkAt, "chunk " + tagText(tag), "unknown chunk (expected TICK, KEYF or END!)");
  }

  void readBuild(ByteReader& in) {
    const size_t n = in.count("BILD fact count", 2, kMaxBuildFacts);
    r_.build.reserve(n);
    for (size_t i = 0; i < n; ++i) {
      BuildFact f;
      const size_t keyAt = in.offset();
      f.key = in.str("BILD fact " + std::to_string(i) + " key", kMaxFactKeyBytes);
      if (f.key.empty()) in.failAt(keyAt, "BILD fact " + std::to_string(i) + " key", "empty");
      f.value = in.str("BILD fact " + std::to_string(i) + " (" + printable(f.key) + ") value", kMaxFactValueBytes);
      r_.build.push_back(std::move(f));
    }
    in.expectEnd("BILD");
  }

  void readMap(ByteReader& in) {
    r_.mapName = in.str("MAPJ name", kMaxNameBytes);
    const size_t hashAt = in.offset();
    r_.mapHash = in.u64("MAPJ hash");
    if (in.remaining() > kMaxMapBytes) in.fail("MAPJ json", std::to_string(in.remaining()) + " bytes of map; at most " + std::to_string(kMaxMapBytes));
    if (in.remaining() == 0) in.fail("MAPJ json", "the map is empty");
    r_.mapJson = std::string(in.bytes("MAPJ json", in.remaining()));
    if (fnv1a64(r_.mapJson) != r_.mapHash) in.failAt(hashAt, "MAPJ hash", "the embedded map's FNV-1a hash does not match: the map was changed");
  }

  void readConfig(ByteReader& in) {
    ReplayConfig& c = r_.config;
    c.seed = in.u64("CONF seed");
    c.unitsPerTeam = uint32_t(in.varint("CONF unitsPerTeam", 1, kMaxUnitsPerTeam));
    const size_t modeAt = in.offset();
    c.stepMode = in.u8("CONF stepMode");
    if (c.stepMode > 2) in.failAt(modeAt, "CONF stepMode", std::to_string(c.stepMode) + ": expected 0 (hybrid), 1 (discrete) or 2 (predictive)");
    c.weapons = in.flag("CONF weapons");
    const size_t teamsAt = in.offset();
    c.opponentTeams = in.u8("CONF opponentTeams");
    if (c.opponentTeams > 3) in.failAt(teamsAt, "CONF opponentTeams", std::to_string(c.opponentTeams) + ": expected 0 to 3");
    c.keyframeEvery = uint32_t(in.varint("CONF keyframeEvery", 1, kMaxKeyframeEvery));
    const size_t countAt = in.offset();
    c.unitCount = uint32_t(in.varint("CONF unitCount", 0, 2 * kMaxUnitsPerTeam));
    if (c.unitCount != 2 * c.unitsPerTeam) in.failAt(countAt, "CONF unitCount", std::to_string(c.unitCount) + ": expected twice unitsPerTeam");
    c.gateCount = uint32_t(in.varint("CONF gateCount", 0, kMaxGates));
    c.doorwayCount = uint32_t(in.varint("CONF doorwayCount", 0, kMaxDoorways));
    c.roomCount = uint32_t(in.varint("CONF roomCount", 0, kMaxRooms));
    c.recordedBy = in.str("CONF recordedBy", kMaxNameBytes);
    in.expectEnd("CONF");
  }

  void readKeyframe(ByteReader& in, size_t chunkAt) {
    const uint32_t expected = r_.tickCount();
    const size_t tickAt = in.offset();
    const uint64_t tick = in.varint("KEYF tick");
    if (tick != expected) in.failAt(tickAt, "KEYF tick", std::to_string(tick) + ": expected " + std::to_string(expected) + " (the last TICK's)");
    (void)chunkAt;
    Keyframe k;
    k.tick = expected;
    k.state = decodeSnapshot(in, r_.config, "keyframe " + std::to_string(expected));
    in.expectEnd("keyframe " + std::to_string(expected));
    r_.keyframes.push_back(std::move(k));
  }

  void readTick(ByteReader& in) {
    const uint32_t expected = r_.tickCount() + 1;
    if (expected > kMaxTicks) in.fail("TICK", "more than " + std::to_string(kMaxTicks) + " ticks");
    const std::string where = "tick " + std::to_string(expected);
    const size_t tickAt = in.offset();
    const uint64_t tick = in.varint(where + " number");
    if (tick != expected) in.failAt(tickAt, where + " number", std::to_string(tick) + ": ticks must count up from 1 without gaps");
    TickRecord t;
    t.tick = expected;
    t.stateHash = in.u64(where + " stateHash");
    t.worldHash = in.u64(where + " worldHash");
    const size_t commands = in.count(where + " command count", kMinCommandBytes, UINT32_MAX);
    t.commands.reserve(commands);
    for (size_t i = 0; i < commands; ++i) {
      t.commands.push_back(decodeCommand(in, r_.config, expected - 1, where + " command " + std::to_string(i)));
    }
    Digests& d = t.digests;
    d.counters = in.u16(where + " counters digest");
    if (r_.config.unitCount > in.remaining() / 2) in.fail(where + " unit digests", std::to_string(r_.config.unitCount) + " unit digests cannot fit in the bytes left");
    d.units.resize(r_.config.unitCount);
    for (size_t u = 0; u < d.units.size(); ++u) d.units[u] = in.u16(where + " unit " + std::to_string(u) + " digest");
    const size_t shots = in.count(where + " shot count", 3, UINT32_MAX);
    d.shots.reserve(shots);
    uint64_t id = 0;
    for (size_t s = 0; s < shots; ++s) {
      const size_t gapAt = in.offset();
      const uint64_t gap = in.varint(where + " shot " + std::to_string(s) + " id gap", 0, UINT32_MAX);
      id = s == 0 ? gap : id + 1 + gap;
      if (id > UINT32_MAX) in.failAt(gapAt, where + " shot " + std::to_string(s) + " id gap", "shot id beyond 2^32 - 1");
      d.shots.push_back({uint32_t(id), in.u16(where + " shot " + std::to_string(s) + " digest")});
    }
    if (r_.config.gateCount > in.remaining() / 2) in.fail(where + " gate digests", "the gate digests cannot fit in the bytes left");
    d.gates.resize(r_.config.gateCount);
    for (size_t g = 0; g < d.gates.size(); ++g) d.gates[g] = in.u16(where + " gate " + std::to_string(g) + " digest");
    in.expectEnd(where);
    r_.ticks.push_back(std::move(t));
  }

  void readEnd(ByteReader& in, size_t chunkAt) {
    const size_t countAt = in.offset();
    const uint64_t count = in.varint("END! tickCount");
    if (count != r_.tickCount()) {
      in.failAt(countAt, "END! tickCount", std::to_string(count) + ", but the file holds " + std::to_string(r_.tickCount()) + " ticks");
    }
    const size_t hashAt = in.offset();
    const uint64_t finalHash = in.u64("END! finalStateHash");
    const uint64_t lastHash = r_.ticks.empty() ? r_.initialStateHash : r_.ticks.back().stateHash;
    if (finalHash != lastHash) in.failAt(hashAt, "END! finalStateHash", "does not match the last tick's state hash");
    in.expectEnd("END!");
    if (r_.keyframes.back().tick != r_.tickCount()) {
      in.failAt(chunkAt, "chunk 'END!'", "the last tick (" + std::to_string(r_.tickCount()) + ") has no keyframe");
    }
  }

  std::string_view file_;
  Replay r_;
  Expect expect_ = Expect::Build;
  bool extraKeyframe_ = false;
};

}  // namespace

std::string ReadError::describe() const { return "byte " + std::to_string(offset) + ": " + field + ": " + message; }

ReadResult readReplay(std::string_view bytes) noexcept {
  ReadResult result;
  try {
    result.replay = Parser(bytes).run();
  } catch (const FormatError& e) {
    result.replay.reset();
    try {
      result.error = {e.offset(), e.field(), e.what()};
    } catch (...) {
    }
  } catch (const std::bad_alloc&) {
    result.replay.reset();
    result.error.message = "out of memory";
  } catch (...) {
    result.replay.reset();
    result.error.message = "internal error while reading the replay";
  }
  return result;
}

ReadResult readReplay(const uint8_t* data, size_t size) noexcept {
  return readReplay(std::string_view(reinterpret_cast<const char*>(data), data ? size : 0));
}

ReadResult readReplayFile(const std::string& path) noexcept {
  ReadResult result;
  try {
    // A directory opens as a stream whose end is at the largest offset there is: say what it is instead.
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
      result.error = {0, "file", path + ": is a directory, not a replay file"};
      return result;
    }
    errno = 0;
    std::ifstream in(path, std::ios::binary);
    if (!in) {
      result.error = {0, "file", path + ": cannot open" + rts::errnoReason()};
      return result;
    }
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    if (size < 0) {
      result.error = {0, "file", path + ": cannot read"};
      return result;
    }
    if (uint64_t(size) > kMaxFileBytes) {
      result.error = {0, "file", path + ": " + std::to_string(size) + " bytes; replays over " + std::to_string(kMaxFileBytes) + " bytes are refused"};
      return result;
    }
    in.seekg(0);
    std::string bytes(size_t(size), '\0');
    if (!in.read(bytes.data(), size)) {
      result.error = {0, "file", path + ": cannot read"};
      return result;
    }
    return readReplay(bytes);
  } catch (...) {
    result.replay.reset();
    result.error = {0, "file", path + ": cannot read (out of memory?)"};
  }
  return result;
}

}  // namespace rts::replay
