// rattle-world-api-inputs: runs files through the world_api fuzz target's entry point
// (fuzz/world_api.cpp) in an ordinary build, without libFuzzer, so that `make test` replays the seeds
// and the kept findings under g++ (and under ASan+UBSan in make test-sanitize). A violated invariant
// aborts with the fuzzer's message, after the line naming the file. Built with RATTLE_FUZZ_TARGET set to
// another target's name (fuzz/CMakeLists.txt), it is that target's runner (rattle-game-state-inputs).
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

#ifndef RATTLE_FUZZ_TARGET
#define RATTLE_FUZZ_TARGET "world_api"
#define RATTLE_FUZZ_PROGRAM "rattle-world-api-inputs"
#define RATTLE_FUZZ_ENVIRONMENT \
  "RATTLE_WORLD_API_OFF and RATTLE_WORLD_API_MODES apply as in the fuzzer (fuzz/README.md).\n"
#endif
#ifndef RATTLE_FUZZ_ENVIRONMENT
#define RATTLE_FUZZ_ENVIRONMENT ""
#endif

namespace {

void usage(FILE* out) {
  std::fputs(
      "usage: " RATTLE_FUZZ_PROGRAM " [--quiet] FILE|DIR...\n"
      "\n"
      "Runs each FILE, and each file of each DIR (in name order; README.md and seeds.txt skipped), as one\n"
      "input of the " RATTLE_FUZZ_TARGET " fuzz target (fuzz/" RATTLE_FUZZ_TARGET ".cpp). Prints the file's name\n"
      "before running it; a violated invariant aborts there with the fuzzer's message. Exit status 0 when\n"
      "every input passes, 2 on a usage error or a missing file.\n" RATTLE_FUZZ_ENVIRONMENT
      "\n"
      "  --quiet   print only the summary line\n"
      "  --help    this text\n",
      out);
}

}  // namespace

int main(int argc, char** argv) {
  bool quiet = false;
  std::vector<std::filesystem::path> files;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      usage(stdout);
      return 0;
    }
    if (arg == "--quiet") {
      quiet = true;
      continue;
    }
    if (arg.rfind("-", 0) == 0) {
      std::fprintf(stderr, RATTLE_FUZZ_PROGRAM ": %s: unknown option (see --help)\n", arg.c_str());
      return 2;
    }
    const std::filesystem::path path(arg);
    if (std::filesystem::is_directory(path)) {
      std::vector<std::filesystem::path> inside;
      for (const auto& entry : std::filesystem::directory_iterator(path)) {
        const std::string name = entry.path().filename().string();
        if (entry.is_regular_file() && name != "README.md" && name != "seeds.txt") inside.push_back(entry.path());
      }
      std::sort(inside.begin(), inside.end());
      files.insert(files.end(), inside.begin(), inside.end());
    } else if (std::filesystem::is_regular_file(path)) {
      files.push_back(path);
    } else {
      std::fprintf(stderr, RATTLE_FUZZ_PROGRAM ": %s: no such file or directory\n", arg.c_str());
      return 2;
    }
  }
  if (argc < 2 || (files.empty() && !quiet)) {
    usage(stderr);
    return 2;
  }
  for (const std::filesystem::path& file : files) {
    std::ifstream in(file, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!quiet) std::printf("%s (%zu bytes)\n", file.string().c_str(), bytes.size());
    std::fflush(stdout);
    LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
  }
  std::printf(RATTLE_FUZZ_PROGRAM ": %zu inputs, every invariant held\n", files.size());
  return 0;
}
