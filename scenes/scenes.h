// rattle-bench: the benchmark's scenes, written once as plain data (disks, walls, sensor strips) so that
// every engine adapter builds its own world from the same numbers, and tests and the demo can share them.
//
// Every random start comes from the seed through scenes/random.h (no std distributions, no libm calls in
// the placement), so one seed gives one scene, bit for bit, on every build.
//
// The scenes (defaults in brackets; --packing and --speed override where they apply):
//  - gas:     n equal disks (radius 0.5, density 1) in a closed square box of zero-thickness walls,
//             restitution 1, no gravity, packing fraction [0.3], every disk at speed [1] in a random
//             direction, centres on a jittered triangular lattice (random sequential addition cannot
//             reach packing 0.6, so every packing starts from the lattice, shaken as far as the gaps allow).
//  - pile:    n disks (radius 0.5) in a loose block (packing 0.35) in the upper half of a closed box twice
//             as tall as wide, falling under gravity (0, -10), restitution 0.5, random speeds up to [1].
//  - bullets: n small disks (radius 0.05) in a closed 20 x 20 box of zero-thickness walls, restitution 1,
//             no gravity; speeds 10, 100, 1000, 10000 in turn (disk i gets 10^(1 + i mod 4)), or all at
//             --speed; random directions.
//  - cradle:  n / 6 Newton's cradles, one per horizontal lane 2 units apart in a closed 16-unit-wide
//             box: five touching disks (radius 0.5, centres exactly 1 apart, x = 7..11) and a striker
//             (x = 4.5) coming at them along the lane at a random speed in [1, 3] (or at --speed);
//             restitution 1, so the lane keeps knocking back and forth between its walls. n must be a
//             multiple of 6.
//  - sensors: n disks (radius 0.1) in a closed 20 x 20 box, restitution 1, that collide with the walls
//             but not with each other (so every engine should trace the same billiard paths), speeds
//             uniform in [10, 40] (or --speed), crossing six thin sensor strips (0.05 wide: three
//             vertical, three horizontal).
//  - crowd:   n disks (radius 0.5) in the first of two square rooms side by side (packing 0.35 in the first
//             room, on the jittered lattice), no gravity, restitution 0. The wall between the rooms has two
//             doorways 4 units wide (at a quarter and three quarters of its height); its pieces are walls
//             with solid ends (Wall::solidEnds), so a disk cannot slip round a doorway's jamb. Every step,
//             before the engine steps, each disk's velocity is set at full speed [3] by naive steering
//             (steerCrowd): straight at the nearer doorway while in the first room, then straight at the
//             goal, the second room's centre. A disk has reached the goal region once its centre is a radius
//             past the dividing wall (in the second room, clear of the wall).
// The `arena` scene is not plain data: it is the demo's game itself (bench/arena.h).
#pragma once

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "rattle/geometry.h"
#include "rattle/types.h"
#include "rattle/vec2.h"

namespace rattle {
class World;
}

namespace rattle_bench {

using rattle::Vec2;

struct DiskStart {
  Vec2 position;
  Vec2 velocity;
  double radius = 0.5;
  double density = 1.0;  ///< mass = density * pi * radius^2 in every engine
};

/// A static zero-thickness wall: the segment from a to b.
struct Wall {
  Vec2 a;
  Vec2 b;
  /// Whether the ends collide too (a doorway's jamb). rattle's Segment collides only on its inside, so such
  /// a wall becomes a two-point Polyline there; Box2D's edges and Chipmunk's segments collide at their
  /// ends anyway.
  bool solidEnds = false;
};

/// Naive steering toward a goal through doorways in a vertical dividing wall (the crowd scene). Disks left
/// of the wall (x < wallX) head at full speed for the point one unit past the middle of the nearest
/// doorway; the others head for the goal.
struct Steering {
  bool enabled = false;
  double speed = 0;
  double wallX = 0;
  std::vector<double> doorwayY;  ///< the doorways' middles, ascending
  double doorwayHalfWidth = 0;
  Vec2 goal;
};

/// A static sensor: a convex polygon, counter-clockwise.
struct SensorStrip {
  std::vector<Vec2> points;
};

struct Scene {
  std::string name;
  std::vector<DiskStart> disks;
  std::vector<Wall> walls;
  std::vector<SensorStrip> sensors;
  double restitution = 1.0;  ///< of every surface (disks and walls alike)
  Vec2 gravity;
  /// The container's inside: a disk whose centre is found outside it has tunnelled.
  rattle::Box bounds;
  /// False: disks pass through one another and meet only walls (and sensors).
  bool disksCollide = true;
  /// The parameters the scene was built with, for the CSV row: packing fraction (disk area over the
  /// container's area) and speed (the common speed, or NaN when speeds differ between disks: the
  /// row's column is then empty).
  double packing = 0;
  double speed = std::numeric_limits<double>::quiet_NaN();
  uint64_t seed = 0;
  /// The crowd's steering, and its goal region; disabled in the other scenes.
  Steering steering;
};

struct SceneParams {
  std::string name = "gas";
  int n = 1000;
  uint64_t seed = 1;
  /// Packing fraction of the gas; NaN: the scene's default. Only `gas` takes it.
  double packing = std::numeric_limits<double>::quiet_NaN();
  /// Speed of every disk; NaN: the scene's default. Every scene takes it.
  double speed = std::numeric_limits<double>::quiet_NaN();
};

/// The scene names buildScene knows, in the order the help lists them.
const std::vector<std::string>& sceneNames();

/// The number of disks a scene has when none is asked for: gas and pile 1000, bullets 100, cradle 60,
/// sensors 200, crowd 1000.
int defaultDiskCount(const std::string& scene);

/// A scene that cannot be built from the parameters given; the message names the parameter and the value.
struct SceneError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

/// Builds a scene. Throws SceneError naming the parameter and the value when it cannot be built
/// (an unknown name, n < 1, a packing the lattice cannot hold, a cradle n that is not a multiple of 6).
Scene buildScene(const SceneParams& params);

/// The crowd scene's naive steering: each disk's velocity at full speed (scene.steering.speed) toward the
/// nearer doorway (the lower one on a tie) while in the first room, then toward the goal; a disk exactly on
/// its aim point gets zero. `velocities` is resized to the positions'.
void steerCrowd(const Scene& scene, const std::vector<Vec2>& positions, std::vector<Vec2>& velocities);

/// Whether a centre is in the crowd's goal region: at least a radius past the dividing wall, inside the
/// container.
bool inGoalRegion(const Scene& scene, size_t disk, Vec2 position);

/// Whether the move of a centre from `from` to `to` crossed the crowd's dividing wall anywhere but through a
/// doorway (the line x = wallX crossed at a height outside every doorway's span); false in a scene without
/// steering.
bool crossedWallOutsideDoorways(const Scene& scene, Vec2 from, Vec2 to);

/// Mass of a disk: density * pi * r^2.
double massOf(const DiskStart& d);

/// A 64-bit FNV-1a hash of the exact bits of everything in the scene (for determinism checks).
uint64_t sceneHash(const Scene& scene);

/// The scene in a rattle world: one static body with the walls (Segment fixtures) and the sensor strips
/// (Polygon sensor fixtures), then a dynamic body with one Circle fixture per disk, of the scene's
/// density and restitution (walls get the same restitution); in a scene whose disks must not meet, every
/// disk is in collision group 1. The same world whoever builds it: rattle-bench, the tests, rattle-trace.
struct RattleScene {
  std::vector<rattle::BodyId> disks;        ///< in the scene's order
  std::vector<rattle::FixtureId> sensors;   ///< the sensor strips' fixtures, in the scene's order
};
RattleScene addToWorld(rattle::World& world, const Scene& scene);

}  // namespace rattle_bench
