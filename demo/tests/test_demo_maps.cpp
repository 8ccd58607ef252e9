// The map reader: the shipped maps load, and every kind of bad map fails with a message that names
// the object id and the field.
#include <gtest/gtest.h>

#include <string>

#include "map/map_loader.h"
#include "map/printable.h"

namespace {

using rts::Map;
using rts::MapError;

std::string assetPath(const std::string& name) { return std::string(RATTLE_SOURCE_DIR) + "/assets/maps/" + name; }

// A minimal valid map with two spawn points; `extra` adds objects to its one object layer.
std::string mapWith(const std::string& extra, const std::string& spawns =
                                                  R"({"id": 1, "x": 16, "y": 16, "point": true,
                                                      "properties": [{"name": "kind", "type": "string", "value": "spawn"},
                                                                     {"name": "team", "type": "int", "value": 0}]},
                                                     {"id": 2, "x": 48, "y": 16, "point": true,
                                                      "properties": [{"name": "kind", "type": "string", "value": "spawn"},
                                                                     {"name": "team", "type": "int", "value": 1}]})") {
  return R"({"type": "map", "orientation": "orthogonal", "infinite": false,
             "width": 8, "height": 4, "tilewidth": 8, "tileheight": 8,
             "layers": [{"type": "objectgroup", "name": "things", "objects": [)" +
         spawns + (extra.empty() || spawns.empty() ? "" : ",") + extra + "]}]}";
}

std::string object(int id, const std::string& kind, const std::string& shape, const std::string& moreProperties = "") {
  return "{\"id\": " + std::to_string(id) + ", " + shape +
         ", \"properties\": [{\"name\": \"kind\", \"type\": \"string\", \"value\": \"" + kind + "\"}" +
         (moreProperties.empty() ? "" : ", " + moreProperties) + "]}";
}

// Parses and returns the error message ("" when the map is accepted).
std::string errorOf(const std::string& json) {
  try {
    rts::parseMap(json, "test.json");
  } catch (const MapError& e) {
    return e.what();
  }
  return "";
}

void expectError(const std::string& json, std::initializer_list<const char*> fragments) {
  const std::string message = errorOf(json);
  ASSERT_FALSE(message.empty()) << "the map was accepted";
  for (const char* f : fragments) EXPECT_NE(message.find(f), std::string::npos) << "'" << f << "' not in: " << message;
}

TEST(DemoMaps, ArenaLoads) {
  Map m = rts::loadMap(assetPath("arena.json"));
  EXPECT_EQ(m.name, "arena");
  EXPECT_DOUBLE_EQ(m.width, 192);
  EXPECT_DOUBLE_EQ(m.height, 108);
  EXPECT_EQ(m.doorways.size(), 3u);
  EXPECT_EQ(m.gates.size(), 1u);
  EXPECT_EQ(m.rooms.size(), 3u);
  EXPECT_EQ(m.spawns.size(), 2u);
  int buildings = 0;
  for (const rts::MapWall& w : m.walls) buildings += w.building;
  EXPECT_GE(buildings, 4);
  EXPECT_GT(m.gates[0].period, 0);
}

TEST(DemoMaps, SmallMapLoads) {
  Map m = rts::loadMap(assetPath("small.json"));
  EXPECT_DOUBLE_EQ(m.width, 40);
  EXPECT_DOUBLE_EQ(m.height, 24);
  ASSERT_EQ(m.doorways.size(), 1u);
  EXPECT_EQ(m.doorways[0].a, (rts::Vec2{20, 8}));
  EXPECT_EQ(m.doorways[0].b, (rts::Vec2{20, 12}));
  ASSERT_EQ(m.gates.size(), 1u);
  EXPECT_EQ(m.gates[0].openOffset, (rts::Vec2{0, 3.5}));
  EXPECT_EQ(m.gates[0].period, 0);
}

TEST(DemoMaps, EveryShapeMapsOntoAGeometry) {
  const std::string json = mapWith(
      object(3, "wall", R"("x": 8, "y": 8, "polyline": [{"x": 0, "y": 0}, {"x": 16, "y": 0}, {"x": 16, "y": 8}])") + "," +
      object(4, "wall", R"("x": 40, "y": 8, "polygon": [{"x": 0, "y": 0}, {"x": 8, "y": 0}, {"x": 4, "y": 6}])") + "," +
      object(5, "building", R"("x": 24, "y": 16, "width": 8, "height": 4)") + "," +
      object(6, "wall", R"("x": 50, "y": 20, "width": 4, "height": 4, "ellipse": true)") + "," +
      object(7, "doorway", R"("x": 32, "y": 0, "polyline": [{"x": 0, "y": 0}, {"x": 0, "y": 8}])") + "," +
      object(8, "room", R"("x": 0, "y": 0, "width": 32, "height": 32)"));
  Map m = rts::parseMap(json, "shapes.json");
  ASSERT_EQ(m.walls.size(), 4u);
  EXPECT_TRUE(std::holds_alternative<rattle::Polyline>(m.walls[0].shape));
  EXPECT_TRUE(std::holds_alternative<rattle::Polygon>(m.walls[1].shape));
  EXPECT_TRUE(std::holds_alternative<rattle::Polygon>(m.walls[2].shape));
  EXPECT_TRUE(m.walls[2].building);
  ASSERT_TRUE(std::holds_alternative<rattle::Circle>(m.walls[3].shape));
  EXPECT_DOUBLE_EQ(std::get<rattle::Circle>(m.walls[3].shape).radius, 0.25);  // 4 px wide at 8 px per unit
  EXPECT_EQ(m.walls[3].origin, (rts::Vec2{50.0 / 8, 20.0 / 8}));
  ASSERT_EQ(m.doorways.size(), 1u);
  EXPECT_EQ(m.doorways[0].b, (rts::Vec2{4, 1}));
  ASSERT_EQ(m.rooms.size(), 1u);
  EXPECT_EQ(m.rooms[0].polygon[2], (rts::Vec2{4, 4}));
}

TEST(DemoMaps, KindMayComeFromTiledClass) {
  const std::string json = mapWith(R"({"id": 3, "class": "building", "x": 8, "y": 8, "width": 8, "height": 8})");
  EXPECT_EQ(rts::parseMap(json, "class.json").walls.size(), 1u);
}

TEST(DemoMaps, UnknownKind) {
  expectError(mapWith(object(7, "tower", R"("x": 8, "y": 8, "width": 8, "height": 8)")),
              {"object 7", "property 'kind'", "\"tower\"", "unknown kind"});
}

TEST(DemoMaps, MissingKind) {
  expectError(mapWith(R"({"id": 9, "x": 8, "y": 8, "width": 8, "height": 8})"), {"object 9", "property 'kind' is missing"});
}

TEST(DemoMaps, NonConvexPolygon) {
  expectError(mapWith(object(12, "building",
                             R"("x": 8, "y": 8, "polygon": [{"x": 0, "y": 0}, {"x": 16, "y": 0}, {"x": 4, "y": 4}, {"x": 0, "y": 16}])")),
              {"object 12", "polygon", "not convex at point"});
}

TEST(DemoMaps, PolygonThatWindsTwice) {
  // A pentagram: every corner turns the same way, but it goes round twice.
  expectError(mapWith(object(13, "building", R"("x": 32, "y": 16, "polygon": [{"x": 0, "y": -10}, {"x": 6, "y": 8},
                                                   {"x": -9.5, "y": -3}, {"x": 9.5, "y": -3}, {"x": -6, "y": 8}])")),
              {"object 13", "polygon", "winds around more than once"});
}

TEST(DemoMaps, ConvexPolygonsWindOnceEitherWayRound) {
  // The winding count works on the signs of the edges alone (no atan2): edges along the axes, whose
  // mirrored y is -0 when the turns are clockwise, and a start on either side of the axis, wind once.
  const char* polygons[] = {
      R"([{"x": 0, "y": 0}, {"x": 8, "y": 0}, {"x": 8, "y": 8}, {"x": 0, "y": 8}])",  // counterclockwise
      R"([{"x": 0, "y": 0}, {"x": 0, "y": 8}, {"x": 8, "y": 8}, {"x": 8, "y": 0}])",  // clockwise
      R"([{"x": 8, "y": 8}, {"x": 0, "y": 8}, {"x": 0, "y": 0}, {"x": 8, "y": 0}])",
      R"([{"x": 0, "y": 8}, {"x": 8, "y": 8}, {"x": 8, "y": 0}, {"x": 0, "y": 0}])",
      R"([{"x": 0, "y": 0}, {"x": 8, "y": 4}, {"x": 0, "y": 8}])",
      R"([{"x": 0, "y": 0}, {"x": 0, "y": 8}, {"x": 8, "y": 4}])",
      R"([{"x": 4, "y": 0}, {"x": 8, "y": 4}, {"x": 4, "y": 8}, {"x": 0, "y": 4}])",
      R"([{"x": 4, "y": 0}, {"x": 0, "y": 4}, {"x": 4, "y": 8}, {"x": 8, "y": 4}])",
  };
  for (const char* polygon : polygons) {
    EXPECT_EQ(errorOf(mapWith(object(14, "building", std::string(R"("x": 24, "y": 8, "polygon": )") + polygon))), "")
        << polygon;
  }
}

TEST(DemoMaps, MissingTeamOnSpawn) {
  expectError(mapWith(object(3, "spawn", R"("x": 8, "y": 8, "point": true)")), {"object 3", "property 'team' is missing"});
}

TEST(DemoMaps, BadTeam) {
  expectError(mapWith(object(3, "spawn", R"("x": 8, "y": 8, "point": true)",
                             R"({"name": "team", "type": "int", "value": 2})")),
              {"object 3", "property 'team' = 2", "expected 0 or 1"});
}

TEST(DemoMaps, MissingCoordinate) {
  expectError(mapWith(object(4, "building", R"("y": 8, "width": 8, "height": 8)")), {"object 4", "field 'x' is missing"});
}

TEST(DemoMaps, NaNLiteralIsReportedWithItsPlace) {
  const std::string message = errorOf(mapWith(object(5, "building", R"("x": NaN, "y": 8, "width": 8, "height": 8)")));
  ASSERT_FALSE(message.empty());
  EXPECT_NE(message.find("line 8, column"), std::string::npos) << message;
  EXPECT_NE(message.find("near field \"x\""), std::string::npos) << message;
  EXPECT_NE(message.find("after object id 5"), std::string::npos) << message;
}

TEST(DemoMaps, NaNTypedIntoAFloatProperty) {
  expectError(mapWith(object(6, "gate", R"("x": 8, "y": 8, "width": 8, "height": 4)",
                             R"({"name": "open_dx", "type": "float", "value": "NaN"})")),
              {"object 6", "property 'open_dx'", "\"NaN\"", "expected a number"});
}

TEST(DemoMaps, OverflowingNumber) {
  const std::string message = errorOf(mapWith(object(5, "building", R"("x": 1e999, "y": 8, "width": 8, "height": 8)")));
  EXPECT_NE(message.find("not valid JSON"), std::string::npos) << message;
  EXPECT_NE(message.find("near field \"x\""), std::string::npos) << message;
}

TEST(DemoMaps, NoSpawnPoints) {
  expectError(mapWith(object(3, "building", R"("x": 8, "y": 8, "width": 8, "height": 8)"), ""), {"no spawn points"});
}

TEST(DemoMaps, NoSpawnPointForOneTeam) {
  const std::string oneTeam = R"({"id": 1, "x": 16, "y": 16, "point": true,
      "properties": [{"name": "kind", "type": "string", "value": "spawn"}, {"name": "team", "type": "int", "value": 0}]})";
  expectError(mapWith("", oneTeam), {"no spawn point for team 1"});
}

TEST(DemoMaps, UnknownPropertyIsATypo) {
  expectError(mapWith(object(3, "spawn", R"("x": 8, "y": 8, "point": true)",
                             R"({"name": "team", "type": "int", "value": 0}, {"name": "tema", "type": "int", "value": 0})")),
              {"object 3", "property 'tema'", "not used by kind 'spawn'"});
}

TEST(DemoMaps, WrongShapeForKind) {
  expectError(mapWith(object(3, "doorway", R"("x": 8, "y": 8, "width": 8, "height": 8)")),
              {"object 3", "shape rectangle", "kind 'doorway'"});
  expectError(mapWith(object(4, "building", R"("x": 8, "y": 8, "polyline": [{"x": 0, "y": 0}, {"x": 8, "y": 0}])")),
              {"object 4", "shape polyline", "kind 'building'"});
}

TEST(DemoMaps, EllipseMustBeACircle) {
  expectError(mapWith(object(3, "wall", R"("x": 8, "y": 8, "width": 8, "height": 4, "ellipse": true)")),
              {"object 3", "ellipse width = 8, height = 4: only circles"});
}

TEST(DemoMaps, RotatedObject) {
  expectError(mapWith(object(3, "building", R"("x": 8, "y": 8, "width": 8, "height": 8, "rotation": 30)")),
              {"object 3", "rotation = 30"});
}

TEST(DemoMaps, GateThatCannotOpen) {
  expectError(mapWith(object(3, "gate", R"("x": 8, "y": 8, "width": 8, "height": 4)")), {"object 3", "'open_dx'", "missing"});
  expectError(mapWith(object(4, "gate", R"("x": 8, "y": 8, "width": 8, "height": 4)",
                             R"({"name": "open_dx", "type": "float", "value": 0})")),
              {"object 4", "both 0"});
}

TEST(DemoMaps, DuplicateIds) {
  expectError(mapWith(object(1, "building", R"("x": 8, "y": 8, "width": 8, "height": 8)")), {"object 1", "used twice"});
}

TEST(DemoMaps, SpawnOutsideTheMap) {
  expectError(mapWith(object(3, "spawn", R"("x": 800, "y": 8, "point": true)", R"({"name": "team", "type": "int", "value": 0})")),
              {"object 3", "x, y = 800, 8: a spawn point must lie inside the map (64 x 32 pixels)"});
}

// The file is in pixels (8 a world unit in these maps); its errors quote what the file says.
TEST(DemoMaps, ErrorsQuoteTheFilesPixelsNotWorldUnits) {
  expectError(mapWith(object(3, "building", R"("x": 8, "y": 8, "width": -152, "height": 32)")),
              {"object 3", "width = -152, height = 32: a rectangle needs both > 0"});
  expectError(mapWith(object(4, "room", R"("x": 8, "y": 8, "width": 24, "height": 0)")),
              {"object 4", "width = 24, height = 0: a rectangle needs both > 0"});
  expectError(mapWith(object(5, "wall", R"("x": 8, "y": 8, "width": 20, "height": 12, "ellipse": true)")),
              {"object 5", "ellipse width = 20, height = 12"});
  expectError(mapWith(object(6, "gate", R"("x": 8, "y": 8, "width": 8, "height": 4)",
                             R"({"name": "open_dx", "type": "float", "value": 100}, {"name": "open_dy", "type": "float", "value": -8})")),
              {"object 6", "'open_dx', 'open_dy' = 100, -8: the gate would slide off the map", "96 pixels"});
}

TEST(DemoMaps, NamesFromTheFileLoseTheirControlBytesInMessages) {
  expectError(mapWith(object(3, "spawn", R"("x": 8, "y": 8, "point": true)",
                             R"({"name": "team", "type": "int", "value": 0}, {"name": "te\u001b]0;x\u0007ma", "type": "int", "value": 0})")),
              {"object 3", "property 'te?]0;x?ma' is not used by kind 'spawn'"});
  expectError(mapWith(object(4, "wall", R"("x": 8, "y": 8, "width": 8, "height": 8)",
                             R"({"name": "a\u009bb", "value": 1}, {"name": "a\u009bb", "value": 2})")),
              {"object 4", "property 'a?b' is given twice"});
}

TEST(DemoMaps, PrintableReplacesWhatATerminalWouldActOn) {
  EXPECT_EQ(rts::printable("plain text, 'quotes' and \"more\""), "plain text, 'quotes' and \"more\"");
  EXPECT_EQ(rts::printable("a\x1b[2Jb\x1b]0;title\x07" "c"), "a?[2Jb?]0;title?c");
  EXPECT_EQ(rts::printable("line\r\nnext\ttab\x7f"), "line??next?tab?");
  EXPECT_EQ(rts::printable(std::string("nul\0byte", 8)), "nul?byte");
  // UTF-8 stays, except the C1 controls (U+0080 to U+009F) and the bidirectional overrides.
  EXPECT_EQ(rts::printable("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x8e\xae"), "caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x8e\xae");
  EXPECT_EQ(rts::printable("\xc2\x9b" "31m \xc2\x85 \xc2\xa0"), "?31m ? \xc2\xa0");
  EXPECT_EQ(rts::printable("abc\xe2\x80\xae" "def \xe2\x81\xa6" "x"), "abc?def ?x");
  // Bytes that are not UTF-8: one '?' each (a lone 0x9b is CSI to an 8-bit terminal).
  EXPECT_EQ(rts::printable("\x9b" "31m"), "?31m");
  EXPECT_EQ(rts::printable("\xff\xfe"), "??");
  EXPECT_EQ(rts::printable("\xc0\xaf"), "??");          // an overlong '/'
  EXPECT_EQ(rts::printable("\xed\xa0\x80"), "???");     // a surrogate
  EXPECT_EQ(rts::printable("\xf4\x90\x80\x80"), "????");  // past U+10FFFF
  EXPECT_EQ(rts::printable("cut \xe2\x82"), "cut ??");  // a sequence cut short
  EXPECT_EQ(rts::printable(""), "");
}

TEST(DemoMaps, NotAMapAtAll) {
  expectError("[1, 2, 3]", {"not a JSON object"});
  expectError("{\"width\": 8}", {"field 'height' is missing"});
  expectError("", {"not valid JSON"});
  expectError(R"({"type": "map", "width": 8, "height": 4, "tilewidth": 8, "tileheight": 8, "layers": [{"type": "objectgroup", "objects": 5}]})",
              {"objects: expected an array"});
}

TEST(DemoMaps, DeeplyNestedGroupsAreRefused) {
  std::string layers = R"({"type": "objectgroup", "objects": []})";
  // 20 groups: past the 16 group levels allowed, still within the 64 levels of JSON nesting allowed.
  for (int i = 0; i < 20; ++i) layers = R"({"type": "group", "name": "g", "layers": [)" + layers + "]}";
  expectError(R"({"type": "map", "width": 8, "height": 4, "tilewidth": 8, "tileheight": 8, "layers": [)" + layers + "]}",
              {"nested too deeply"});
}

TEST(DemoMaps, MissingFile) {
  EXPECT_THROW(rts::loadMap("/nonexistent/map.json"), MapError);
}

}  // namespace
