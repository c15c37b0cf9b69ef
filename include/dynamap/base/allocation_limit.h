#pragma once
// AllocationLimit: a bound on the size of any single heap allocation while one is in scope.
//
// MRPT's deserializers trust the sizes a file states: a scan "of 2^31 beams" is resized, and zero
// filled, before its data are read. A reader keeps an AllocationLimit alive while it deserializes
// one record; any single allocation larger than the bound then throws std::bad_alloc, which the
// reader reports as a corrupt record. Outside a limit, allocation is as usual.
//
// Contract: this unit replaces the program's global operator new and delete (malloc and free
// underneath) and libmrpt-core's mrpt::aligned_malloc (MRPT's vectors allocate through it), and
// applies the innermost live limit of the calling thread. The replacements are linked into any
// program that uses AllocationLimit; nothing else in dynamap replaces an allocator.

#include <cstddef>

namespace dynamap {

/// Far above any real record's largest buffer (a laser scan of a million beams takes 4 MB).
constexpr std::size_t kMaxRecordAllocation = std::size_t{256} << 20;

/// The innermost live limit of the calling thread in bytes, 0 when none: for the replacements of
/// other libraries' allocators (rosbag's Buffer) that apply it too.
std::size_t currentAllocationLimit();

class AllocationLimit {
 public:
  /// While this object lives, single allocations above `max_bytes` on this thread throw
  /// std::bad_alloc, and so does any allocation that takes the bytes allocated since it was made
  /// (frees not subtracted) past `max_total` (0: no such bound). The total catches a record that
  /// states a count of many small things (a frame "of 67 million observations" is a deque grown
  /// in 512-byte blocks, each under any single bound); it throws once, then no longer applies in
  /// this limit's scope (so that unwinding can allocate). Limits nest; the previous one is restored
  /// on destruction, and what the inner one allocated counts in the outer one's total.
  explicit AllocationLimit(std::size_t max_bytes = kMaxRecordAllocation, std::size_t max_total = 0);
  ~AllocationLimit();
  AllocationLimit(const AllocationLimit&) = delete;
  AllocationLimit& operator=(const AllocationLimit&) = delete;

 private:
  std::size_t saved_, saved_total_, saved_used_;
};

}  // namespace dynamap
