#pragma once
// Counts the heap allocations of the whole test process (the test binary and every library
// it loaded) between start and stop: a haptic step must make none.
#include <cstddef>

namespace suturesim::test_support
{
  struct Allocations
  {
    /// Calls of the replaceable operator new (the standard library's containers).
    std::size_t operator_new = 0;
    /// Calls of malloc, calloc, realloc, aligned_alloc, posix_memalign, memalign (Eigen's
    /// matrices: Eigen/src/Core/util/Memory.h allocates with std::malloc).
    std::size_t malloc = 0;

    std::size_t
    total() const
    {
      return operator_new + malloc;
    }
  };

  /// False under AddressSanitizer: its allocator serves operator new and malloc alike and
  /// its hook cannot tell them apart, so everything is counted in Allocations::malloc.
  extern const bool operator_new_counted_apart;

  void
  start_counting_allocations();

  Allocations
  stop_counting_allocations();
} // namespace suturesim::test_support
