// The program's command line: --help, bad options and bad maps give one clear line and a non-zero exit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>
#include <sys/wait.h>

namespace {

struct Outcome {
  int status = -1;
  std::string output;
};

Outcome run(const std::string& arguments) {
  // One log per test: ctest runs these tests as parallel processes.
  const std::string log = testing::TempDir() + "/rattle_demo_program_" +
                          testing::UnitTest::GetInstance()->current_test_info()->name() + ".log";
  const std::string command = std::string(RATTLE_DEMO_BINARY) + " " + arguments + " > " + log + " 2>&1";
  Outcome r;
  const int raw = std::system(command.c_str());
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  std::ifstream in(log);
  r.output.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return r;
}

TEST(DemoProgram, HelpListsTheOptions) {
  Outcome r = run("--help");
  EXPECT_EQ(r.status, 0);
  for (const char* option : {"--map", "--ticks", "--seed", "--frames", "--every", "--size", "--units", "--no-render", "--window", "--steering"}) {
    EXPECT_NE(r.output.find(option), std::string::npos) << option;
  }
}

TEST(DemoProgram, BadOptionsNameTheOptionAndTheValue) {
  Outcome r = run("--ticks lots");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--ticks lots: expected a whole number"), std::string::npos) << r.output;
  r = run("--size 1280by720");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--size 1280by720"), std::string::npos) << r.output;
  r = run("--units 0");
  EXPECT_EQ(r.status, 2);
  r = run("--seed -3");
  EXPECT_EQ(r.status, 2);
  r = run("--fog purple");
  EXPECT_EQ(r.status, 2);
  r = run("--steering shove");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--steering shove: expected keep-apart or naive"), std::string::npos) << r.output;
  r = run("--steering");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--steering (missing)"), std::string::npos) << r.output;
  r = run("--steering naive --record " + testing::TempDir() + "/rattle_demo_naive.replay");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--steering naive cannot go with --record"), std::string::npos) << r.output;
  // A network player sees its own team's fog only (the parse refuses before any connection is tried).
  r = run("--host 0 --fog 1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--fog 1: a player in a network game sees its own team's fog only (0 here)"),
            std::string::npos)
      << r.output;
  r = run("--join 127.0.0.1:1 --fog none");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--fog none: a player in a network game sees its own team's fog only (1 here)"),
            std::string::npos)
      << r.output;
  r = run("--frobnicate");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("unknown option '--frobnicate'"), std::string::npos) << r.output;
  r = run("--ticks");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("(missing)"), std::string::npos) << r.output;
}

TEST(DemoProgram, ABadMapIsOneLineNamingTheObject) {
  const std::string path = testing::TempDir() + "/rattle_demo_bad_map.json";
  {
    std::ofstream out(path);
    out << R"({"type": "map", "width": 8, "height": 4, "tilewidth": 8, "tileheight": 8, "layers": [
      {"type": "objectgroup", "name": "stuff", "objects": [
        {"id": 41, "x": 8, "y": 8, "width": 8, "height": 8,
         "properties": [{"name": "kind", "type": "string", "value": "castle"}]}]}]})";
  }
  Outcome r = run("--no-render --map " + path);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("object 41 (layer \"stuff\"): property 'kind' = \"castle\": unknown kind"), std::string::npos)
      << r.output;
  r = run("--no-render --map /nonexistent.json");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("cannot open"), std::string::npos) << r.output;
}

TEST(DemoProgram, ADirectoryGivenAsTheMapIsNamedAsOne) {
  const std::string dir = testing::TempDir() + "/rattle_demo_map_dir";
  std::filesystem::create_directories(dir);
  Outcome r = run("--no-render --map " + dir);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find(dir + ": is a directory, not a map file"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("bytes"), std::string::npos) << r.output;
}

// The summary names the map and its rooms, which come from the file: no escape sequence gets through.
TEST(DemoProgram, TheSummaryShowsNamesFromTheMapWithoutControlBytes) {
  std::ifstream in(std::string(RATTLE_SOURCE_DIR) + "/assets/maps/small.json");
  std::string map((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto replace = [&](const std::string& from, const std::string& to) {
    const size_t at = map.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    map.replace(at, from.size(), to);
  };
  replace(R"("value": "small")", R"("value": "small\u001b]0;owned\u0007\u001b[2J")");
  replace(R"("name": "west")", R"("name": "west\r\u009b31m")");
  const std::string path = testing::TempDir() + "/rattle_demo_evil_names.json";
  std::ofstream(path) << map;
  Outcome r = run("--no-render --quiet --ticks 3 --units 2 --map " + path);
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("on small?]0;owned??[2J ("), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Rooms: west??31m "), std::string::npos) << r.output;
  for (char c : r.output) {
    const unsigned char b = static_cast<unsigned char>(c);
    EXPECT_FALSE((b < 0x20 && c != '\n') || b == 0x7f || b == 0x9b) << "byte " << int(b) << " in: " << r.output;
  }
}

// An earlier, longer game's frames in the same directory would be globbed into one video with this one's.
TEST(DemoProgram, FramesOfAnEarlierRunAreRemovedAndNothingElse) {
  const std::string dir = testing::TempDir() + "/rattle_demo_stale_frames";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::vector<std::string> stale = {"frame_000590.png", "frame_1000000.png"};
  const std::vector<std::string> kept = {"frame_1.png", "frame_notes.png", "frame_000030.png.txt", "notes.txt"};
  for (const std::string& name : stale) std::ofstream(dir + "/" + name) << "an earlier game";
  for (const std::string& name : kept) std::ofstream(dir + "/" + name) << "the user's";
  Outcome r = run("--map " + std::string(RATTLE_SOURCE_DIR) + "/assets/maps/small.json --units 2 --ticks 20 --every 10 --size 160x96 --frames " +
                  dir + " --quiet");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("removed 2 frame_NNNNNN.png files of an earlier run from " + dir), std::string::npos) << r.output;
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"frame_000000.png", "frame_000010.png", "frame_000020.png", "frame_000030.png.txt",
                                             "frame_1.png", "frame_notes.png", "notes.txt"}));
}

TEST(DemoProgram, AShortHeadlessRunEndsWithTheSummary) {
  const std::string frames = testing::TempDir() + "/rattle_demo_frames";
  Outcome r = run("--map " + std::string(RATTLE_SOURCE_DIR) + "/assets/maps/small.json --units 5 --ticks 20 --every 10 --size 160x96 --frames " +
              frames + " --quiet");
  EXPECT_EQ(r.status, 0) << r.output;
  for (const char* part : {"Ran 20 ticks", "Units left", "Shots fired", "Doorway crossings", "median", "Frames: 3 PNG"}) {
    EXPECT_NE(r.output.find(part), std::string::npos) << part << " in: " << r.output;
  }
  EXPECT_TRUE(std::ifstream(frames + "/frame_000020.png").good());
}

TEST(DemoProgram, NaiveSteeringIsNamedInTheSummaryWithTheStepTimes) {
  Outcome r = run("--map " + std::string(RATTLE_SOURCE_DIR) + "/assets/maps/small.json --units 5 --ticks 20 --no-render "
                  "--steering naive --quiet");
  EXPECT_EQ(r.status, 0) << r.output;
  for (const char* part : {"naive steering", "median", "95th percentile", "99th percentile", "worst"}) {
    EXPECT_NE(r.output.find(part), std::string::npos) << part << " in: " << r.output;
  }
  r = run("--map " + std::string(RATTLE_SOURCE_DIR) + "/assets/maps/small.json --units 5 --ticks 20 --no-render --quiet");
  EXPECT_EQ(r.output.find("naive steering"), std::string::npos) << r.output;
}

}  // namespace
