// Hostile maps: files built to crash the map reader, hang it or make it allocate far more than the
// file's size. Each must give a MapError that says what is wrong and where, and none may use more heap
// than kHeapPerByte times the file's size plus a small allowance (the same bound fuzz/map_reader.cpp
// enforces): nlohmann-json's document costs up to about 30 bytes per byte of the worst-shaped input.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>

#include "heap_meter.h"
#include "map/map_loader.h"

namespace {

constexpr size_t kHeapPerByte = 32;
constexpr size_t kHeapAllowance = 64 << 10;

std::string readAsset(const std::string& name) {
  std::ifstream in(std::string(RATTLE_SOURCE_DIR) + "/assets/maps/" + name, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// A map of the given size in tiles with two spawn points; `properties` go on the map, `objects` into
// its one object layer after the spawns.
std::string mapWith(const std::string& properties, const std::string& objects = "", int width = 8, int height = 4) {
  return R"({"type": "map", "width": )" + std::to_string(width) + R"(, "height": )" + std::to_string(height) +
         R"(, "tilewidth": 8, "tileheight": 8, "properties": [)" + properties +
         R"(], "layers": [{"type": "objectgroup", "name": "things", "objects": [
           {"id": 1, "x": 16, "y": 16, "point": true, "class": "spawn", "properties": [{"name": "team", "value": 0}]},
           {"id": 2, "x": 48, "y": 16, "point": true, "class": "spawn", "properties": [{"name": "team", "value": 1}]})" +
         (objects.empty() ? "" : ", " + objects) + "]}]}";
}

// Parses under the heap meter; returns the message ("" when the map was accepted) and checks the bound.
std::string errorOf(const std::string& json) {
  std::string message;
  size_t peak = 0;
  {
    rattle_test::HeapMeter meter;
    try {
      rts::parseMap(json, "hostile.json");
    } catch (const rts::MapError& e) {
      message = e.what();
    }
    peak = meter.peak();
  }
  EXPECT_LE(peak, kHeapPerByte * json.size() + kHeapAllowance) << "for a file of " << json.size() << " bytes";
  return message;
}

void expectError(const std::string& json, std::initializer_list<const char*> fragments) {
  const std::string message = errorOf(json);
  ASSERT_FALSE(message.empty()) << "the map was accepted";
  EXPECT_EQ(message.rfind("hostile.json: ", 0), 0u) << message;
  EXPECT_LT(message.size(), 600u) << message;
  for (const char* f : fragments) EXPECT_NE(message.find(f), std::string::npos) << "'" << f << "' not in: " << message;
}

std::string repeat(const std::string& s, size_t n) {
  std::string out;
  out.reserve(s.size() * n);
  for (size_t i = 0; i < n; ++i) out += s;
  return out;
}

}  // namespace

TEST(HostileMaps, TheShippedMapsStayWithinTheHeapBound) {
  // The bound is not vacuous: real maps use a few bytes of heap per byte of file.
  for (const char* name : {"arena.json", "small.json"}) {
    const std::string text = readAsset(name);
    EXPECT_EQ(errorOf(text), "") << name;
  }
}

TEST(HostileMaps, HundredThousandNestedArrays) {
  // Recursion in nlohmann-json (copies, comparisons, dumps) would overflow the stack on these.
  const std::string deep = repeat("[", 100'000) + repeat("]", 100'000);
  expectError(deep, {"line 1, column 65", "nested more than 64 deep"});
  expectError(mapWith(R"({"name": "name", "type": "string", "value": )" + deep + "}"), {"nested more than 64 deep"});
}

TEST(HostileMaps, HundredThousandNestedObjects) {
  expectError(repeat(R"({"a":)", 100'000) + "1" + repeat("}", 100'000), {"line 1, column 321", "nested more than 64 deep"});
}

TEST(HostileMaps, NestingCountsOnlyBracketsOutsideStrings) {
  // 60,000 brackets inside a string are just text (the escaped quotes do not end it); the name is then
  // too long, which is its own error.
  expectError(mapWith(R"({"name": "name", "type": "string", "value": ")" + repeat("[{\\\"", 30'000) + "\"}"),
              {"property 'name' is 90000 bytes long: at most 256"});
  // 64 levels are allowed (the limit is on what comes after).
  std::string ok = repeat("[", 64) + repeat("]", 64);
  expectError(ok, {"not a JSON object"});
}

TEST(HostileMaps, EnormousStrings) {
  const std::string big(4 << 20, 'x');
  expectError(mapWith(R"({"name": "name", "type": "string", "value": ")" + big + "\"}"),
              {"property 'name' is 4194304 bytes long: at most 256"});
  expectError(mapWith("", R"({"id": 3, "name": ")" + big + R"(", "class": "room", "x": 0, "y": 0, "width": 8, "height": 8})"),
              {"object 3", "name is 4194304 bytes long"});
  expectError(mapWith("", R"({"id": 3, "class": ")" + big + R"(", "x": 0, "y": 0})"), {"object 3", "class is 4194304 bytes long"});
  // Unknown top-level fields are ignored, however long; the file limit still holds.
  expectError(std::string(rts::kMaxMapFileBytes + 1, ' '), {"16777217 bytes: a map may be at most 16777216 bytes"});
}

TEST(HostileMaps, HugeCounts) {
  expectError(mapWith(R"({"name": "pixels_per_unit", "value": 1})", "", 100'000, 4),
              {"800000 x 32 world units (100000 x 4 tiles of 8 x 8 pixels, pixels_per_unit 1): at most 100000 each way"});
  expectError(mapWith("", "", 10'000, 10'000), {"10000 x 10000 world units (10000 x 10000 tiles of 8 x 8 pixels, pixels_per_unit 8): its area may be at most 1048576"});
  expectError(mapWith("", "", 2'000'000'000, 4), {"width = 2000000000: expected a whole number from 1 to 100000"});
  std::string points = "{\"x\": 0, \"y\": 0}";
  for (int i = 1; i <= 10'000; ++i) points += ", {\"x\": " + std::to_string(i % 2) + ", \"y\": " + std::to_string(i) + "}";
  expectError(mapWith("", R"({"id": 3, "class": "wall", "x": 0, "y": 0, "polyline": [)" + points + "]}"),
              {"object 3", "polyline has 10001 points, at most 10000"});
  // A convex polygon of 257 corners (on a circle): refused before the engine's O(n^2) convexity check.
  std::string corners;
  for (int i = 0; i < 257; ++i) {
    const double a = 2 * 3.141592653589793 * i / 257;
    corners += std::string(i ? ", " : "") + "{\"x\": " + std::to_string(1000 * std::cos(a)) + ", \"y\": " +
               std::to_string(1000 * std::sin(a)) + "}";
  }
  expectError(mapWith("", R"({"id": 3, "class": "building", "x": 0, "y": 0, "polygon": [)" + corners + "]}"),
              {"object 3", "polygon has 257 points, at most 256"});
  std::string props;
  for (int i = 0; i < 65; ++i) props += std::string(i ? ", " : "") + R"({"name": "p)" + std::to_string(i) + R"(", "value": 1})";
  expectError(mapWith("", R"({"id": 3, "class": "wall", "x": 0, "y": 0, "width": 8, "height": 8, "properties": [)" + props + "]}"),
              {"object 3", "65 of them, at most 64"});
  expectError(mapWith("", R"({"id": 3000000000, "class": "wall", "x": 0, "y": 0, "width": 8, "height": 8})"),
              {"has no valid id (id = 3000000000)"});
}

TEST(HostileMaps, NonFiniteAndOutOfRangeNumbers) {
  expectError(mapWith("", R"({"id": 3, "class": "wall", "x": NaN, "y": 0})"), {"not valid JSON"});
  expectError(mapWith("", R"({"id": 3, "class": "wall", "x": 1e999, "y": 0})"), {"not valid JSON", "1e999"});
  expectError(mapWith("", R"({"id": 3, "class": "wall", "x": 1e300, "y": 0, "width": 8, "height": 8})"),
              {"object 3", "x = 1.0000000000000001e+300: outside +-1e6 pixels"});
  expectError(mapWith(R"({"name": "pixels_per_unit", "value": "Infinity"})"), {"property 'pixels_per_unit'", "expected a number"});
  expectError(mapWith(R"({"name": "pixels_per_unit", "value": 1e-300})"), {"world units (8 x 4 tiles of 8 x 8 pixels, pixels_per_unit 1e-300): at most 100000 each way"});
  expectError(mapWith("", R"({"id": 3, "class": "gate", "x": 0, "y": 0, "width": 8, "height": 8,
                            "properties": [{"name": "open_dx", "value": 8}, {"name": "period", "value": -1e308}]})"),
              {"object 3", "property 'period' = -1e+308: expected seconds in [0, 1e6]"});
}

TEST(HostileMaps, WrongTypes) {
  expectError(R"({"type": "map", "width": 8, "height": 4, "tilewidth": 8, "tileheight": 8, "layers": {}})",
              {"field 'layers' is missing or not an array"});
  expectError(R"({"type": "map", "width": "8", "height": 4, "tilewidth": 8, "tileheight": 8, "layers": []})",
              {"width = \"8\": expected a whole number"});
  expectError(R"({"type": "map", "width": 8.5, "height": 4, "tilewidth": 8, "tileheight": 8, "layers": []})",
              {"width = 8.5"});
  expectError(R"({"type": ["map"], "width": 8, "height": 4, "tilewidth": 8, "tileheight": 8, "layers": []})",
              {"type = [...]: expected \"map\""});
  expectError(mapWith(R"({"name": "name", "value": {"a": [1, 2, 3]}})"), {"property 'name' = {...}: expected a string"});
  expectError(mapWith("", R"({"id": "3", "class": "wall", "x": 0, "y": 0})"), {"has no valid id (id = \"3\")"});
  expectError(mapWith("", R"({"id": 3, "class": "wall", "x": "0", "y": 0})"), {"object 3", "x = \"0\": expected a number"});
  expectError(mapWith("", R"({"id": 3, "class": "wall", "x": 0, "y": 0, "polyline": [1, 2]})"),
              {"object 3", "polyline[0] = 1: expected {x, y}"});
  expectError(mapWith("", R"({"id": 3, "class": "wall", "x": 0, "y": 0, "polyline": {"x": 1}})"),
              {"object 3", "polyline = {...}: expected an array of {x, y}"});
  expectError(mapWith("", R"({"id": 3, "class": "spawn", "x": 8, "y": 8, "point": true, "properties": [{"name": "team", "value": true}]})"),
              {"object 3", "property 'team' = true: expected 0 or 1"});
  expectError(mapWith("", R"({"id": 3, "class": "wall", "x": 0, "y": 0, "ellipse": "yes", "width": 8, "height": 8})"),
              {"object 3", "ellipse = \"yes\": expected true or false"});
  expectError(mapWith("", R"({"id": 3, "class": "wall", "x": 0, "y": 0, "properties": {"kind": "wall"}})"),
              {"object 3", "properties = {...}: expected an array"});
  expectError(mapWith("", "null"), {"objects: entry is not an object"});
}

TEST(HostileMaps, ControlBytesAndInvalidText) {
  expectError(std::string("{\"type\": \"map\"\0, \"width\": 8}", 27), {"line 1, column 15", "not valid JSON"});
  expectError(mapWith("", "{\"id\": 3, \"class\": \"wa\\u0000ll\", \"x\": 0, \"y\": 0}"), {"object 3", "unknown kind"});
  expectError("\xff\xfe{}", {"not valid JSON"});
  expectError(mapWith("", "{\"id\": 3, \"name\": \"\xc3\x28\", \"class\": \"wall\", \"x\": 0, \"y\": 0}"), {"not valid JSON"});
}

TEST(HostileMaps, EveryTruncationOfARealMapIsAnError) {
  // Cutting the file anywhere leaves an unclosed bracket, so every prefix must be refused cleanly.
  const std::string text = readAsset("small.json");
  for (size_t n = 0; n < text.size(); n += 7) {
    const std::string message = errorOf(text.substr(0, n));
    ASSERT_NE(message, "") << "a prefix of " << n << " bytes was accepted";
    ASSERT_EQ(message.rfind("hostile.json: ", 0), 0u) << message;
  }
}

