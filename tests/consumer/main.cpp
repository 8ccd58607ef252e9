// A user's program built against the installed package: one disk falls onto a floor once.
#include <rattle/rattle.h>

#include <cstdio>

int main() {
  rattle::World world;
  rattle::BodyId floor = world.createBody({});
  world.createFixture(floor, {.geometry = rattle::Segment{{-10, 0}, {10, 0}}});
  rattle::BodyId disk = world.createBody({.type = rattle::BodyType::Dynamic, .position = {0, 2}, .velocity = {0, -3}});
  world.createFixture(disk, {.geometry = rattle::Circle{{0, 0}, 0.5}, .restitution = 1.0});
  world.step(1.0);
  std::printf("contacts: %zu\n", world.contactEvents().size());
  return world.contactEvents().size() == 1 ? 0 : 1;
}
