// The program's command line: --help, bad options and bad maps give one clear line and a non-zero exit.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>
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
  for (const char* option : {"--map", "--ticks", "--seed", "--frames", "--every", "--size", "--units", "--no-render", "--window"}) {
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

}  // namespace
