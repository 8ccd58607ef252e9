// rattle-bench: rattle's three step modes (discrete, hybrid, predictive) behind the Engine interface.
//
// One static body holds the walls (Segment fixtures) and the sensor strips (Polygon sensor fixtures);
// each disk is a dynamic body with one Circle fixture of the scene's density and restitution (walls get
// the same restitution; rattle combines two by taking the larger). In a scene whose disks must not meet,
// every disk is in collision group 1 (members of one nonzero group never touch) and the walls and sensors
// in none. Everything else is rattle's default (WorldDef), except collapseTime when --collapse-time sets it.
// The collisions counted are the contact events of each step.
#include <stdexcept>
#include <string>

#include "engine.h"
#include "rattle/rattle.h"

namespace rattle_bench {

namespace {

class RattleEngine final : public Engine {
 public:
  RattleEngine(const Scene& scene, RattleMode mode, double collapseTime)
      : world_(worldDef(scene, mode, collapseTime)) {
    rattle::BodyDef ground;
    ground.type = rattle::BodyType::Static;
    const rattle::BodyId groundId = world_.createBody(ground);
    for (const Wall& w : scene.walls) {
      rattle::FixtureDef fd;
      fd.geometry = rattle::Segment{w.a, w.b};
      fd.restitution = scene.restitution;
      world_.createFixture(groundId, fd);
    }
    for (const SensorStrip& s : scene.sensors) {
      rattle::FixtureDef fd;
      fd.geometry = rattle::Polygon{s.points};
      fd.sensor = true;
      sensorIndex_.push_back(world_.createFixture(groundId, fd).index);
    }
    bodies_.reserve(scene.disks.size());
    for (size_t i = 0; i < scene.disks.size(); ++i) {
      const DiskStart& d = scene.disks[i];
      rattle::BodyDef bd;
      bd.type = rattle::BodyType::Dynamic;
      bd.position = d.position;
      bd.velocity = d.velocity;
      const rattle::BodyId id = world_.createBody(bd);
      rattle::FixtureDef fd;
      fd.geometry = rattle::Circle{{0, 0}, d.radius};
      fd.density = d.density;
      fd.restitution = scene.restitution;
      if (!scene.disksCollide) fd.filter.group = 1;
      world_.createFixture(id, fd);
      bodies_.push_back(id);
      if (id.index >= diskOfBody_.size()) diskOfBody_.resize(id.index + 1, -1);
      diskOfBody_[id.index] = static_cast<int>(i);
    }
    sensorBegins.assign(scene.sensors.size() * scene.disks.size(), 0);
  }

  void step(double dt) override { world_.step(dt); }

  void collect() override {
    collisions += static_cast<long long>(world_.contactEvents().size());
    for (const rattle::SensorEvent& e : world_.sensorEvents()) {
      if (!e.begin) continue;
      const int disk = e.visitorBody.index < diskOfBody_.size() ? diskOfBody_[e.visitorBody.index] : -1;
      for (size_t s = 0; s < sensorIndex_.size(); ++s)
        if (sensorIndex_[s] == e.sensor.index && disk >= 0) ++sensorBegins[s * bodies_.size() + static_cast<size_t>(disk)];
    }
    if (world_.stats().eventBudgetReached) ++budgetSteps_;
    if (budgetSteps_ > 0)
      notes = "event budget (WorldDef::maxEventsPerStep) reached in " + std::to_string(budgetSteps_) + " steps";
  }

  void state(std::vector<Vec2>& positions, std::vector<Vec2>& velocities) const override {
    positions.resize(bodies_.size());
    velocities.resize(bodies_.size());
    for (size_t i = 0; i < bodies_.size(); ++i) {
      positions[i] = world_.position(bodies_[i]);
      velocities[i] = world_.velocity(bodies_[i]);
    }
  }

 private:
  static rattle::WorldDef worldDef(const Scene& scene, RattleMode mode, double collapseTime) {
    rattle::WorldDef def;
    def.mode = mode == RattleMode::Discrete   ? rattle::StepMode::Discrete
               : mode == RattleMode::Hybrid   ? rattle::StepMode::Hybrid
                                              : rattle::StepMode::Predictive;
    def.gravity = scene.gravity;
    def.collapseTime = collapseTime;
    return def;
  }

  rattle::World world_;
  std::vector<rattle::BodyId> bodies_;
  std::vector<int> diskOfBody_;       // body slot index -> disk index
  std::vector<uint32_t> sensorIndex_;  // sensor strip -> fixture slot index
  long long budgetSteps_ = 0;
};

}  // namespace

std::unique_ptr<Engine> makeRattleEngine(const Scene& scene, RattleMode mode, double collapseTime) {
  return std::make_unique<RattleEngine>(scene, mode, collapseTime);
}

}  // namespace rattle_bench
