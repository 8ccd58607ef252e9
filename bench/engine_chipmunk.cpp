// rattle-bench: Chipmunk 7 (Debian's libchipmunk-dev, double precision) behind the Engine interface,
// engine `chipmunk`.
//
// Set up as fairly as Chipmunk allows for rattle's model: every disk a body of the scene's mass and
// infinite moment (it never spins), one circle shape, no friction; walls are segment shapes of radius 0
// (whose ends collide, as a wall with solid ends must) and sensor strips polygon sensors on the space's static body. Chipmunk multiplies the two elasticities
// of a contact, so every shape gets sqrt(restitution) and every contact the scene's restitution. Disks that
// must not meet share a group. Everything else is Chipmunk's default: 10 iterations, collision slop 0.1,
// the bounding-box tree as spatial index, no sleeping. Chipmunk has no continuous collision.
//
// Collisions are counted in the default collision handler's begin callback (a contact that starts
// touching; a resting contact counts once), which runs inside cpSpaceStep and only increments a counter.
//
// Debian's libchipmunk 7.0.3 is built without NDEBUG: the first cpSpaceNew of a process prints "(Debug
// Enabled)" on stdout, and the library runs its runtime assertion checks. That print would break the CSV,
// so it is caught here (stdout is pointed at a pipe around the first cpSpaceNew) and told in the row's
// notes instead; the checks stay on, as that is the Chipmunk people get from the package.
#include <chipmunk/chipmunk.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "engine.h"

namespace rattle_bench {

namespace {

/// cpSpaceNew with whatever it prints on stdout caught (see the file comment) and returned in `said`.
cpSpace* quietSpaceNew(std::string& said) {
  std::fflush(stdout);
  int fds[2];
  const int saved = dup(1);
  if (saved < 0 || pipe(fds) != 0) {
    if (saved >= 0) close(saved);
    return cpSpaceNew();
  }
  dup2(fds[1], 1);
  cpSpace* space = cpSpaceNew();
  std::fflush(stdout);
  dup2(saved, 1);
  close(saved);
  close(fds[1]);
  char buf[512];
  ssize_t got;
  while ((got = read(fds[0], buf, sizeof buf)) > 0) said.append(buf, static_cast<size_t>(got));
  close(fds[0]);
  return space;
}

/// Whether the library is a debug build: it says so when the first space of the process is made.
bool& libraryIsDebugBuild() {
  static bool debug = false;
  return debug;
}

cpSpace* newSpace() {
  std::string said;
  cpSpace* space = quietSpaceNew(said);
  if (said.find("Debug Enabled") != std::string::npos) libraryIsDebugBuild() = true;
  return space;
}

class ChipmunkEngine final : public Engine {
 public:
  explicit ChipmunkEngine(const Scene& scene) : space_(newSpace()), diskCount_(scene.disks.size()) {
    if (libraryIsDebugBuild()) notes = "libchipmunk is a debug build (runtime assertion checks on)";
    cpSpaceSetGravity(space_, cpv(scene.gravity.x, scene.gravity.y));
    const cpFloat elasticity = std::sqrt(scene.restitution);
    cpBody* ground = cpSpaceGetStaticBody(space_);
    for (const Wall& w : scene.walls) {
      cpShape* s = add(cpSegmentShapeNew(ground, cpv(w.a.x, w.a.y), cpv(w.b.x, w.b.y), 0));
      cpShapeSetElasticity(s, elasticity);
      cpShapeSetFriction(s, 0);
    }
    for (size_t k = 0; k < scene.sensors.size(); ++k) {
      std::vector<cpVect> points;
      for (Vec2 p : scene.sensors[k].points) points.push_back(cpv(p.x, p.y));
      cpShape* s = add(cpPolyShapeNewRaw(ground, static_cast<int>(points.size()), points.data(), 0));
      cpShapeSetSensor(s, cpTrue);
      sensorOf_[s] = k;
    }
    const cpShapeFilter apart = cpShapeFilterNew(1, CP_ALL_CATEGORIES, CP_ALL_CATEGORIES);
    for (size_t i = 0; i < scene.disks.size(); ++i) {
      const DiskStart& d = scene.disks[i];
      cpBody* body = cpSpaceAddBody(space_, cpBodyNew(massOf(d), INFINITY));
      cpBodySetPosition(body, cpv(d.position.x, d.position.y));
      cpBodySetVelocity(body, cpv(d.velocity.x, d.velocity.y));
      cpShape* s = add(cpCircleShapeNew(body, d.radius, cpvzero));
      cpShapeSetElasticity(s, elasticity);
      cpShapeSetFriction(s, 0);
      if (!scene.disksCollide) cpShapeSetFilter(s, apart);
      cpShapeSetUserData(s, reinterpret_cast<cpDataPointer>(i + 1));
      bodies_.push_back(body);
    }
    cpCollisionHandler* handler = cpSpaceAddDefaultCollisionHandler(space_);
    handler->beginFunc = &ChipmunkEngine::begin;
    handler->userData = this;
    sensorBegins.assign(scene.sensors.size() * scene.disks.size(), 0);
  }

  ~ChipmunkEngine() override {
    // The order of the Chipmunk manual's "Hello Chipmunk": shapes, then bodies, then the space.
    for (cpShape* s : shapes_) {
      cpSpaceRemoveShape(space_, s);
      cpShapeFree(s);
    }
    for (cpBody* b : bodies_) {
      cpSpaceRemoveBody(space_, b);
      cpBodyFree(b);
    }
    cpSpaceFree(space_);
  }
  ChipmunkEngine(const ChipmunkEngine&) = delete;
  ChipmunkEngine& operator=(const ChipmunkEngine&) = delete;

  void step(double dt) override { cpSpaceStep(space_, dt); }

  void setVelocities(const std::vector<Vec2>& velocities) override {
    for (size_t i = 0; i < bodies_.size(); ++i) cpBodySetVelocity(bodies_[i], cpv(velocities[i].x, velocities[i].y));
  }

  void state(std::vector<Vec2>& positions, std::vector<Vec2>& velocities) const override {
    positions.resize(bodies_.size());
    velocities.resize(bodies_.size());
    for (size_t i = 0; i < bodies_.size(); ++i) {
      const cpVect p = cpBodyGetPosition(bodies_[i]), v = cpBodyGetVelocity(bodies_[i]);
      positions[i] = {p.x, p.y};
      velocities[i] = {v.x, v.y};
    }
  }

 private:
  cpShape* add(cpShape* s) {
    shapes_.push_back(cpSpaceAddShape(space_, s));
    return s;
  }

  static cpBool begin(cpArbiter* arb, cpSpace*, cpDataPointer data) {
    ChipmunkEngine* self = static_cast<ChipmunkEngine*>(data);
    CP_ARBITER_GET_SHAPES(arb, a, b);
    const bool sa = cpShapeGetSensor(a), sb = cpShapeGetSensor(b);
    if (!sa && !sb) {
      ++self->collisions;
      return cpTrue;
    }
    cpShape* sensor = sa ? a : b;
    cpShape* other = sa ? b : a;
    const uintptr_t disk = reinterpret_cast<uintptr_t>(cpShapeGetUserData(other));
    const auto it = self->sensorOf_.find(sensor);
    if (it != self->sensorOf_.end() && disk > 0) ++self->sensorBegins[it->second * self->diskCount_ + (disk - 1)];
    return cpTrue;
  }

  cpSpace* space_;
  size_t diskCount_;
  std::vector<cpBody*> bodies_;
  std::vector<cpShape*> shapes_;
  std::map<cpShape*, size_t> sensorOf_;
};

}  // namespace

std::unique_ptr<Engine> makeChipmunkEngine(const Scene& scene) { return std::make_unique<ChipmunkEngine>(scene); }

std::string chipmunkVersion() {
  cpSpaceFree(newSpace());
  return std::string("Chipmunk ") + cpVersionString +
         (libraryIsDebugBuild() ? " (a debug build: runtime assertion checks on)" : "");
}

}  // namespace rattle_bench
