// Shared by the fuzz targets: a check that stops the fuzzer with a message (libFuzzer then saves the
// input as a crash), and a meter of the heap a call uses at its peak, through the sanitizer's malloc
// hooks (every fuzz target is built with AddressSanitizer).
#pragma once

#include <sanitizer/allocator_interface.h>

#include <cstddef>
#include <cstdio>
#include <cstdlib>

namespace rattle_fuzz {

[[noreturn]] inline void failed(const char* what, const char* detail) {
  std::fprintf(stderr, "\nrattle fuzz check failed: %s%s%s\n", what, detail ? ": " : "", detail ? detail : "");
  std::abort();
}

#define RATTLE_FUZZ_CHECK(condition, detail) \
  ((condition) ? (void)0 : ::rattle_fuzz::failed(#condition, detail))

/// Live heap bytes between start() and stop(), at their highest. One at a time; not thread-safe (the
/// fuzzers run one input at a time on one thread).
class HeapMeter {
 public:
  HeapMeter() {
    static const bool installed = __sanitizer_install_malloc_and_free_hooks(onMalloc, onFree) != 0;
    if (!installed) failed("the sanitizer's malloc hooks could not be installed", nullptr);
    live_ = peak_ = 0;
    on_ = true;
  }
  ~HeapMeter() { on_ = false; }
  size_t stop() {
    on_ = false;
    return peak_;
  }

 private:
  static void onMalloc(const volatile void*, size_t size) {
    if (!on_) return;
    live_ += size;
    if (live_ > peak_) peak_ = live_;
  }
  static void onFree(const volatile void* p) {
    if (!on_ || p == nullptr) return;
    const size_t size = __sanitizer_get_allocated_size(p);
    // Memory allocated before start() and freed inside it does not count against the call.
    live_ = size > live_ ? 0 : live_ - size;
  }
  static inline bool on_ = false;
  static inline size_t live_ = 0;
  static inline size_t peak_ = 0;
};

}  // namespace rattle_fuzz
