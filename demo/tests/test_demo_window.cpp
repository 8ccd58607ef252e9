// The SDL2 window under Xvfb: a few seconds of scripted input (a drag selects blue units, a right-click
// sends them, space pauses and resumes, v hides the sight ranges), then the window's own picture is
// saved and checked: not blank, and the same size as asked.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sys/wait.h>

#include "render/png.h"

namespace {

TEST(DemoWindow, ScriptedInputUnderXvfbShowsTheGame) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0) {
    FAIL() << "xvfb-run is missing: scripts/install-deps.sh installs it (package xvfb)";
  }
  const std::string dir = testing::TempDir();
  const std::string script = dir + "/rattle_demo_input.txt", shot = dir + "/rattle_demo_window.png",
                    log = dir + "/rattle_demo_window.log";
  std::remove(shot.c_str());
  {
    std::ofstream out(script);
    out << "# frame event arguments (window pixels, 640x360 window on a 40x24 map: 16 px per unit)\n"
           "5 drag 20 20 330 370\n"    // the west room: blue's unit(s)
           "6 rclick 560 180\n"        // go east, through the doorway
           "30 key space\n"            // pause
           "40 key space\n"            // resume
           "50 key v\n"                // sight ranges off
           "60 key g\n"                // work the gate
           "70 click 100 100\n";       // select nothing much
  }
  const std::string command = std::string("xvfb-run -a -s '-screen 0 800x600x24' ") + RATTLE_DEMO_BINARY +
                              " --window --map " + RATTLE_SOURCE_DIR + "/assets/maps/small.json --units 3 --size 640x360" +
                              " --ticks 90 --input " + script + " --screenshot " + shot + " > " + log + " 2>&1";
  const int status = std::system(command.c_str());
  std::ifstream in(log);
  const std::string output((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(status, 0) << command << "\n" << output;
  EXPECT_NE(output.find("Ran 90 ticks"), std::string::npos) << output;

  int w = 0, h = 0;
  std::vector<uint8_t> rgba;
  ASSERT_EQ(rts::readPng(shot, w, h, rgba), "");
  EXPECT_EQ(w, 640);
  EXPECT_EQ(h, 360);
  std::set<uint32_t> colours;
  for (size_t i = 0; i + 3 < rgba.size(); i += 4) colours.insert(uint32_t(rgba[i]) | uint32_t(rgba[i + 1]) << 8 | uint32_t(rgba[i + 2]) << 16);
  EXPECT_GT(colours.size(), 20u) << "the window's picture is (nearly) blank";
}

TEST(DemoWindow, AnInputScriptThatIsADirectoryIsRefused) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0) {
    FAIL() << "xvfb-run is missing: scripts/install-deps.sh installs it (package xvfb)";
  }
  const std::string dir = testing::TempDir() + "/rattle_demo_input_dir", log = testing::TempDir() + "/rattle_demo_input_dir.log";
  std::filesystem::create_directories(dir);
  const std::string command = std::string("xvfb-run -a -s '-screen 0 800x600x24' ") + RATTLE_DEMO_BINARY + " --window --map " +
                              RATTLE_SOURCE_DIR + "/assets/maps/small.json --units 2 --size 160x96 --ticks 30 --input " + dir + " > " + log +
                              " 2>&1";
  const int raw = std::system(command.c_str());
  std::ifstream in(log);
  const std::string output((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, 1) << output;
  EXPECT_NE(output.find(dir + ": is a directory, not an input script"), std::string::npos) << output;
}

// Without a display SDL would fall back to a driver that shows nothing, and the game would run unseen.
TEST(DemoWindow, NoDisplayIsAnErrorNamingIt) {
  const std::string log = testing::TempDir() + "/rattle_demo_no_display.log";
  const std::string args = std::string(" --window --map ") + RATTLE_SOURCE_DIR + "/assets/maps/small.json --units 2 --size 160x96 --ticks 30";
  auto run = [&](const std::string& environment, std::string& output) {
    const std::string command = "env -u DISPLAY -u WAYLAND_DISPLAY -u SDL_VIDEODRIVER " + environment + " " + RATTLE_DEMO_BINARY + args +
                                " > " + log + " 2>&1";
    const int raw = std::system(command.c_str());
    std::ifstream in(log);
    output.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  };
  std::string output;
  EXPECT_EQ(run("", output), 1) << output;
  EXPECT_NE(output.find("cannot open a window: no display (DISPLAY and WAYLAND_DISPLAY are both unset)"), std::string::npos) << output;
  EXPECT_EQ(output.find("Ran 30 ticks"), std::string::npos) << output;
  // A display that is named but not there: SDL's own fallback must not pass for a window either.
  EXPECT_EQ(run("DISPLAY=:4093", output), 1) << output;
  EXPECT_NE(output.find("cannot open a window"), std::string::npos) << output;
  EXPECT_NE(output.find("DISPLAY=:4093"), std::string::npos) << output;
  EXPECT_EQ(output.find("Ran 30 ticks"), std::string::npos) << output;
}

}  // namespace
