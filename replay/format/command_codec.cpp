#include "format/command_codec.h"

namespace rts::replay {

void encodeCommand(ByteWriter& out, const Command& c) {
  out.u8(uint8_t(c.type));
  out.u8(c.team);
  switch (c.type) {
    case CommandType::Move:
    case CommandType::Stop:
      out.varint(c.units.size());
      for (uint32_t id : c.units) out.varint(id);
      if (c.type == CommandType::Move) {
        out.f64(c.target.x);
        out.f64(c.target.y);
      }
      break;
    case CommandType::ToggleGate: out.varint(c.gate); break;
    // No fields but a reserved 0: every command takes at least three bytes, which bounds what a count of
    // commands may make a reader allocate.
    case CommandType::ReloadWorld:
      out.varint(0);
      break;
  }
}

Command decodeCommand(ByteReader& in, const ReplayConfig& config, uint32_t tick, const std::string& field) {
  Command c;
  c.tick = tick;
  const size_t typeAt = in.offset();
  const uint8_t type = in.u8(field + " type");
  const uint8_t team = in.u8(field + " team");
  if (team > 1) in.failAt(in.offset() - 1, field + " team", std::to_string(team) + ": expected 0 or 1");
  c.team = team;
  switch (type) {
    case uint8_t(CommandType::Move):
    case uint8_t(CommandType::Stop): {
      c.type = CommandType(type);
      const size_t n = in.count(field + " unit count", 1, config.unitCount);
      c.units.reserve(n);
      for (size_t i = 0; i < n; ++i) {
        c.units.push_back(uint32_t(in.varint(field + " unit " + std::to_string(i), 0, config.unitCount - 1)));
      }
      if (c.type == CommandType::Move) {
        c.target.x = in.finite(field + " target.x");
        c.target.y = in.finite(field + " target.y");
      }
      break;
    }
    case uint8_t(CommandType::ToggleGate):
      c.type = CommandType::ToggleGate;
      if (config.gateCount == 0) in.fail(field + " gate", "a gate command on a map without gates");
      c.gate = uint32_t(in.varint(field + " gate", 0, config.gateCount - 1));
      break;
    case uint8_t(CommandType::ReloadWorld):
      c.type = CommandType::ReloadWorld;
      in.varint(field + " reserved", 0, 0);
      break;
    default:
      in.failAt(typeAt, field + " type",
                "unknown command type " + std::to_string(type) + " (1 move, 2 stop, 3 toggle gate, 4 reload world)");
  }
  return c;
}

}  // namespace rts::replay
