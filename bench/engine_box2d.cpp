// rattle-bench: Box2D 2.4 (Debian's libbox2d-dev) behind the Engine interface, engines `box2d` and
// `box2d-bullet`.
//
// Set up as fairly as Box2D 2.4 allows for rattle's model: every disk a dynamic body with fixed rotation,
// one circle fixture of the scene's density, no friction, the scene's restitution (Box2D mixes two by the
// larger, as rattle does) and a restitution threshold of 0 (the fixture field that replaced
// b2_velocityThreshold in 2.4: every approaching contact bounces, however slow). Walls are two-sided edge
// shapes (which collide at their ends too, as a wall with solid ends must), sensor strips polygon sensors, all on one static body. Disks that must not meet share a negative
// group index. Everything else is Box2D's default: Step(dt, 8 velocity iterations, 3 position iterations),
// sleeping allowed, continuous collision of dynamic bodies against static ones on; `box2d-bullet` also
// marks every disk a bullet (continuous collision between dynamic bodies too).
//
// The crowd's steering sets each disk's velocity with SetLinearVelocity before a step (outside the timing).
//
// Collisions are counted as BeginContact between two physical fixtures (a contact that starts touching;
// a resting contact counts once), in a listener that runs inside Step (it only increments a counter).
// Box2D works in float, and moves no body more than b2_maxTranslation (2 length units) in one step: a
// faster body is slowed to 2 / dt. Both are compiled into the library; the row's notes say when the cap
// bites.
#include <box2d/box2d.h>

#include <algorithm>
#include <string>

#include "engine.h"

namespace rattle_bench {

namespace {

class Box2dEngine final : public Engine, private b2ContactListener {
 public:
  Box2dEngine(const Scene& scene, bool bullets)
      : world_(b2Vec2(static_cast<float>(scene.gravity.x), static_cast<float>(scene.gravity.y))),
        diskCount_(scene.disks.size()) {
    world_.SetContactListener(this);
    b2BodyDef gd;
    b2Body* ground = world_.CreateBody(&gd);
    for (const Wall& w : scene.walls) {
      b2EdgeShape edge;
      edge.SetTwoSided(vec(w.a), vec(w.b));
      b2FixtureDef fd;
      fd.shape = &edge;
      fd.friction = 0;
      fd.restitution = static_cast<float>(scene.restitution);
      fd.restitutionThreshold = 0;
      ground->CreateFixture(&fd);
    }
    for (size_t s = 0; s < scene.sensors.size(); ++s) {
      std::vector<b2Vec2> points;
      for (Vec2 p : scene.sensors[s].points) points.push_back(vec(p));
      b2PolygonShape poly;
      poly.Set(points.data(), static_cast<int32>(points.size()));
      b2FixtureDef fd;
      fd.shape = &poly;
      fd.isSensor = true;
      fd.userData.pointer = s + 1;  // 0 means "not a sensor strip"
      ground->CreateFixture(&fd);
    }
    bodies_.reserve(scene.disks.size());
    for (size_t i = 0; i < scene.disks.size(); ++i) {
      const DiskStart& d = scene.disks[i];
      b2BodyDef bd;
      bd.type = b2_dynamicBody;
      bd.position = vec(d.position);
      bd.linearVelocity = vec(d.velocity);
      bd.fixedRotation = true;
      bd.bullet = bullets;
      bd.userData.pointer = i + 1;
      b2Body* body = world_.CreateBody(&bd);
      b2CircleShape circle;
      circle.m_radius = static_cast<float>(d.radius);
      b2FixtureDef fd;
      fd.shape = &circle;
      fd.density = static_cast<float>(d.density);
      fd.friction = 0;
      fd.restitution = static_cast<float>(scene.restitution);
      fd.restitutionThreshold = 0;
      if (!scene.disksCollide) fd.filter.groupIndex = -1;
      body->CreateFixture(&fd);
      bodies_.push_back(body);
      maxSpeed_ = std::max(maxSpeed_, rattle::length(d.velocity));
    }
    sensorBegins.assign(scene.sensors.size() * scene.disks.size(), 0);
  }

  void step(double dt) override {
    dt_ = dt;
    world_.Step(static_cast<float>(dt), 8, 3);
  }

  void collect() override {
    if (maxSpeed_ * dt_ > b2_maxTranslation && notes.empty())
      notes = "Box2D moves a body at most b2_maxTranslation = 2 units per step: speeds above " +
              std::to_string(static_cast<int>(b2_maxTranslation / dt_)) + " units/s are cut";
  }

  // SetLinearVelocity wakes a sleeping body when the velocity is not zero.
  void setVelocities(const std::vector<Vec2>& velocities) override {
    for (size_t i = 0; i < bodies_.size(); ++i) bodies_[i]->SetLinearVelocity(vec(velocities[i]));
  }

  long long asleep() const override {
    long long n = 0;
    for (const b2Body* b : bodies_) n += b->IsAwake() ? 0 : 1;
    return n;
  }

  void state(std::vector<Vec2>& positions, std::vector<Vec2>& velocities) const override {
    positions.resize(bodies_.size());
    velocities.resize(bodies_.size());
    for (size_t i = 0; i < bodies_.size(); ++i) {
      const b2Vec2 p = bodies_[i]->GetPosition(), v = bodies_[i]->GetLinearVelocity();
      positions[i] = {p.x, p.y};
      velocities[i] = {v.x, v.y};
    }
  }

 private:
  static b2Vec2 vec(Vec2 v) { return b2Vec2(static_cast<float>(v.x), static_cast<float>(v.y)); }

  void BeginContact(b2Contact* contact) override {
    b2Fixture* a = contact->GetFixtureA();
    b2Fixture* b = contact->GetFixtureB();
    if (!a->IsSensor() && !b->IsSensor()) {
      ++collisions;
      return;
    }
    b2Fixture* sensor = a->IsSensor() ? a : b;
    b2Fixture* other = a->IsSensor() ? b : a;
    const uintptr_t s = sensor->GetUserData().pointer, disk = other->GetBody()->GetUserData().pointer;
    if (s > 0 && disk > 0) ++sensorBegins[(s - 1) * diskCount_ + (disk - 1)];
  }

  b2World world_;
  size_t diskCount_;
  std::vector<b2Body*> bodies_;
  double maxSpeed_ = 0, dt_ = 0;
};

}  // namespace

std::unique_ptr<Engine> makeBox2dEngine(const Scene& scene, bool bullets) {
  return std::make_unique<Box2dEngine>(scene, bullets);
}

std::string box2dVersion() {
  // The CMake package's version (b2_version in 2.4.1 still says 2.4.0).
  return std::string("Box2D ") + RATTLE_BENCH_BOX2D_VERSION;
}

}  // namespace rattle_bench
