// Shared pieces of the tests whose scenes a random search of closed containers found (points and disks
// thrown about in them under gravity): a thrown body, a recorded step, how far a centre lies outside a
// convex container, and a container played with its checks. Header-only.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rattle/rattle.h"

namespace container_search {

struct Throw {
  rattle::Vec2 position, velocity;
  double radius, restitution;
};

struct Step {
  double dt;
  int setVelocityOf;  // a body given `velocity` before the step, or -1
  rattle::Vec2 velocity;
};

/// The search's world: `mode`, gravity (0, gravityY), and an event budget of 20,000 (as the fuzz target: a
/// step that loops reaches it in a moment).
inline rattle::WorldDef searchWorld(rattle::StepMode mode, double gravityY = -9.81) {
  rattle::WorldDef def;
  def.mode = mode;
  def.gravity = {0, gravityY};
  def.maxEventsPerStep = 20000;
  return def;
}

/// How far outside a counter-clockwise convex polygon `q` lies (negative inside: minus its distance to the
/// nearest side).
inline double distanceOutside(const std::vector<rattle::Vec2>& corners, rattle::Vec2 q) {
  double worst = -INFINITY;
  for (size_t i = 0; i < corners.size(); ++i) {
    const rattle::Vec2 a = corners[i], b = corners[(i + 1) % corners.size()];
    worst = std::max(worst, -rattle::cross(b - a, q - a) / rattle::length(b - a));
  }
  return worst;
}

/// A dynamic body of one circle for each throw, in order.
inline std::vector<rattle::BodyId> throwBodies(rattle::World& w, const std::vector<Throw>& throws) {
  std::vector<rattle::BodyId> bodies;
  for (const Throw& t : throws) {
    bodies.push_back(w.createBody({.type = rattle::BodyType::Dynamic, .position = t.position, .velocity = t.velocity}));
    w.createFixture(bodies.back(), {.geometry = rattle::Circle{{0, 0}, t.radius}, .restitution = t.restitution});
  }
  return bodies;
}

enum class Walls { Segments, Polyline };

/// A closed container of static walls with the bodies thrown into it and the steps played.
struct Container {
  rattle::StepMode mode;
  Walls walls;
  std::vector<rattle::Vec2> corners;    // counter-clockwise, convex
  std::vector<double> wallRestitution;  // one a Segment, or the closed Polyline's
  std::vector<Throw> bodies;
  std::vector<Step> steps;
  double gravityY = -9.81;  // the world's gravity is (0, gravityY)
};

/// The container's walls, on one static body: a Segment a side, or one closed Polyline.
inline void buildWalls(rattle::World& w, const Container& c) {
  const rattle::BodyId walls = w.createBody({.type = rattle::BodyType::Static});
  const size_t n = c.corners.size();
  if (c.walls == Walls::Polyline) {
    rattle::Polyline closed{c.corners};
    closed.points.push_back(c.corners.front());
    w.createFixture(walls, {.geometry = closed, .restitution = c.wallRestitution[0]});
    return;
  }
  for (size_t k = 0; k < n; ++k) {
    w.createFixture(walls, {.geometry = rattle::Segment{c.corners[k], c.corners[(k + 1) % n]},
                            .restitution = c.wallRestitution[k]});
  }
}

/// A container's scene: its world (searchWorld), walls and bodies.
struct Scene {
  rattle::World world;
  std::vector<rattle::BodyId> bodies;
};
inline Scene setUp(const Container& c) {
  Scene scene{rattle::World(searchWorld(c.mode, c.gravityY)), {}};
  buildWalls(scene.world, c);
  scene.bodies = throwBodies(scene.world, c.bodies);
  return scene;
}

/// Sets the velocity the step names, if any, and steps.
inline void play(rattle::World& w, const std::vector<rattle::BodyId>& bodies, const Step& step) {
  if (step.setVelocityOf >= 0) w.setVelocity(bodies[static_cast<size_t>(step.setVelocityOf)], step.velocity);
  w.step(step.dt);
}

/// Plays every container's steps, each container on its own (an ASSERT ends only its call, so that every
/// one that fails is named): after each step, none may have reached the event budget, and no body's
/// centre may lie more than 1e-9 outside the container.
inline void playEachChecked(const Container* containers, size_t count) {
  auto playChecked = [](const Container& c) {
    auto [w, bodies] = setUp(c);
    for (size_t s = 0; s < c.steps.size(); ++s) {
      play(w, bodies, c.steps[s]);
      ASSERT_FALSE(w.stats().eventBudgetReached) << "step " << s;
      for (size_t j = 0; j < bodies.size(); ++j) {
        ASSERT_LE(distanceOutside(c.corners, w.position(bodies[j])), 1e-9)
            << "body " << j << " (radius " << c.bodies[j].radius << "), step " << s;
      }
    }
  };
  for (size_t i = 0; i < count; ++i) {
    SCOPED_TRACE("container " + std::to_string(i));
    playChecked(containers[i]);
  }
}

}  // namespace container_search
