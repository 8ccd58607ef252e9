// Tiled JSON -> rts::Map. Every check names the object id and the field, so a map author can find the
// problem in Tiled (View > Objects shows ids). Properties are strict: an unknown property is an error,
// because a silently ignored typo ("tema") is worse than a message.
#include "map/map_loader.h"

#include <nlohmann/json.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <utility>

#include "map/errno_reason.h"
#include "map/printable.h"

namespace rts {
namespace {

using json = nlohmann::json;

// Bounds that keep hostile files cheap: no count here can exceed what the file size allows anyway,
// but they keep the numbers the game works with sane.
constexpr size_t kMaxObjects = 100'000;
constexpr size_t kMaxPointsPerObject = 10'000;
// The engine checks a polygon's convexity in O(n^2) (rattle::validationError); a convex piece needs a
// handful of corners, and this keeps a file of 10,000-corner polygons from costing minutes.
constexpr size_t kMaxPolygonPoints = 256;
// nlohmann-json copies and compares nested values recursively (a property value is copied), so the
// depth of arrays and objects is bounded before parsing; a Tiled map needs about 40 at most.
constexpr int kMaxJsonDepth = 64;
// The game lays a grid of one cell per square world unit over the map (demo/game/navigation.h).
constexpr double kMaxMapArea = 1 << 20;
constexpr size_t kMaxPropertiesPerObject = 64;
constexpr size_t kMaxStringBytes = 256;
constexpr int kMaxLayerDepth = 16;
constexpr double kMaxCoordinate = 1e6;  // map pixels
constexpr size_t kMaxGates = 32;        // the game keeps gate states in a 32-bit mask

std::string inQuotes(const std::string& s) {
  std::string out = "\"";
  for (char c : printable(s.substr(0, 64))) out += c == '"' ? '?' : c;
  if (s.size() > 64) out += "...";
  return out + "\"";
}

// A short rendering of a JSON value for messages, never long whatever the file holds.
std::string shown(const json& v) {
  if (v.is_string()) return inQuotes(v.get<std::string>());
  if (v.is_object()) return "{...}";
  if (v.is_array()) return "[...]";
  std::string s = v.dump();
  return s.size() > 40 ? s.substr(0, 40) + "..." : s;
}

std::string formatNumber(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

[[noreturn]] void fail(const std::string& message) { throw MapError(message); }

// Where an object sits, for messages: "arena.json: object 12 (layer "walls")".
struct Place {
  std::string source;
  std::string layer;
  int objectId = -1;  // -1: the map itself
  std::string str() const {
    if (objectId < 0) return source;
    return source + ": object " + std::to_string(objectId) + " (layer " + inQuotes(layer) + ")";
  }
};

double finiteNumber(const Place& at, const std::string& field, const json& v) {
  if (!v.is_number()) fail(at.str() + ": " + field + " = " + shown(v) + ": expected a number");
  double d = v.get<double>();
  if (!std::isfinite(d)) fail(at.str() + ": " + field + " = " + formatNumber(d) + ": expected a finite number");
  return d;
}

double coordinate(const Place& at, const std::string& field, const json& v) {
  double d = finiteNumber(at, field, v);
  if (std::fabs(d) > kMaxCoordinate) {
    fail(at.str() + ": " + field + " = " + formatNumber(d) + ": outside +-1e6 pixels");
  }
  return d;
}

std::string boundedString(const Place& at, const std::string& field, const json& v) {
  if (!v.is_string()) fail(at.str() + ": " + field + " = " + shown(v) + ": expected a string");
  const std::string& s = v.get_ref<const std::string&>();
  if (s.size() > kMaxStringBytes) {
    fail(at.str() + ": " + field + " is " + std::to_string(s.size()) + " bytes long: at most " +
         std::to_string(kMaxStringBytes));
  }
  return s;
}

// One object's custom properties, read once, each consumed by name; what is left over is unknown.
class Properties {
 public:
  Properties(const Place& at, const json& object) : at_(at) {
    auto it = object.find("properties");
    if (it == object.end()) return;
    if (!it->is_array()) {
      fail(at.str() + ": properties = " + shown(*it) +
           ": expected an array of {name, type, value} (Tiled 1.2 or later)");
    }
    if (it->size() > kMaxPropertiesPerObject) {
      fail(at.str() + ": properties: " + std::to_string(it->size()) + " of them, at most " +
           std::to_string(kMaxPropertiesPerObject));
    }
    for (const json& p : *it) {
      if (!p.is_object() || !p.contains("name") || !p.contains("value")) {
        fail(at.str() + ": properties: entry " + shown(p) + ": expected {name, type, value}");
      }
      std::string name = boundedString(at, "property name", p["name"]);
      for (const auto& [n, v] : entries_) {
        if (n == name) fail(at.str() + ": property '" + printable(name) + "' is given twice");
      }
      entries_.emplace_back(name, p["value"]);
    }
  }

  bool has(const std::string& name) const { return find(name) != nullptr; }

  std::string string(const std::string& name) {
    const json* v = take(name);
    return v ? boundedString(at_, "property '" + name + "'", *v) : std::string();
  }

  // Tiled writes float properties as numbers; a float typed in as text ("NaN") is caught here too.
  double number(const std::string& name, double fallback) {
    const json* v = take(name);
    if (!v) return fallback;
    return finiteNumber(at_, "property '" + name + "'", *v);
  }

  int team(const std::string& name) {
    const json* v = take(name);
    if (!v) fail(at_.str() + ": property '" + name + "' is missing (0 or 1)");
    if (!v->is_number_integer() || (v->get<int64_t>() != 0 && v->get<int64_t>() != 1)) {
      fail(at_.str() + ": property '" + name + "' = " + shown(*v) + ": expected 0 or 1");
    }
    return static_cast<int>(v->get<int64_t>());
  }

  bool boolean(const std::string& name, bool fallback) {
    const json* v = take(name);
    if (!v) return fallback;
    if (!v->is_boolean()) fail(at_.str() + ": property '" + name + "' = " + shown(*v) + ": expected true or false");
    return v->get<bool>();
  }

  /// Call after taking every property the kind knows: anything left is a typo or belongs to another kind.
  void rejectUnused(const std::string& kind, const std::string& known) const {
    for (size_t i = 0; i < entries_.size(); ++i) {
      if (!used_.count(i)) {
        fail(at_.str() + ": property '" + printable(entries_[i].first) + "' is not used by kind '" + kind + "'" +
             (known.empty() ? std::string(" (it takes no properties)") : " (it takes: " + known + ")"));
      }
    }
  }

 private:
  const json* find(const std::string& name) const {
    for (const auto& [n, v] : entries_) {
      if (n == name) return &v;
    }
    return nullptr;
  }
  const json* take(const std::string& name) {
    for (size_t i = 0; i < entries_.size(); ++i) {
      if (entries_[i].first == name) {
        used_.insert(i);
        return &entries_[i].second;
      }
    }
    return nullptr;
  }

  Place at_;
  std::vector<std::pair<std::string, json>> entries_;
  std::set<size_t> used_;
};

enum class ShapeKind { Rectangle, Ellipse, Point, Polyline, Polygon };

const char* shapeName(ShapeKind k) {
  switch (k) {
    case ShapeKind::Rectangle: return "rectangle";
    case ShapeKind::Ellipse: return "ellipse";
    case ShapeKind::Point: return "point";
    case ShapeKind::Polyline: return "polyline";
    case ShapeKind::Polygon: return "polygon";
  }
  return "?";
}

// One Tiled object's geometry in world units: its position and its points relative to it. The values
// as the file wrote them (pixels) are kept for messages: a map author looks for -152, not -19.
struct Shape {
  ShapeKind kind = ShapeKind::Rectangle;
  Vec2 origin;
  double width = 0, height = 0;
  std::vector<Vec2> points;  // polyline / polygon, relative to origin
  double xPx = 0, yPx = 0, widthPx = 0, heightPx = 0;
};

bool boolField(const Place& at, const json& object, const char* field) {
  auto it = object.find(field);
  if (it == object.end()) return false;
  if (!it->is_boolean()) fail(at.str() + ": " + field + " = " + shown(*it) + ": expected true or false");
  return it->get<bool>();
}

double numberField(const Place& at, const json& object, const char* field, bool required) {
  auto it = object.find(field);
  if (it == object.end()) {
    if (required) fail(at.str() + ": field '" + field + "' is missing");
    return 0;
  }
  return coordinate(at, field, *it);
}

std::vector<Vec2> pointList(const Place& at, const json& list, const char* field, double ppu) {
  if (!list.is_array()) fail(at.str() + ": " + field + " = " + shown(list) + ": expected an array of {x, y}");
  if (list.size() > kMaxPointsPerObject) {
    fail(at.str() + ": " + field + " has " + std::to_string(list.size()) + " points, at most " +
         std::to_string(kMaxPointsPerObject));
  }
  std::vector<Vec2> out;
  out.reserve(list.size());
  for (size_t i = 0; i < list.size(); ++i) {
    const json& p = list[i];
    std::string name = std::string(field) + "[" + std::to_string(i) + "]";
    if (!p.is_object() || !p.contains("x") || !p.contains("y")) {
      fail(at.str() + ": " + name + " = " + shown(p) + ": expected {x, y}");
    }
    out.push_back({coordinate(at, name + ".x", p["x"]) / ppu, coordinate(at, name + ".y", p["y"]) / ppu});
  }
  return out;
}

Shape readShape(const Place& at, const json& object, double ppu) {
  Shape s;
  s.xPx = numberField(at, object, "x", true);
  s.yPx = numberField(at, object, "y", true);
  s.widthPx = numberField(at, object, "width", false);
  s.heightPx = numberField(at, object, "height", false);
  s.origin = {s.xPx / ppu, s.yPx / ppu};
  s.width = s.widthPx / ppu;
  s.height = s.heightPx / ppu;
  double rotation = numberField(at, object, "rotation", false);
  if (rotation != 0) {
    fail(at.str() + ": rotation = " + formatNumber(rotation) +
         ": rotated objects are not supported (bodies in rattle do not rotate; draw the shape unrotated)");
  }
  if (object.contains("polyline")) {
    s.kind = ShapeKind::Polyline;
    s.points = pointList(at, object["polyline"], "polyline", ppu);
  } else if (object.contains("polygon")) {
    s.kind = ShapeKind::Polygon;
    s.points = pointList(at, object["polygon"], "polygon", ppu);
  } else if (boolField(at, object, "ellipse")) {
    s.kind = ShapeKind::Ellipse;
  } else if (boolField(at, object, "point")) {
    s.kind = ShapeKind::Point;
  } else if (object.contains("text") || object.contains("gid")) {
    fail(at.str() + ": " + (object.contains("text") ? "text" : "gid") +
         ": text and tile objects have no geometry for the game");
  } else {
    s.kind = ShapeKind::Rectangle;
  }
  return s;
}

[[noreturn]] void wrongShape(const Place& at, const Shape& s, const std::string& kind, const char* allowed) {
  fail(at.str() + ": shape " + shapeName(s.kind) + " is not allowed for kind '" + kind + "' (use " + allowed + ")");
}

// Strictly convex, one turn around: every corner turns the same way and the edge directions go round once.
// Names the first corner that breaks it.
void requireConvex(const Place& at, const std::vector<Vec2>& pts, const char* field) {
  const size_t n = pts.size();
  if (n < 3) fail(at.str() + ": " + field + " has " + std::to_string(n) + " points: a polygon needs at least 3");
  double sign = 0;
  for (size_t i = 0; i < n; ++i) {
    Vec2 a = pts[i], b = pts[(i + 1) % n], c = pts[(i + 2) % n];
    if (b == a) fail(at.str() + ": " + field + "[" + std::to_string((i + 1) % n) + "] repeats the point before it");
    double turn = rattle::cross(b - a, c - b);
    if (turn == 0) {
      fail(at.str() + ": " + field + "[" + std::to_string((i + 1) % n) +
           "]: three points in a line; a polygon must be strictly convex");
    }
    if (sign == 0) sign = turn;
    if ((turn > 0) != (sign > 0)) {
      fail(at.str() + ": " + field + " is not convex at point " + std::to_string((i + 1) % n) +
           " (split it into convex pieces, or use a polyline for a wall)");
    }
  }
  // Same-sign turns can still wind twice (a pentagram): count how often the edge direction, turning
  // counterclockwise (mirrored when the turns are clockwise), wraps around: passes from the upper half
  // plane (angles 0 to pi) to the lower one (-pi to 0) across the negative x axis. That is where its angle
  // in (-pi, pi] would drop, but the test is on signs alone, so it is exact and the same on every
  // machine: std::atan2 is libm's and its last bit may differ between x86-64 and aarch64, which could
  // accept a map on one and refuse it on the other (tools/determinism/README.md, "libm").
  const auto below = [&](size_t i) {
    const Vec2 e = pts[(i + 1) % n] - pts[i % n];
    const double y = sign > 0 ? e.y : -e.y;
    return y < 0 || (y == 0 && std::signbit(y) && e.x < 0);  // atan2(-0, x < 0) is -pi
  };
  int wraps = 0;
  for (size_t i = 1; i <= n; ++i) {
    if (below(i % n) && !below(i - 1)) ++wraps;
  }
  if (wraps > 1) fail(at.str() + ": " + field + " winds around more than once; it is not a simple convex polygon");
}

void requirePolyline(const Place& at, const std::vector<Vec2>& pts) {
  if (pts.size() < 2) fail(at.str() + ": polyline has " + std::to_string(pts.size()) + " points: at least 2");
  for (size_t i = 1; i < pts.size(); ++i) {
    if (pts[i] == pts[i - 1]) fail(at.str() + ": polyline[" + std::to_string(i) + "] repeats the point before it");
  }
}

// A closed area: polygon (convex), rectangle, or for some kinds a circle.
std::vector<Vec2> convexArea(const Place& at, const Shape& s, const std::string& kind) {
  if (s.kind == ShapeKind::Rectangle) {
    if (!(s.width > 0) || !(s.height > 0)) {
      fail(at.str() + ": width = " + formatNumber(s.widthPx) + ", height = " + formatNumber(s.heightPx) +
           ": a rectangle needs both > 0");
    }
    return {{0, 0}, {s.width, 0}, {s.width, s.height}, {0, s.height}};
  }
  if (s.kind == ShapeKind::Polygon) {
    if (s.points.size() > kMaxPolygonPoints) {
      fail(at.str() + ": polygon has " + std::to_string(s.points.size()) + " points, at most " +
           std::to_string(kMaxPolygonPoints) + " (split it into convex pieces)");
    }
    requireConvex(at, s.points, "polygon");
    return s.points;
  }
  wrongShape(at, s, kind, "a convex polygon or a rectangle");
}

rattle::Circle circleOf(const Place& at, const Shape& s) {
  if (!(s.width > 0) || s.width != s.height) {
    fail(at.str() + ": ellipse width = " + formatNumber(s.widthPx) + ", height = " + formatNumber(s.heightPx) +
         ": only circles (width == height > 0) are supported");
  }
  return rattle::Circle{{s.width / 2, s.height / 2}, s.width / 2};
}

// The engine's own check, last: it sees world units, so its numbers are not the file's.
void checkGeometry(const Place& at, const rattle::Geometry& g, double ppu) {
  if (auto why = rattle::validationError(g)) {
    fail(at.str() + ": " + *why + " (in world units: the file's pixels divided by pixels_per_unit " + formatNumber(ppu) + ")");
  }
}

// The kind: property 'kind', or Tiled's class field ("class" since 1.9, "type" before).
std::string kindOf(const Place& at, const json& object, Properties& props) {
  if (props.has("kind")) return props.string("kind");
  for (const char* field : {"class", "type"}) {
    auto it = object.find(field);
    if (it != object.end() && it->is_string() && !it->get_ref<const std::string&>().empty()) {
      return boundedString(at, field, *it);
    }
  }
  fail(at.str() + ": property 'kind' is missing (one of wall, building, spawn, doorway, room, gate)");
}

struct Loader {
  Map map;
  double widthPx = 0, heightPx = 0;  // the map's size as the file gives it, for messages
  std::set<int> ids;
  size_t objectCount = 0;

  void object(const Place& layerPlace, const json& object, Vec2 layerOffset) {
    Place at = layerPlace;
    if (!object.is_object()) fail(at.str() + ": layer " + inQuotes(at.layer) + ": objects: entry is not an object");
    if (++objectCount > kMaxObjects) fail(at.str() + ": more than " + std::to_string(kMaxObjects) + " objects");
    auto idIt = object.find("id");
    if (idIt == object.end() || !idIt->is_number_integer() || idIt->get<int64_t>() < 0 ||
        idIt->get<int64_t>() > 1'000'000'000) {
      fail(at.str() + ": layer " + inQuotes(at.layer) + ": object #" + std::to_string(objectCount) +
           " has no valid id (id = " + (idIt == object.end() ? std::string("missing") : shown(*idIt)) + ")");
    }
    at.objectId = static_cast<int>(idIt->get<int64_t>());
    if (!ids.insert(at.objectId).second) fail(at.str() + ": id " + std::to_string(at.objectId) + " is used twice");

    const double ppu = map.pixelsPerUnit;
    Properties props(at, object);
    std::string kind = kindOf(at, object, props);
    Shape s = readShape(at, object, ppu);
    s.origin += layerOffset;
    auto name = [&] { return object.contains("name") ? boundedString(at, "name", object["name"]) : std::string(); };

    if (kind == "wall" || kind == "building") {
      MapWall w{at.objectId, s.origin, rattle::Circle{}, kind == "building"};
      if (s.kind == ShapeKind::Polyline && kind == "wall") {
        requirePolyline(at, s.points);
        w.shape = rattle::Polyline{s.points};
      } else if (s.kind == ShapeKind::Ellipse) {
        w.shape = circleOf(at, s);
      } else if (s.kind == ShapeKind::Rectangle || s.kind == ShapeKind::Polygon) {
        w.shape = rattle::Polygon{convexArea(at, s, kind)};
      } else {
        wrongShape(at, s, kind, kind == "wall" ? "a polyline, convex polygon, rectangle or circle"
                                               : "a convex polygon, rectangle or circle");
      }
      checkGeometry(at, w.shape, ppu);
      props.rejectUnused(kind, "");
      map.walls.push_back(std::move(w));
    } else if (kind == "spawn") {
      if (s.kind != ShapeKind::Point) wrongShape(at, s, kind, "a point");
      int team = props.team("team");
      props.rejectUnused(kind, "team");
      if (s.origin.x < 0 || s.origin.y < 0 || s.origin.x > map.width || s.origin.y > map.height) {
        fail(at.str() + ": x, y = " + formatNumber(s.xPx) + ", " + formatNumber(s.yPx) +
             (layerOffset == Vec2{0, 0} ? std::string() : " (its layers are offset too)") +
             ": a spawn point must lie inside the map (" + formatNumber(widthPx) + " x " +
             formatNumber(heightPx) + " pixels)");
      }
      map.spawns.push_back({at.objectId, team, s.origin});
    } else if (kind == "doorway") {
      if (s.kind != ShapeKind::Polyline) wrongShape(at, s, kind, "a polyline of two points");
      if (s.points.size() != 2) {
        fail(at.str() + ": polyline has " + std::to_string(s.points.size()) + " points: a doorway is one segment (2)");
      }
      requirePolyline(at, s.points);
      bool sensor = props.boolean("sensor", true);
      if (!sensor) fail(at.str() + ": property 'sensor' = false: a doorway is always a sensor (use kind 'wall')");
      props.rejectUnused(kind, "sensor");
      map.doorways.push_back({at.objectId, name(), s.origin + s.points[0], s.origin + s.points[1]});
    } else if (kind == "room") {
      std::vector<Vec2> poly = convexArea(at, s, kind);
      bool sensor = props.boolean("sensor", true);
      if (!sensor) fail(at.str() + ": property 'sensor' = false: a room is always a sensor");
      props.rejectUnused(kind, "sensor");
      for (Vec2& p : poly) p += s.origin;
      checkGeometry(at, rattle::Polygon{poly}, ppu);
      map.rooms.push_back({at.objectId, name(), std::move(poly)});
    } else if (kind == "gate") {
      MapGate g;
      g.objectId = at.objectId;
      g.name = name();
      g.origin = s.origin;
      g.polygon = convexArea(at, s, kind);
      checkGeometry(at, rattle::Polygon{g.polygon}, ppu);
      if (!props.has("open_dx") && !props.has("open_dy")) {
        fail(at.str() + ": property 'open_dx' (or 'open_dy') is missing: how far the gate slides to open, in pixels");
      }
      const double openDx = props.number("open_dx", 0), openDy = props.number("open_dy", 0);
      g.openOffset = {openDx / ppu, openDy / ppu};
      if (g.openOffset == Vec2{0, 0}) fail(at.str() + ": properties 'open_dx', 'open_dy' are both 0: the gate cannot open");
      if (rattle::length(g.openOffset) > map.width + map.height) {
        fail(at.str() + ": properties 'open_dx', 'open_dy' = " + formatNumber(openDx) + ", " + formatNumber(openDy) +
             ": the gate would slide off the map (further than its width and height together, " +
             formatNumber(widthPx + heightPx) + " pixels)");
      }
      g.period = props.number("period", 8);
      if (g.period < 0 || g.period > 1e6) {
        fail(at.str() + ": property 'period' = " + formatNumber(g.period) + ": expected seconds in [0, 1e6]");
      }
      double speedPx = props.number("speed", 4 * ppu);
      if (!(speedPx > 0) || speedPx > 1e6) {
        fail(at.str() + ": property 'speed' = " + formatNumber(speedPx) + ": expected pixels per second in (0, 1e6]");
      }
      g.speed = speedPx / ppu;
      props.rejectUnused(kind, "open_dx, open_dy, period, speed");
      if (map.gates.size() >= kMaxGates) fail(at.str() + ": more than " + std::to_string(kMaxGates) + " gates");
      map.gates.push_back(std::move(g));
    } else {
      fail(at.str() + ": property 'kind' = " + inQuotes(kind) +
           ": unknown kind (one of wall, building, spawn, doorway, room, gate)");
    }
  }

  void layer(const Place& mapPlace, const json& layer, Vec2 offset, int depth) {
    Place at = mapPlace;
    if (!layer.is_object()) fail(at.str() + ": layers: an entry is not an object");
    at.layer = layer.contains("name") && layer["name"].is_string() ? layer["name"].get<std::string>() : "";
    if (at.layer.size() > kMaxStringBytes) at.layer = at.layer.substr(0, 64);
    std::string type = layer.contains("type") ? boundedString(at, "layer type", layer["type"]) : "";
    Vec2 here = offset;
    if (layer.contains("offsetx")) here.x += coordinate(at, "layer " + inQuotes(at.layer) + " offsetx", layer["offsetx"]) / map.pixelsPerUnit;
    if (layer.contains("offsety")) here.y += coordinate(at, "layer " + inQuotes(at.layer) + " offsety", layer["offsety"]) / map.pixelsPerUnit;
    if (type == "objectgroup") {
      auto it = layer.find("objects");
      if (it == layer.end() || !it->is_array()) {
        fail(at.str() + ": layer " + inQuotes(at.layer) + ": objects: expected an array");
      }
      for (const json& o : *it) object(at, o, here);
    } else if (type == "group") {
      if (depth >= kMaxLayerDepth) fail(at.str() + ": layer " + inQuotes(at.layer) + ": groups nested too deeply");
      auto it = layer.find("layers");
      if (it == layer.end() || !it->is_array()) fail(at.str() + ": layer " + inQuotes(at.layer) + ": layers: expected an array");
      for (const json& l : *it) this->layer(mapPlace, l, here, depth + 1);
    } else if (type == "tilelayer" || type == "imagelayer") {
      // Decoration only: the game reads objects.
    } else {
      fail(at.str() + ": layer " + inQuotes(at.layer) + ": type = " + inQuotes(type) +
           ": expected objectgroup, group, tilelayer or imagelayer");
    }
  }
};

int positiveInt(const Place& at, const json& doc, const char* field, int64_t max) {
  auto it = doc.find(field);
  if (it == doc.end()) fail(at.str() + ": field '" + field + "' is missing");
  if (!it->is_number_integer() || it->get<int64_t>() <= 0 || it->get<int64_t>() > max) {
    fail(at.str() + ": " + field + " = " + shown(*it) + ": expected a whole number from 1 to " + std::to_string(max));
  }
  return static_cast<int>(it->get<int64_t>());
}

// nlohmann's messages quote the token it read last ("last read: '...'"), which can be a whole megabyte
// string with newlines in it: keep messages one short line.
std::string tidied(std::string what) {
  constexpr size_t kMaxQuoted = 40, kMaxMessage = 300;
  if (size_t open = what.find("last read: '"); open != std::string::npos) {
    const size_t start = open + 12, close = what.rfind('\'');
    if (close != std::string::npos && close > start + kMaxQuoted) {
      what.replace(start + kMaxQuoted, close - start - kMaxQuoted, "...");
    }
  }
  if (what.size() > kMaxMessage) what = what.substr(0, kMaxMessage) + "...";
  return printable(what);
}

// "line L, column C" of the byte numbered `byte` (counting from 1, as nlohmann does).
std::string lineAndColumn(std::string_view text, size_t byte) {
  byte = std::min(byte, text.size());
  size_t line = 1, column = 1;
  for (size_t i = 0; i + 1 < byte; ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

// nlohmann reports a byte offset; a map author wants a line and column and, if we can tell, which object.
std::string describeParseError(std::string_view text, size_t byte, const std::string& what) {
  byte = std::min(byte, text.size());
  std::string out = lineAndColumn(text, byte) + ": not valid JSON (" + what + ")";
  // Best effort: the last key read and the last object id seen before the error, by a small forward scan.
  std::string_view before = text.substr(0, byte);
  std::string field, id;
  for (size_t i = 0; i < before.size(); ++i) {
    if (before[i] != '"') continue;
    size_t close = i + 1;
    while (close < before.size() && before[close] != '"') close += before[close] == '\\' ? 2 : 1;
    if (close >= before.size()) break;
    std::string_view token = before.substr(i + 1, close - i - 1);
    size_t j = close + 1;
    while (j < before.size() && (before[j] == ' ' || before[j] == '\n' || before[j] == '\r' || before[j] == '\t')) ++j;
    if (j < before.size() && before[j] == ':') {
      field = std::string(token.substr(0, 40));
      if (token == "id") {
        std::string digits;
        for (size_t k = j + 1; k < before.size() && digits.size() < 10; ++k) {
          if (before[k] >= '0' && before[k] <= '9') digits += before[k];
          else if (before[k] != ' ' || !digits.empty()) break;
        }
        if (!digits.empty()) id = digits;
      }
    }
    i = close;
  }
  if (!field.empty()) out += "; near field \"" + field + "\"";
  if (!id.empty()) out += " after object id " + id;
  return out;
}

// The first bracket that opens a level deeper than kMaxJsonDepth, or npos. Brackets inside strings do not
// count. On text that is valid JSON up to some point this counts exactly what the parser will see up to
// there, and the parser stops at its first error, so the parser never goes deeper than this allows.
size_t tooDeep(std::string_view text) {
  int depth = 0;
  bool inString = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (inString) {
      if (c == '\\') ++i;
      else if (c == '"') inString = false;
    } else if (c == '"') {
      inString = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth) return i;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return std::string_view::npos;
}

}  // namespace

Map parseMap(std::string_view text, const std::string& sourceName) {
  Place at{sourceName, "", -1};
  if (text.size() > kMaxMapFileBytes) {
    fail(sourceName + ": " + std::to_string(text.size()) + " bytes: a map may be at most " +
         std::to_string(kMaxMapFileBytes) + " bytes");
  }
  if (size_t at = tooDeep(text); at != std::string_view::npos) {
    fail(sourceName + ": " + lineAndColumn(text, at + 1) + ": arrays and objects nested more than " +
         std::to_string(kMaxJsonDepth) + " deep (a Tiled map needs far fewer)");
  }
  json doc;
  try {
    doc = json::parse(text.begin(), text.end());
  } catch (const json::parse_error& e) {
    std::string what = e.what();
    if (size_t p = what.find("] "); p != std::string::npos) what = what.substr(p + 2);  // "[json.exception...] "
    if (size_t p = what.find(": "); what.rfind("parse error", 0) == 0 && p != std::string::npos) what = what.substr(p + 2);
    fail(sourceName + ": " + describeParseError(text, e.byte, tidied(what)));
  } catch (const json::exception& e) {
    // A number too large for a double: nlohmann names the literal but not its place; find it.
    std::string what = e.what();
    if (size_t p = what.find("] "); p != std::string::npos) what = what.substr(p + 2);
    size_t open = what.find('\''), close = what.rfind('\'');
    if (open != std::string::npos && close > open + 1) {
      size_t at = text.find(what.substr(open + 1, close - open - 1));
      if (at != std::string_view::npos) fail(sourceName + ": " + describeParseError(text, at + 1, tidied(what)));
    }
    fail(sourceName + ": not valid JSON (" + tidied(what) + ")");
  }
  if (!doc.is_object()) fail(sourceName + ": the top level is not a JSON object (expected a Tiled map)");
  if (doc.contains("type") && doc["type"] != "map") fail(sourceName + ": type = " + shown(doc["type"]) + ": expected \"map\"");
  if (doc.contains("orientation") && doc["orientation"] != "orthogonal") {
    fail(sourceName + ": orientation = " + shown(doc["orientation"]) + ": only orthogonal maps are supported");
  }
  if (doc.contains("infinite") && doc["infinite"] != false) fail(sourceName + ": infinite = true: the map must have a fixed size");

  Loader L;
  L.map.source = sourceName;
  const int widthTiles = positiveInt(at, doc, "width", 100'000);
  const int heightTiles = positiveInt(at, doc, "height", 100'000);
  const int tileWidth = positiveInt(at, doc, "tilewidth", 4096);
  const int tileHeight = positiveInt(at, doc, "tileheight", 4096);

  Properties props(at, doc);
  L.map.pixelsPerUnit = props.number("pixels_per_unit", tileWidth);
  if (!(L.map.pixelsPerUnit > 0) || L.map.pixelsPerUnit > 1e4) {
    fail(sourceName + ": property 'pixels_per_unit' = " + formatNumber(L.map.pixelsPerUnit) + ": expected a number in (0, 10000]");
  }
  L.map.name = props.string("name");
  props.rejectUnused("map", "pixels_per_unit, name");
  L.widthPx = double(widthTiles) * tileWidth;
  L.heightPx = double(heightTiles) * tileHeight;
  L.map.width = L.widthPx / L.map.pixelsPerUnit;
  L.map.height = L.heightPx / L.map.pixelsPerUnit;
  // The limits are in world units, which the file never states: show how they follow from its fields.
  auto size = [&] {
    return formatNumber(L.map.width) + " x " + formatNumber(L.map.height) + " world units (" + std::to_string(widthTiles) + " x " +
           std::to_string(heightTiles) + " tiles of " + std::to_string(tileWidth) + " x " + std::to_string(tileHeight) +
           " pixels, pixels_per_unit " + formatNumber(L.map.pixelsPerUnit) + ")";
  };
  if (L.map.width > 1e5 || L.map.height > 1e5) fail(sourceName + ": the map is " + size() + ": at most 100000 each way");
  if (L.map.width * L.map.height > kMaxMapArea) {
    fail(sourceName + ": the map is " + size() + ": its area may be at most " + formatNumber(kMaxMapArea) +
         " square units (the game lays a one-unit grid over it)");
  }

  auto layers = doc.find("layers");
  if (layers == doc.end() || !layers->is_array()) fail(sourceName + ": field 'layers' is missing or not an array");
  for (const json& layer : *layers) L.layer(at, layer, {0, 0}, 0);

  bool teamHasSpawn[2] = {false, false};
  for (const MapSpawn& s : L.map.spawns) teamHasSpawn[s.team] = true;
  if (L.map.spawns.empty()) fail(sourceName + ": no spawn points (add point objects with kind 'spawn' and a team)");
  for (int team = 0; team < 2; ++team) {
    if (!teamHasSpawn[team]) fail(sourceName + ": no spawn point for team " + std::to_string(team));
  }
  return std::move(L.map);
}

std::string readMapFile(const std::string& path) {
  // A directory opens as a stream whose end is at the largest offset there is: say what it is instead.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw MapError(path + ": is a directory, not a map file");
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MapError(path + ": cannot open the map file" + errnoReason());
  in.seekg(0, std::ios::end);
  std::streamoff size = in.tellg();
  if (size < 0) throw MapError(path + ": cannot read the map file");
  if (static_cast<size_t>(size) > kMaxMapFileBytes) {
    throw MapError(path + ": " + std::to_string(size) + " bytes: a map may be at most " +
                   std::to_string(kMaxMapFileBytes) + " bytes");
  }
  in.seekg(0);
  std::string text(static_cast<size_t>(size), '\0');
  in.read(text.data(), size);
  if (!in) throw MapError(path + ": cannot read the map file");
  return text;
}

Map loadMap(const std::string& path) { return parseMap(readMapFile(path), path); }

}  // namespace rts
