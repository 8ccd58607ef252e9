// Shared by the tests that run rattle-demo as a program (two or three processes playing one game): a
// scratch path per test, a process run to its end, a host read until it says its port, one in the
// background, and the line both players print at the end.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "game/commands.h"
#include "lockstep_test_support.h"

namespace net_test {

/// A per-test scratch path (ctest runs tests as parallel processes).
inline std::string scratch(const std::string& name) {
  const auto* info = testing::UnitTest::GetInstance()->current_test_info();
  return testing::TempDir() + "/rattle_net_" + info->test_suite_name() + "_" + info->name() + "_" + name;
}

struct Outcome {
  int status = -1;
  std::string output;  // stdout and stderr
};

inline int statusOf(int raw) { return raw != -1 && WIFEXITED(raw) ? WEXITSTATUS(raw) : -1; }

inline Outcome run(const std::string& binary, const std::string& arguments) {
  const std::string log = scratch("output.log");
  const std::string command = binary + " " + arguments + " > " + log + " 2>&1";
  Outcome r;
  r.status = statusOf(std::system(command.c_str()));
  r.output = readFile(log);
  return r;
}

inline bool has(const Outcome& o, const std::string& text) { return o.output.find(text) != std::string::npos; }

/// A host process, started first: its output is read through a pipe until it says which port the
/// system gave it (--host 0), so two tests never race for one. `timeout` ends it should the joiner
/// never come. `program`: rattle-demo, or the command that runs it (in a window under Xvfb).
class HostProcess {
 public:
  explicit HostProcess(const std::string& arguments, const std::string& program = RATTLE_DEMO_BINARY) {
    const std::string command = "timeout 120 " + program + " --host 0 " + arguments + " 2>&1";
    pipe_ = popen(command.c_str(), "r");
    if (!pipe_) return;
    char line[4096];
    while (port_ == 0 && std::fgets(line, sizeof line, pipe_)) {
      output_ += line;
      const char* at = std::strstr(line, "hosting on UDP port ");
      if (at) port_ = std::atoi(at + std::strlen("hosting on UDP port "));
    }
  }
  ~HostProcess() { finish(); }

  int port() const { return port_; }

  /// Reads the output until a line holds `text` (or the output ends); whether one did.
  bool readUntil(const std::string& text) {
    char line[4096];
    while (pipe_ && std::fgets(line, sizeof line, pipe_)) {
      output_ += line;
      if (std::strstr(line, text.c_str())) return true;
    }
    return false;
  }

  /// Reads the rest of the output and waits for the process.
  Outcome finish() {
    if (pipe_) {
      char buffer[4096];
      size_t n = 0;
      while ((n = std::fread(buffer, 1, sizeof buffer, pipe_)) > 0) output_.append(buffer, n);
      status_ = statusOf(pclose(pipe_));
      pipe_ = nullptr;
    }
    return {status_, output_};
  }

 private:
  FILE* pipe_ = nullptr;
  int port_ = 0;
  int status_ = -1;
  std::string output_;
};

/// The line both sides print at the end of a game, or "none".
inline std::string finalLine(const std::string& output) {
  const size_t at = output.find("Network game over after ");
  if (at == std::string::npos) return "none";
  return output.substr(at, output.find('\n', at) - at);
}

/// A process in the background (its output to a file), waited for by finish().
class Background {
 public:
  Background(const std::string& arguments, const std::string& log) : log_(log) {
    const std::string command = "timeout 120 " RATTLE_DEMO_BINARY " " + arguments + " > " + log + " 2>&1";
    pipe_ = popen(command.c_str(), "r");
  }
  ~Background() { finish(); }
  Outcome finish() {
    if (pipe_) {
      status_ = statusOf(pclose(pipe_));
      pipe_ = nullptr;
    }
    return {status_, readFile(log_)};
  }

 private:
  std::string log_;
  FILE* pipe_ = nullptr;
  int status_ = -1;
};

/// The same command recorded on both sides of a game: team, type, units and target.
inline void expectSameCommand(const rts::Command& x, const rts::Command& y) {
  EXPECT_EQ(x.team, y.team);
  EXPECT_EQ(x.type, y.type);
  EXPECT_EQ(x.units, y.units);
  EXPECT_EQ(x.target.x, y.target.x);
  EXPECT_EQ(x.target.y, y.target.y);
}

inline std::string hashIn(const std::string& line) {
  const size_t at = line.find("final state hash ");
  return at == std::string::npos ? "none" : line.substr(at + 17, 16);
}

}  // namespace net_test
