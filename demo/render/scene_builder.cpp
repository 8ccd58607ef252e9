// Reads the game (and asks it the sight questions the fog needs); touches no OpenGL.
#include "render/scene_builder.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <variant>

namespace rts {
namespace {

// Past this many units per team the fog uses plain sight disks: a fan of rays per unit per frame
// would cost more than the frame is worth.
constexpr int kMaxFogFanUnits = 1500;

const char* teamName(int team) { return team == 0 ? "blue" : "red"; }

}  // namespace

std::vector<std::string> hudLines(const Game& game, bool paused, bool showTimes) {
  const std::vector<double>& steps = game.stats().stepSeconds;
  char time[64] = "";
  if (showTimes) std::snprintf(time, sizeof time, "   engine step %.2f ms", steps.empty() ? 0.0 : steps.back() * 1e3);
  char line[512];
  std::snprintf(line, sizeof line, "tick %u%s   blue %d   red %d   shots %ld   crossings %ld%s", game.tickCount(),
                paused ? " (paused)" : "", game.alive(0), game.alive(1), game.stats().shotsFired, game.stats().crossings, time);
  std::string rooms = "rooms:";
  for (size_t r = 0; r < game.rooms().size(); ++r) {
    const int h = game.rooms()[r].holder;
    const std::string& name = game.map().rooms[r].name;
    rooms += "  " + (name.empty() ? "room " + std::to_string(r) : name) + " " +
             (h < 0 ? "-" : h == 2 ? "contested" : teamName(h));
  }
  return {line, rooms};
}

Scene buildScene(const Game& game, const SceneOptions& options) {
  const Map& map = game.map();
  Scene s;
  s.worldWidth = map.width;
  s.worldHeight = map.height;
  for (size_t r = 0; r < map.rooms.size(); ++r) s.rooms.push_back({map.rooms[r].polygon, game.rooms()[r].holder});
  for (const MapWall& w : map.walls) {
    SceneWall out;
    out.building = w.building;
    if (const auto* line = std::get_if<rattle::Polyline>(&w.shape)) {
      out.shape = SceneWall::Shape::Lines;
      for (Vec2 p : line->points) out.points.push_back(w.origin + p);
    } else if (const auto* poly = std::get_if<rattle::Polygon>(&w.shape)) {
      out.shape = SceneWall::Shape::Polygon;
      for (Vec2 p : poly->points) out.points.push_back(w.origin + p);
    } else if (const auto* c = std::get_if<rattle::Circle>(&w.shape)) {
      out.shape = SceneWall::Shape::Circle;
      out.center = w.origin + c->center;
      out.radius = c->radius;
    } else {
      continue;
    }
    s.walls.push_back(std::move(out));
  }
  for (size_t d = 0; d < map.doorways.size(); ++d) {
    const DoorwayState& st = game.doorways()[d];
    const double since = double(game.tickCount()) - double(st.lastCrossTick);
    s.doorways.push_back({map.doorways[d].a, map.doorways[d].b, std::max(0.0, 1.0 - since / 20.0), st.lastCrossTeam});
  }
  for (size_t g = 0; g < map.gates.size(); ++g) s.gates.push_back(game.gateOutline(g));

  const int fogTeam = options.fogTeam;
  std::vector<uint8_t> visible;
  if (fogTeam == 0 || fogTeam == 1) {
    visible = game.visibleTo(fogTeam);
    s.fog = true;
    const bool fans = options.fogRays > 0 && game.alive(fogTeam) <= kMaxFogFanUnits;
    for (const Unit& u : game.units()) {
      if (!u.alive || u.team != fogTeam) continue;
      std::vector<Vec2> fan{u.position};
      if (fans) {
        std::vector<Vec2> outline = game.sightOutline(u, options.fogRays);
        fan.insert(fan.end(), outline.begin(), outline.end());
      } else {
        const double r = kUnitTypes[u.type].sight;
        for (int i = 0; i < 32; ++i) {
          const double a = 2 * 3.141592653589793 * i / 32;
          fan.push_back(u.position + Vec2{std::cos(a) * r, std::sin(a) * r});
        }
      }
      s.fogFans.push_back(std::move(fan));
    }
  }
  for (const Unit& u : game.units()) {
    // An enemy the fog team does not see is not drawn at all: a dimmed one would give its place away.
    if (!u.alive || (!visible.empty() && !visible[u.id])) continue;
    const UnitType& type = kUnitTypes[u.type];
    SceneUnit su;
    su.position = u.position;
    su.radius = type.radius;
    su.team = u.team;
    su.selected = u.id < options.selected.size() && options.selected[u.id];
    su.health = double(u.hitPoints) / double(type.hitPoints);
    s.units.push_back(su);
    if (options.showSight) s.sight.push_back({u.position, type.sight, u.team});
  }
  for (const Shot& sh : game.shots()) s.shots.push_back({sh.position, sh.velocity, kUnitTypes[sh.type].shotRadius, sh.team});
  for (const Impact& i : game.impacts()) {
    s.impacts.push_back({i.point, std::min(1.0, double(game.tickCount() - i.tick) / 12.0), i.wall});
  }
  s.hasSelectionBox = options.hasSelectionBox;
  s.selectionA = options.selectionA;
  s.selectionB = options.selectionB;
  s.hud = hudLines(game, options.paused, options.showTimes);
  if (!options.banner.empty()) s.hud.push_back(options.banner);
  return s;
}

}  // namespace rts
