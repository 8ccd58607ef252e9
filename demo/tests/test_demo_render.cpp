// The renderer: the same game state gives the same bytes, and a frame is a picture, not a blank.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <set>
#include <variant>

#include "game/game.h"
#include "game/opponent.h"
#include "game/tick_loop.h"
#include "map/map_loader.h"
#include "render/offscreen.h"
#include "render/png.h"
#include "render/renderer.h"
#include "render/scene_builder.h"

namespace {

std::string assetPath(const std::string& name) { return std::string(RATTLE_SOURCE_DIR) + "/assets/maps/" + name; }

std::unique_ptr<rts::Game> playedGame(int ticks) {
  rts::GameConfig config;
  config.unitsPerTeam = 40;
  auto owned = std::make_unique<rts::Game>(rts::loadMap(assetPath("arena.json")), config);
  rts::Game& game = *owned;
  rts::ScriptedOpponent opponent(5);
  rts::TickLoop loop(game);
  loop.add(opponent);
  for (int t = 0; t < ticks; ++t) loop.tick();
  return owned;
}

// Distinct colours, and how many pixels differ from the first one.
std::pair<size_t, size_t> variety(const std::vector<uint8_t>& rgba) {
  std::set<uint32_t> colours;
  size_t differing = 0;
  for (size_t i = 0; i + 3 < rgba.size(); i += 4) {
    const uint32_t c = uint32_t(rgba[i]) | uint32_t(rgba[i + 1]) << 8 | uint32_t(rgba[i + 2]) << 16;
    colours.insert(c);
    differing += rgba[i] != rgba[0] || rgba[i + 1] != rgba[1] || rgba[i + 2] != rgba[2];
  }
  return {colours.size(), differing};
}

TEST(DemoRender, SameStateSameBytesAndNotBlank) {
  std::unique_ptr<rts::Game> owned = playedGame(90);
  const rts::Game& game = *owned;
  rts::SceneOptions options;
  options.showTimes = false;  // the one wall-clock number on screen
  rts::OffscreenRenderer renderer(320, 180, 2);
  const std::vector<uint8_t> first = renderer.render(rts::buildScene(game, options));
  const std::vector<uint8_t> second = renderer.render(rts::buildScene(game, options));
  EXPECT_EQ(first, second);
  auto [colours, differing] = variety(first);
  EXPECT_GT(colours, 50u);
  EXPECT_GT(differing, first.size() / 4 / 2) << "most of the frame is one colour";

  // A second renderer, and a second game played the same way, draw the very same frame.
  std::unique_ptr<rts::Game> again = playedGame(90);
  rts::OffscreenRenderer other(320, 180, 2);
  EXPECT_EQ(other.render(rts::buildScene(*again, options)), first);
}

// The window's network line (whom a network game waits for) is one more HUD line, drawn as the others;
// without one the HUD and the frame are as they were.
TEST(DemoRender, ABannerIsAThirdHudLine) {
  std::unique_ptr<rts::Game> owned = playedGame(10);
  rts::SceneOptions options;
  options.showTimes = false;
  const rts::Scene plain = rts::buildScene(*owned, options);
  ASSERT_EQ(plain.hud.size(), 2u);
  options.banner = "waiting for team 1 (red): its commands for tick 12 (1.5 s)";
  const rts::Scene banner = rts::buildScene(*owned, options);
  ASSERT_EQ(banner.hud.size(), 3u);
  EXPECT_EQ(banner.hud[0], plain.hud[0]);
  EXPECT_EQ(banner.hud[2], options.banner);
  rts::OffscreenRenderer renderer(320, 180, 1);
  const std::vector<uint8_t> without = renderer.render(plain);
  EXPECT_NE(renderer.render(banner), without) << "the banner is drawn";
}

TEST(DemoRender, UnitsAreDrawnInTheirTeamColours) {
  std::unique_ptr<rts::Game> owned = playedGame(1);
  const rts::Game& game = *owned;
  rts::SceneOptions options;
  options.fogTeam = -1;
  options.showSight = false;
  const int w = 640, h = 360;
  rts::OffscreenRenderer renderer(w, h, 2);
  const std::vector<uint8_t>& px = renderer.render(rts::buildScene(game, options));
  // The middle of blue's spawn blob is blue, of red's is red.
  auto at = [&](rts::Vec2 p) {
    const int x = int(p.x * w / game.map().width), y = int(p.y * h / game.map().height);
    return &px[(size_t(y) * w + size_t(x)) * 4];
  };
  const uint8_t* blue = at(game.units()[0].position);
  const uint8_t* red = at(game.units()[1].position);
  EXPECT_GT(blue[2], blue[0] + 60);
  EXPECT_GT(red[0], red[2] + 60);
}

// small.json, one unit a team: blue spawns at (8, 12) in the west room, red at (32, 12) in the open, 24
// units away, farther than any unit sees. Drawn at 16 pixels a world unit.
TEST(DemoRender, FogHidesTheEnemiesItCovers) {
  rts::GameConfig config;
  config.unitsPerTeam = 1;
  config.weapons = false;
  const rts::Game game(rts::loadMap(assetPath("small.json")), config);
  const rts::Unit& red = game.units()[1];
  ASSERT_EQ(red.team, 1);
  ASSERT_FALSE(game.visibleTo(0)[red.id]) << "the scene no longer hides red from blue";
  const int w = 640, h = 384;
  ASSERT_EQ(rts::fitView(game.map().width, game.map().height, w, h).scale, 16.0);
  rts::OffscreenRenderer renderer(w, h, 2);
  rts::SceneOptions options;
  options.showSight = false;
  options.showTimes = false;
  auto pixel = [&](const std::vector<uint8_t>& px, int x, int y) {
    const size_t i = (size_t(y) * w + size_t(x)) * 4;
    return std::array<int, 3>{px[i], px[i + 1], px[i + 2]};
  };
  const int cx = int(red.position.x * 16), cy = int(red.position.y * 16);
  const int reach = int(std::ceil(rts::kUnitTypes[red.type].radius * 16)) + 1;
  // Every pixel where red stands looks like the open ground two units east of it, where nothing is.
  auto differingFromGround = [&](const std::vector<uint8_t>& px) {
    int differing = 0;
    for (int y = cy - reach; y <= cy + reach; ++y) {
      for (int x = cx - reach; x <= cx + reach; ++x) differing += pixel(px, x, y) != pixel(px, x + 32, y);
    }
    return differing;
  };
  options.fogTeam = 0;
  EXPECT_EQ(differingFromGround(renderer.render(rts::buildScene(game, options))), 0) << "red shows through blue's fog";
  // Red's own view and no fog at all show it: the check above can fail.
  options.fogTeam = 1;
  EXPECT_GT(differingFromGround(renderer.render(rts::buildScene(game, options))), 100);
  options.fogTeam = -1;
  EXPECT_GT(differingFromGround(renderer.render(rts::buildScene(game, options))), 100);
}

// A trooper's shot on the arena at 1280x720 (6.67 pixels a world unit) is a streak a player sees: it
// changes at least 80 pixels of the ground clearly (by more than 60 of 255 in some channel), and its
// head is near white.
TEST(DemoRender, AShotIsClearlyVisibleAt1280x720) {
  rts::Scene scene;
  scene.worldWidth = 192;
  scene.worldHeight = 108;
  const int w = 1280, h = 720;
  rts::OffscreenRenderer renderer(w, h, 2);
  const std::vector<uint8_t> ground = renderer.render(scene);
  const rts::UnitType& trooper = rts::kUnitTypes[0];
  scene.shots.push_back({{96, 54}, {trooper.shotSpeed, 0}, trooper.shotRadius, 0});
  const std::vector<uint8_t>& shot = renderer.render(scene);
  int changed = 0, brightest = 0;
  for (size_t i = 0; i + 3 < shot.size(); i += 4) {
    int most = 0;
    for (int c = 0; c < 3; ++c) most = std::max(most, std::abs(int(shot[i + c]) - int(ground[i + c])));
    changed += most > 60;
    brightest = std::max(brightest, std::min({int(shot[i]), int(shot[i + 1]), int(shot[i + 2])}));
  }
  EXPECT_GE(changed, 80);
  EXPECT_GE(brightest, 220);
}

// A heavy's shot is a heavy's size (kUnitTypes[1].shotRadius, twice a trooper's), in the game and in
// the frame. small.json, one heavy a team; blue walks through the doorway until it fires.
TEST(DemoRender, ShotsHaveTheirShootersSize) {
  rts::GameConfig config;
  config.unitsPerTeam = 1;
  config.unitTypes = {1};
  rts::Game game(rts::loadMap(assetPath("small.json")), config);
  rts::Command c;
  c.team = 0;
  c.type = rts::CommandType::Move;
  c.units = {0};
  c.target = {26, 10};
  ASSERT_TRUE(game.apply(c));
  for (int t = 0; t < 600 && game.shots().empty(); ++t) game.tick();
  ASSERT_FALSE(game.shots().empty()) << "nobody fired";
  const double radius = rts::kUnitTypes[1].shotRadius;
  ASSERT_NE(radius, rts::kUnitTypes[0].shotRadius);
  const rattle::World& world = game.physics().world();
  const auto fixtures = world.fixtures(game.shots()[0].body);
  ASSERT_EQ(fixtures.size(), 1u);
  EXPECT_EQ(std::get<rattle::Circle>(world.geometry(fixtures[0])).radius, radius);
  const rts::Scene scene = rts::buildScene(game, rts::SceneOptions{});
  ASSERT_EQ(scene.shots.size(), game.shots().size());
  EXPECT_EQ(scene.shots[0].radius, radius);
}

TEST(DemoRender, PngRoundTrip) {
  std::vector<uint8_t> rgba(16 * 8 * 4);
  for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = uint8_t(i % 4 == 3 ? 255 : i * 7);
  const std::string path = testing::TempDir() + "/rattle_demo_roundtrip.png";
  ASSERT_EQ(rts::writePng(path, 16, 8, rgba), "");
  int w = 0, h = 0;
  std::vector<uint8_t> back;
  ASSERT_EQ(rts::readPng(path, w, h, back), "");
  EXPECT_EQ(w, 16);
  EXPECT_EQ(h, 8);
  EXPECT_EQ(back, rgba);
  EXPECT_NE(rts::writePng("/nonexistent/dir/x.png", 16, 8, rgba), "");
}

TEST(DemoRender, TooLargeAFrameIsAClearError) {
  EXPECT_THROW(rts::OffscreenRenderer(20000, 100, 2), rts::RenderError);
}

}  // namespace
