// The map as the game sees it: plain data in world units, built from a file by map_loader.h.
//
// Coordinates follow Tiled's: x to the right, y downward, in world units (map pixels divided by the
// map's pixels_per_unit). Every object keeps its Tiled id so errors and tools can point at it.
#pragma once

#include <rattle/geometry.h>

#include <string>
#include <vector>

namespace rts {

using rattle::Vec2;

/// Something solid that blocks movement, sight and projectiles. Buildings are drawn filled; walls as
/// lines (a polyline) or filled (a polygon or circle).
struct MapWall {
  int objectId = 0;
  Vec2 origin;              ///< the object's position; `shape` is relative to it
  rattle::Geometry shape;   ///< Polyline, Polygon or Circle
  bool building = false;
};

/// Where a team's units start. Units fill the free space nearest to the spawn points of their team.
struct MapSpawn {
  int objectId = 0;
  int team = 0;
  Vec2 position;
};

/// A sensor segment across an opening: counts who passes, and links the regions on its two sides.
struct MapDoorway {
  int objectId = 0;
  std::string name;
  Vec2 a, b;
};

/// A convex region that a team holds while it has units inside and the other team has none.
struct MapRoom {
  int objectId = 0;
  std::string name;
  std::vector<Vec2> polygon;  ///< convex, absolute coordinates
};

/// A kinematic body that slides by `openOffset` to open and back to close.
struct MapGate {
  int objectId = 0;
  std::string name;
  Vec2 origin;                ///< closed position of the body
  std::vector<Vec2> polygon;  ///< convex, relative to origin
  Vec2 openOffset;            ///< world units from closed to open
  double period = 0;          ///< seconds between automatic toggles; 0: only on command
  double speed = 4;           ///< world units per second while moving
};

struct Map {
  std::string name;
  std::string source;  ///< the file it came from, for messages
  double width = 0;    ///< world units
  double height = 0;
  double pixelsPerUnit = 1;
  std::vector<MapWall> walls;
  std::vector<MapSpawn> spawns;
  std::vector<MapDoorway> doorways;
  std::vector<MapRoom> rooms;
  std::vector<MapGate> gates;
};

}  // namespace rts
