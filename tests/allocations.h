// Counting every allocation of the test program (operator new and delete are replaced in
// allocations.cpp, for the library too), so that memory bounds are checked against what was
// really allocated, not against the arithmetic that states them.
#pragma once

#include <cstdint>

namespace dacrt::test {

// The most bytes allocated at once, beyond what was allocated when the watch started, by any
// thread, until peak() is read.
class AllocationWatch {
 public:
  AllocationWatch();
  uint64_t peak() const;
  // The bytes allocated and not yet freed, by the whole program, now.
  static uint64_t live();

 private:
  uint64_t base_;
};

}  // namespace dacrt::test
