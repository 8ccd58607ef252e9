// What a frame shows, as plain data: no engine, no OpenGL. scene_builder.cpp makes one from a Game;
// renderer.cpp draws one. Keeping the two apart means the renderer can be tested (or replaced) without a
// game, and a game without a renderer.
#pragma once

#include <rattle/vec2.h>

#include <string>
#include <vector>

namespace rts {

using rattle::Vec2;

struct SceneWall {
  enum class Shape { Lines, Polygon, Circle } shape = Shape::Lines;
  std::vector<Vec2> points;  ///< Lines: a polyline; Polygon: convex outline
  Vec2 center;               ///< Circle
  double radius = 0;
  bool building = false;
};

struct SceneDoorway {
  Vec2 a, b;
  double glow = 0;  ///< 1 just crossed, fading to 0
  int team = 0;     ///< who crossed last
};

struct SceneRoom {
  std::vector<Vec2> polygon;
  int holder = -1;  ///< -1 nobody, 0/1 a team, 2 contested
};

struct SceneUnit {
  Vec2 position;
  double radius = 0.5;
  int team = 0;
  bool selected = false;
  double health = 1;  ///< 0..1
};

struct SceneShot {
  Vec2 position, velocity;
  double radius = 0.15;  ///< the projectile's disk in the game; drawn larger, so a player sees it
  int team = 0;
};

struct SceneImpact {
  Vec2 position;
  double age = 0;  ///< 0 new .. 1 gone
  bool wall = false;
};

struct SceneSight {
  Vec2 center;
  double radius = 0;
  int team = 0;
};

struct Scene {
  double worldWidth = 1, worldHeight = 1;
  std::vector<SceneRoom> rooms;
  std::vector<SceneWall> walls;
  std::vector<SceneDoorway> doorways;
  std::vector<std::vector<Vec2>> gates;
  std::vector<SceneSight> sight;  ///< sight ranges, drawn as each team's outline; empty when hidden
  /// Fog of war: when `fog` is set, everything outside these fans (each a centre, then its outline) is
  /// dimmed. One fan per unit of the fog team. Units the fog team does not see are not in `units`.
  bool fog = false;
  std::vector<std::vector<Vec2>> fogFans;
  std::vector<SceneUnit> units;
  std::vector<SceneShot> shots;
  std::vector<SceneImpact> impacts;
  bool hasSelectionBox = false;
  Vec2 selectionA, selectionB;  ///< world units
  std::vector<std::string> hud;  ///< lines of text at the top left
};

}  // namespace rts
