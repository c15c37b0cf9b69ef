#include "dynamap/base/allocation_limit.h"

#include <mrpt/core/aligned_allocator.h>

#include <cstdlib>
#include <new>

// The program's replacements of the global operator new and delete (see the header's contract).
namespace {
thread_local std::size_t t_allocation_limit = 0;  // 0: no limit
thread_local std::size_t t_total_limit = 0;       // 0: no limit
thread_local std::size_t t_total_used = 0;        // bytes allocated under the live limit

// Throws std::bad_alloc when an allocation of n bytes breaks the live limit of this thread.
// The total trips once: the handlers that unwind the failed read (MRPT formats its exception
// messages with a call stack) must still allocate, or the bad_alloc would terminate the program.
inline void checkLimit(std::size_t n) {
  if (t_allocation_limit != 0 && n > t_allocation_limit) throw std::bad_alloc();
  t_total_used += n;  // counted under any limit: an inner one's bytes count in the outer's total
  if (t_total_limit != 0 && t_total_used > t_total_limit) {
    t_total_limit = 0;  // until the limit's scope ends
    throw std::bad_alloc();
  }
}
}  // namespace

// The operator delete below frees what the operator new below took from malloc; GCC cannot see
// that the two are replaced together and warns about every call it inlines.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif

void* operator new(std::size_t n) {
  checkLimit(n);
  if (void* p = std::malloc(n != 0 ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  return ::operator new(n);
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return ::operator new(n);
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, const std::nothrow_t& tag) noexcept {
  return ::operator new(n, tag);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}

namespace mrpt {
// MRPT's scans keep their beams in vectors of mrpt::aligned_allocator_cpp11, which allocate
// through this libmrpt-core function rather than operator new; this definition takes its place
// (same behaviour: C++17 aligned_alloc, released by mrpt::aligned_free's free()) and applies the
// record limit. Its callers do not check for null: a refusal throws.
void* aligned_malloc(std::size_t size, std::size_t alignment) {
  checkLimit(size);
  if (alignment != 0 && size % alignment != 0) size = (size / alignment + 1) * alignment;
  return ::aligned_alloc(alignment, size);
}
}  // namespace mrpt

namespace dynamap {

std::size_t currentAllocationLimit() {
  return t_allocation_limit;
}

AllocationLimit::AllocationLimit(std::size_t max_bytes, std::size_t max_total)
    : saved_(t_allocation_limit), saved_total_(t_total_limit), saved_used_(t_total_used) {
  t_allocation_limit = max_bytes;
  t_total_limit = max_total;
  t_total_used = 0;
}

AllocationLimit::~AllocationLimit() {
  t_allocation_limit = saved_;
  t_total_limit = saved_total_;
  t_total_used += saved_used_;
}

}  // namespace dynamap
