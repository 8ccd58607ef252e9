#include "tool/build_facts.h"

#include <cfloat>
#include <map>

#include "build_info.h"
#include "map/printable.h"

namespace rts::replay {
namespace {

std::string compiler() {
#if defined(__clang__)
  return std::string("Clang ") + __clang_version__;
#elif defined(__GNUC__)
  return std::string("GNU ") + __VERSION__;
#elif defined(_MSC_VER)
  return "MSVC " + std::to_string(_MSC_FULL_VER);
#else
  return "unknown";
#endif
}

std::string architecture() {
#if defined(__x86_64__) || defined(_M_X64)
  std::string a = "x86_64";
#elif defined(__aarch64__)
  std::string a = "aarch64";
#elif defined(__i386__)
  std::string a = "i386";
#else
  std::string a = "other";
#endif
#if defined(__AVX2__)
  a += " avx2";
#elif defined(__AVX__)
  a += " avx";
#endif
#if defined(__FMA__)
  a += " fma";
#endif
  return a;
}

// What the compiler says about floating point in this translation unit (compiled with the same flags
// as the engine).
std::string floatingPoint() {
  std::string f = "FLT_EVAL_METHOD=" + std::to_string(FLT_EVAL_METHOD);
#if defined(__FAST_MATH__)
  f += " fast-math";
#endif
#if defined(__FP_FAST_FMA)
  f += " fast-fma";
#endif
#if defined(__SSE2_MATH__)
  f += " sse2-math";
#endif
#if defined(__OPTIMIZE__)
  f += " optimized";
#endif
  return f;
}

std::string sanitizers() {
#if defined(__SANITIZE_ADDRESS__)
  const bool address = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  const bool address = true;
#else
  const bool address = false;
#endif
#else
  const bool address = false;
#endif
  // GCC has no macro for UBSan: the CMake option says whether it is on.
  const bool cmakeOption = std::string(RATTLE_BUILD_SANITIZE) == "ON";
  return cmakeOption ? "address,undefined" : address ? "address" : "none";
}

std::string standardLibrary() {
#if defined(_LIBCPP_VERSION)
  return "libc++ " + std::to_string(_LIBCPP_VERSION);
#elif defined(_GLIBCXX_RELEASE)
  return "libstdc++ " + std::to_string(_GLIBCXX_RELEASE);
#else
  return "unknown";
#endif
}

}  // namespace

std::vector<BuildFact> thisBuild() {
  return {
      {"engine", std::string("rattle ") + RATTLE_BUILD_ENGINE_VERSION},
      {"compiler", compiler()},
      {"build type", RATTLE_BUILD_TYPE},
      {"flags", RATTLE_BUILD_CXX_FLAGS},
      {"floating point", floatingPoint()},
      {"architecture", architecture()},
      {"standard library", standardLibrary()},
      {"sanitizers", sanitizers()},
  };
}

std::vector<std::string> buildDifferences(const std::vector<BuildFact>& recorded, const std::vector<BuildFact>& current) {
  std::map<std::string, std::pair<const std::string*, const std::string*>> all;
  for (const BuildFact& f : recorded) all[f.key].first = &f.value;
  for (const BuildFact& f : current) all[f.key].second = &f.value;
  std::vector<std::string> out;
  for (const auto& [key, values] : all) {
    const auto [was, now] = values;
    if (was && now && *was == *now) continue;
    // The recorded side comes from the file: printable, since verify prints these lines.
    out.push_back(printable(key) + ": recorded " + (was ? "\"" + printable(*was) + "\"" : "(not recorded)") + ", this build " +
                  (now ? "\"" + printable(*now) + "\"" : "(unknown)"));
  }
  return out;
}

}  // namespace rts::replay
