#include "dynamap/mapping/dynamic_grid_map.h"
// The miss of a run of cells, the inner loop of every insertion: 16 cells at a time with SSE2,
// 32 with AVX2 where the processor has it (chosen at run time), one by one otherwise. Every
// path does the same integer operations, so the same cells come out.

#include <atomic>
#include <cstdint>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "dynamap/mapping/ray_cast.h"

namespace dynamap {
namespace {

using cellType = DynamicGridMap::cellType;

#if defined(__SSE2__)
// mask ? a : b, lane by lane (SSE2 has no blend).
inline __m128i select(__m128i mask, __m128i a, __m128i b) {
  return _mm_or_si128(_mm_and_si128(mask, a), _mm_andnot_si128(mask, b));
}

// A miss's update of 16 cells: saturating add, then clamp to the layer's range. Saturating
// first changes nothing the clamp keeps, so this equals the scalar clampCell(c + delta, lo, hi).
struct SimdStep {
  __m128i delta, lo, hi;
  __m128i apply(__m128i c) const {
    const __m128i sum = _mm_adds_epi8(c, delta);
    const __m128i raised = select(_mm_cmpgt_epi8(lo, sum), lo, sum);
    return select(_mm_cmpgt_epi8(raised, hi), hi, raised);
  }
};

// The bits set in a 16-bit mask, in a few instructions: without -mpopcnt (x86-64's baseline
// has no POPCNT) __builtin_popcount is a call into libgcc.
inline std::uint32_t popcount16(std::uint32_t x) {
  x = x - ((x >> 1) & 0x5555u);
  x = (x & 0x3333u) + ((x >> 2) & 0x3333u);
  x = (x + (x >> 4)) & 0x0F0Fu;
  return (x + (x >> 8)) & 0x1Fu;
}

inline __m128i loadLanes(const cellType (&lanes)[16]) {
  return _mm_load_si128(reinterpret_cast<const __m128i*>(lanes));
}

// The miss of 16 cells from `i`, those this scan has not updated yet: how many it updated.
// Cells it already updated (stamped) are left as they are, so blocks may overlap. (A template
// only because the kernel is a private type of DynamicGridMap.)
template <typename Kernel>
struct MissBlock {
  const Kernel& k;
  __m128i mark, object_cell;
  SimdStep s_step, d_step;

  /// `lanes`: the cells of the 16 to consider (all, or the first few of a short span, the rest
  /// written back as they were).
  std::uint32_t operator()(std::size_t i, __m128i lanes = _mm_set1_epi8(-1)) const {
    auto* st = reinterpret_cast<__m128i*>(k.stamp + i);
    auto* sp = reinterpret_cast<__m128i*>(k.s + i);
    auto* dp = reinterpret_cast<__m128i*>(k.d + i);
    const __m128i st0 = _mm_loadu_si128(st);
    const __m128i fresh = _mm_andnot_si128(_mm_cmpeq_epi8(st0, mark), lanes);
    const int fresh_bits = _mm_movemask_epi8(fresh);
    if (fresh_bits == 0) return 0;
    _mm_storeu_si128(st, select(lanes, mark, st0));
    const __m128i s0 = _mm_loadu_si128(sp), d0 = _mm_loadu_si128(dp);
    const __m128i s1 = s_step.apply(s0), d1 = d_step.apply(d0);
    _mm_storeu_si128(sp, select(fresh, s1, s0));
    _mm_storeu_si128(dp, select(fresh, d1, d0));
    // An object cell (d < object_cell) that this miss takes out of the objects, in order.
    const __m128i left = _mm_andnot_si128(_mm_cmpgt_epi8(object_cell, d1),
                                          _mm_and_si128(fresh, _mm_cmpgt_epi8(object_cell, d0)));
    for (int bits = _mm_movemask_epi8(left); bits != 0; bits &= bits - 1) {
      k.changed->push_back(static_cast<std::uint32_t>(i + __builtin_ctz(bits)));
    }
    return popcount16(static_cast<std::uint32_t>(fresh_bits));
  }
};
#endif

}  // namespace

#if defined(__x86_64__) && defined(__GNUC__)
#define DYNAMAP_AVX2_SPANS 1
namespace {

// MissBlock's update over 32 cells, for processors with AVX2 (chosen at run time: the build
// assumes only x86-64's SSE2). The same integer operations, so the same cells.
__attribute__((target("avx2,popcnt"))) inline std::uint32_t missBlock32(
    cellType* s, cellType* d, std::uint8_t* stamp, std::vector<std::uint32_t>& changed,
    std::size_t i, const __m256i (&c)[8]) {
  enum { kMark, kObject, kSDelta, kSLo, kSHi, kDDelta, kDLo, kDHi };
  auto* st = reinterpret_cast<__m256i*>(stamp + i);
  auto* sp = reinterpret_cast<__m256i*>(s + i);
  auto* dp = reinterpret_cast<__m256i*>(d + i);
  const __m256i fresh =
      _mm256_xor_si256(_mm256_cmpeq_epi8(_mm256_loadu_si256(st), c[kMark]), _mm256_set1_epi8(-1));
  const auto fresh_bits = static_cast<std::uint32_t>(_mm256_movemask_epi8(fresh));
  if (fresh_bits == 0) return 0;
  _mm256_storeu_si256(st, c[kMark]);
  const __m256i s0 = _mm256_loadu_si256(sp), d0 = _mm256_loadu_si256(dp);
  const __m256i s1 =
      _mm256_min_epi8(_mm256_max_epi8(_mm256_adds_epi8(s0, c[kSDelta]), c[kSLo]), c[kSHi]);
  const __m256i d1 =
      _mm256_min_epi8(_mm256_max_epi8(_mm256_adds_epi8(d0, c[kDDelta]), c[kDLo]), c[kDHi]);
  _mm256_storeu_si256(sp, _mm256_blendv_epi8(s0, s1, fresh));
  _mm256_storeu_si256(dp, _mm256_blendv_epi8(d0, d1, fresh));
  const __m256i left =
      _mm256_andnot_si256(_mm256_cmpgt_epi8(c[kObject], d1),
                          _mm256_and_si256(fresh, _mm256_cmpgt_epi8(c[kObject], d0)));
  for (auto bits = static_cast<std::uint32_t>(_mm256_movemask_epi8(left)); bits != 0;
       bits &= bits - 1) {
    changed.push_back(static_cast<std::uint32_t>(i + __builtin_ctz(bits)));
  }
  return static_cast<std::uint32_t>(__builtin_popcount(fresh_bits));
}

// A span of at least 32 cells in blocks of 32, the last overlapping the one before.
template <typename Lanes>
__attribute__((target("avx2,popcnt"))) std::uint32_t spanAvx2(cellType* s, cellType* d,
                                                              std::uint8_t* stamp,
                                                              std::vector<std::uint32_t>& changed,
                                                              const Lanes& l, std::size_t begin,
                                                              std::size_t end) {
  const cellType* rows[8] = {l.mark, l.object_cell, l.s_delta, l.s_lo,
                             l.s_hi, l.d_delta,     l.d_lo,    l.d_hi};
  __m256i c[8];
  for (int r = 0; r < 8; ++r) {
    c[r] = _mm256_broadcastsi128_si256(_mm_load_si128(reinterpret_cast<const __m128i*>(rows[r])));
  }
  std::uint32_t freed = 0;
  std::size_t i = begin;
  for (; i + 32 <= end; i += 32) freed += missBlock32(s, d, stamp, changed, i, c);
  if (i < end) freed += missBlock32(s, d, stamp, changed, end - 32, c);
  return freed;
}

bool hasAvx2() {
  static const bool yes = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("popcnt");
  return yes;
}

}  // namespace
#endif

namespace {

// The path forceMissPath() set: read once per span, so a relaxed load costs nothing measurable.
std::atomic<DynamicGridMap::MissPath> g_forced{DynamicGridMap::MissPath::Auto};

}  // namespace

void DynamicGridMap::forceMissPath(MissPath path) {
  g_forced.store(path, std::memory_order_relaxed);
}

bool DynamicGridMap::missPathAvailable(MissPath path) {
  switch (path) {
    case MissPath::Auto:
    case MissPath::Scalar:
      return true;
    case MissPath::Sse2:
#if defined(__SSE2__)
      return true;
#else
      return false;
#endif
    case MissPath::Avx2:
#if defined(DYNAMAP_AVX2_SPANS)
      return hasAvx2();
#else
      return false;
#endif
  }
  return false;
}

std::uint32_t DynamicGridMap::MissKernel::span(std::size_t begin, std::size_t end) const {
  const MissKernel k = *this;
  std::uint32_t freed = 0;
  std::size_t i = begin;
  [[maybe_unused]] const MissPath path = g_forced.load(std::memory_order_relaxed);
#if defined(__SSE2__)
  if (path != MissPath::Scalar && k.lanes != nullptr && begin + 16 <= k.cells) {
    // 16 cells at a time: the miss is a saturating add clamped to the layer's range, the same
    // value the tables hold (lanes is null when a step does not fit a cell). The last block
    // ends at `end`, overlapping the one before: the overlap is stamped, so it is left alone.
    // A span shorter than a block takes its first lanes only (the grid goes on past it).
    const MissLanes& l = *k.lanes;
#if defined(DYNAMAP_AVX2_SPANS)
    if (path != MissPath::Sse2 && end - begin >= 32 && hasAvx2())
      return spanAvx2(k.s, k.d, k.stamp, *k.changed, l, begin, end);
#endif
    const MissBlock<MissKernel> block{
        k, loadLanes(l.mark), loadLanes(l.object_cell),
        SimdStep{loadLanes(l.s_delta), loadLanes(l.s_lo), loadLanes(l.s_hi)},
        SimdStep{loadLanes(l.d_delta), loadLanes(l.d_lo), loadLanes(l.d_hi)}};
    if (end - begin < 16) {
      const __m128i lane = _mm_setr_epi8(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
      return block(begin, _mm_cmplt_epi8(lane, _mm_set1_epi8(static_cast<char>(end - begin))));
    }
    for (; i + 16 <= end; i += 16) freed += block(i);
    if (i < end) freed += block(end - 16);
    return freed;
  }
#endif
  for (; i < end; ++i) freed += k.visit(i);
  return freed;
}

std::uint32_t DynamicGridMap::MissKernel::ray(int x0, int y0, int x1, int y1,
                                              std::size_t size_x) const {
  const MissKernel k = *this;
  std::uint32_t freed = 0;
  traceRayIndex(x0, y0, x1, y1, size_x, [k, &freed](std::size_t i) { freed += k.visit(i); });
  return freed;
}

}  // namespace dynamap
