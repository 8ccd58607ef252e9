// Replaces operator new and delete (the plain, array, sized and nothrow forms; the over-aligned forms
// keep the library's own pair) with malloc plus a 16-byte header that holds the size, so that delete
// knows what it frees. The counters are atomic because GoogleTest may allocate from other threads.
#include "heap_meter.h"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <new>

namespace {

constexpr size_t kHeader = 16;  // keeps the alignment malloc gives (max_align_t)
std::atomic<long long> live{0};
std::atomic<long long> high{0};

void* allocate(size_t n) noexcept {
  char* block = static_cast<char*>(std::malloc(n + kHeader));
  if (!block) return nullptr;
  *reinterpret_cast<size_t*>(block) = n;
  const long long now = live.fetch_add(static_cast<long long>(n), std::memory_order_relaxed) + static_cast<long long>(n);
  long long seen = high.load(std::memory_order_relaxed);
  while (now > seen && !high.compare_exchange_weak(seen, now, std::memory_order_relaxed)) {
  }
  return block + kHeader;
}

void release(void* p) noexcept {
  if (!p) return;
  char* block = static_cast<char*>(p) - kHeader;
  live.fetch_sub(static_cast<long long>(*reinterpret_cast<size_t*>(block)), std::memory_order_relaxed);
  std::free(block);
}

void* allocateOrThrow(size_t n) {
  if (void* p = allocate(n)) return p;
  throw std::bad_alloc();
}

}  // namespace

void* operator new(size_t n) { return allocateOrThrow(n); }
void* operator new[](size_t n) { return allocateOrThrow(n); }
void* operator new(size_t n, const std::nothrow_t&) noexcept { return allocate(n); }
void* operator new[](size_t n, const std::nothrow_t&) noexcept { return allocate(n); }
void operator delete(void* p) noexcept { release(p); }
void operator delete[](void* p) noexcept { release(p); }
void operator delete(void* p, size_t) noexcept { release(p); }
void operator delete[](void* p, size_t) noexcept { release(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { release(p); }

namespace rattle_test {

// The peak is a high-water mark over the whole program, so a meter resets it to the live count at its
// start and reports how far above its start it rose. One meter at a time.
HeapMeter::HeapMeter() : start_(live.load()) { high.store(start_); }
HeapMeter::~HeapMeter() = default;
size_t HeapMeter::peak() const { return static_cast<size_t>(std::max(0LL, high.load() - start_)); }

}  // namespace rattle_test
