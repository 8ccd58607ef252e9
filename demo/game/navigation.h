// Where to go: flow fields. For a target, one Dijkstra pass over a grid of the map (1 world unit per
// cell) gives every cell its walking distance to the target around walls, buildings and closed gates,
// through doorways; a unit then only needs the field's downhill direction where it stands. One field
// serves every unit sent to the same place (a Move command makes one field for its whole group), so
// the cost does not grow with the number of units. Fields are cached by target cell and gate states.
//
// This is the standard RTS answer to "many units, one destination"; per-unit path searches would cost
// a search per unit per order.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "game/physics.h"
#include "map/map.h"

namespace rts {

struct FlowField {
  int targetCell = 0;
  uint32_t gatesOpen = 0;           ///< bit g: gate g was open when the field was made
  int layer = 0;                    ///< the clearance it was made for (Navigation's constructor)
  std::vector<float> distance;      ///< per cell; infinity where the target cannot be reached
};

class Navigation {
 public:
  /// Marks which cells a unit needing each of `clearances` (a layer each; a unit of radius r needs about
  /// r) can stand in, asking the physics about walls. A wider unit cannot take the gaps a narrow one
  /// can, so its fields are made on its own layer.
  Navigation(const Map& map, const Physics& physics, const std::vector<double>& clearances);

  /// The field toward `target` with the given gates open (bit g for gate g), for units of the given
  /// layer; cached.
  std::shared_ptr<const FlowField> field(Vec2 target, uint32_t gatesOpen, uint32_t tick, int layer = 0);
  /// The field toward the centre of `cell` (a FlowField's targetCell), cached likewise: a field is a
  /// function of its cell, gates and layer alone, so this gives one equal to any made for them.
  std::shared_ptr<const FlowField> fieldForCell(int cell, uint32_t gatesOpen, uint32_t tick, int layer);
  int cellCount() const { return nx_ * ny_; }
  /// The walking distance from p to the field's target, or infinity.
  double distance(const FlowField& field, Vec2 p) const;
  /// Which way to walk from p: a unit vector downhill, or {0, 0} when no way is known from here.
  Vec2 direction(const FlowField& field, Vec2 p) const;

  /// The room whose polygon contains p, or -1 (the open field).
  int roomAt(Vec2 p) const;

  int columns() const { return nx_; }
  int rows() const { return ny_; }
  double cellSize() const { return 1.0; }
  int layers() const { return int(layers_.size()); }
  bool walkable(int cell, uint32_t gatesOpen, int layer = 0) const;

 private:
  int cellAt(Vec2 p) const;
  Vec2 centre(int cell) const;
  std::shared_ptr<const FlowField> build(int targetCell, uint32_t gatesOpen, int layer) const;

  int nx_ = 0, ny_ = 0;
  struct Layer {
    std::vector<uint8_t> blocked;      // by a wall or building
    std::vector<uint32_t> gateClosed;  // bit g: blocked while gate g is closed
    std::vector<uint32_t> gateOpen;    // bit g: blocked while gate g is open (where it slides to)
  };
  std::vector<Layer> layers_;
  std::vector<std::vector<Vec2>> rooms_;
  struct Cached {
    std::shared_ptr<const FlowField> field;
    uint32_t lastUsed = 0;
  };
  std::vector<Cached> cache_;
};

}  // namespace rts
