// AllocationLimit: single allocations above the bound throw, the total bound throws once and then
// lets the unwinding allocate, limits nest, and outside a limit nothing is bounded.

#include "dynamap/base/allocation_limit.h"

#include <gtest/gtest.h>

#include <memory>
#include <new>
#include <string>
#include <vector>

namespace dynamap {
namespace {

// Where an allocation is kept until freed: the compiler may not elide it.
void* volatile g_sink = nullptr;

// Allocates `n` bytes through operator new and frees them; true when it was refused.
bool refused(std::size_t n) {
  try {
    g_sink = ::operator new(n);
  } catch (const std::bad_alloc&) {
    return true;
  }
  ::operator delete(g_sink);
  return false;
}

TEST(AllocationLimit, ASingleAllocationAboveTheBoundThrows) {
  const AllocationLimit limit(1000);
  EXPECT_FALSE(refused(1000));
  EXPECT_TRUE(refused(1001));
  EXPECT_EQ(currentAllocationLimit(), 1000u);
}

TEST(AllocationLimit, TheTotalThrowsOnceThenLetsTheUnwindingAllocate) {
  const AllocationLimit limit(1000, 4000);
  EXPECT_FALSE(refused(1000));
  EXPECT_FALSE(refused(1000));
  EXPECT_FALSE(refused(1000));  // 3000 in all: frees do not count back
  EXPECT_TRUE(refused(1001));   // over the single bound: no matter the total
  EXPECT_FALSE(refused(1000));  // 4000
  EXPECT_TRUE(refused(1));      // 4001: over the total
  // Tripped: a handler formatting its message can allocate, the single bound still holds.
  EXPECT_FALSE(refused(500));
  EXPECT_TRUE(refused(2000));
}

TEST(AllocationLimit, ManySmallAllocationsOfOneStatedCountAreStopped) {
  // A container grown element by element to what a file states: each block small, all too many.
  const AllocationLimit limit(std::size_t{1} << 20, std::size_t{8} << 20);
  std::vector<std::unique_ptr<std::string>> blocks;
  bool stopped = false;
  try {
    for (int i = 0; i < 1000000; ++i) blocks.push_back(std::make_unique<std::string>(512, 'x'));
  } catch (const std::bad_alloc&) {
    stopped = true;
  }
  EXPECT_TRUE(stopped);
  EXPECT_LT(blocks.size(), 20000u);  // 8 MiB of 512-byte strings and their pointers
}

TEST(AllocationLimit, LimitsNestAndAreRestored) {
  // Results kept in plain bools and checked after the limits end: a check's own message must not
  // count against them.
  bool inner_over = false, inner_at = true, outer_single = true, outer_near = true,
       outer_over = false;
  std::size_t inside = 0, after_inner = 0;
  {
    const AllocationLimit outer(10000, 20000);
    {
      const AllocationLimit inner(100);
      inner_over = refused(101);
      inner_at = refused(100);
      inside = currentAllocationLimit();
    }
    after_inner = currentAllocationLimit();
    outer_single = refused(10000);
    outer_near = refused(9000);
    outer_over = refused(1000);  // 100 (inner) + 10000 + 9000 + 1000 > 20000
  }
  EXPECT_TRUE(inner_over);
  EXPECT_FALSE(inner_at);
  EXPECT_EQ(inside, 100u);
  EXPECT_EQ(after_inner, 10000u);
  EXPECT_FALSE(outer_single);
  EXPECT_FALSE(outer_near);
  EXPECT_TRUE(outer_over);
  EXPECT_EQ(currentAllocationLimit(), 0u);
  EXPECT_FALSE(refused(std::size_t{64} << 20));  // no limit outside
}

}  // namespace
}  // namespace dynamap
