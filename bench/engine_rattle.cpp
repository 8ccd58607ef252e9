// rattle-bench: rattle's three step modes (discrete, hybrid, predictive) behind the Engine interface.
//
// The world is the scene as addToWorld (scenes.h) builds it: one static body with the walls and sensor
// strips, a dynamic circle per disk (rattle combines two restitutions by taking the larger; disks that must
// not meet share collision group 1, whose members never touch). Everything else is rattle's default
// (WorldDef), except collapseTime when --collapse-time sets it.
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
    const RattleScene built = addToWorld(world_, scene);
    for (const rattle::FixtureId f : built.sensors) sensorIndex_.push_back(f.index);
    bodies_ = built.disks;
    for (size_t i = 0; i < bodies_.size(); ++i) {
      const rattle::BodyId id = bodies_[i];
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

  void setVelocities(const std::vector<Vec2>& velocities) override {
    for (size_t i = 0; i < bodies_.size(); ++i) world_.setVelocity(bodies_[i], velocities[i]);
  }

  long long asleep() const override {
    long long n = 0;
    for (const rattle::BodyId b : bodies_) n += world_.isAsleep(b) ? 1 : 0;
    return n;
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
