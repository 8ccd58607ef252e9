// The README's hello world: a disk falls onto a static segment and bounces.
#include <rattle/rattle.h>

#include <cstdio>

int main() {
  rattle::World world;  // hybrid stepping by default

  rattle::BodyId ground = world.createBody({.type = rattle::BodyType::Static});
  world.createFixture(ground, {.geometry = rattle::Segment{{-5, 0}, {5, 0}}});

  rattle::BodyId ball = world.createBody({.type = rattle::BodyType::Dynamic, .position = {0, 4}, .velocity = {1, -8}});
  world.createFixture(ball, {.geometry = rattle::Circle{{0, 0}, 0.5}, .density = 1.0, .restitution = 0.8});

  for (int frame = 0; frame < 60; ++frame) {
    world.step(1.0 / 60.0);
    for (const rattle::ContactEvent& c : world.contactEvents()) {
      std::printf("t=%.6f s  point (%.4f, %.4f)  normal (%.1f, %.1f)  impulse %.4f\n",
                  world.time() - 1.0 / 60.0 + c.time, c.point.x, c.point.y, c.normal.x, c.normal.y, c.impulse);
    }
  }
  rattle::Vec2 p = world.position(ball);
  std::printf("ball at (%.4f, %.4f) after %.2f s\n", p.x, p.y, world.time());
}
