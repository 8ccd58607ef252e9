// Measures the C++ heap a piece of code uses at its peak: this test binary replaces the global operator
// new and delete (heap_meter.cpp) with versions that count live bytes. Only the binary that links
// heap_meter.cpp is metered; nothing else in the project replaces operator new.
#pragma once

#include <cstddef>

namespace rattle_test {

/// How far the live bytes allocated through operator new rose above their level at construction. (Memory
/// allocated before and freed inside the scope lowers the level: the map reader frees none.)
class HeapMeter {
 public:
  HeapMeter();
  ~HeapMeter();
  size_t peak() const;

 private:
  long long start_;
};

}  // namespace rattle_test
