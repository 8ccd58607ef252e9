// A bench scene as a rattle world (scenes.h, addToWorld): the one place rattle-bench, the tests and
// rattle-trace build it, so that they all measure the same world.
#include "rattle/world.h"
#include "scenes.h"

namespace rattle_bench {

RattleScene addToWorld(rattle::World& world, const Scene& scene) {
  RattleScene out;
  rattle::BodyDef ground;
  ground.type = rattle::BodyType::Static;
  const rattle::BodyId groundId = world.createBody(ground);
  for (const Wall& w : scene.walls) {
    rattle::FixtureDef fd;
    // A Segment collides only on its inside; a wall whose ends must collide (a doorway's jamb) is a
    // two-point Polyline, whose ends collide too.
    if (w.solidEnds)
      fd.geometry = rattle::Polyline{{w.a, w.b}};
    else
      fd.geometry = rattle::Segment{w.a, w.b};
    fd.restitution = scene.restitution;
    world.createFixture(groundId, fd);
  }
  for (const SensorStrip& s : scene.sensors) {
    rattle::FixtureDef fd;
    fd.geometry = rattle::Polygon{s.points};
    fd.sensor = true;
    out.sensors.push_back(world.createFixture(groundId, fd));
  }
  out.disks.reserve(scene.disks.size());
  for (const DiskStart& d : scene.disks) {
    rattle::BodyDef bd;
    bd.type = rattle::BodyType::Dynamic;
    bd.position = d.position;
    bd.velocity = d.velocity;
    const rattle::BodyId id = world.createBody(bd);
    rattle::FixtureDef fd;
    fd.geometry = rattle::Circle{{0, 0}, d.radius};
    fd.density = d.density;
    fd.restitution = scene.restitution;
    if (!scene.disksCollide) fd.filter.group = 1;
    world.createFixture(id, fd);
    out.disks.push_back(id);
  }
  return out;
}

}  // namespace rattle_bench
