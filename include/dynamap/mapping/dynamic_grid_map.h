#pragma once
// DynamicGridMap: Wolf & Sukhatme's static map S and dynamic map D in one MRPT grid.
//
// The base COccupancyGridMap2D's own cells are S, so every MRPT tool that takes a grid (images,
// saving, likelihoods, localisation) works on the static map. D is a second layer of the same
// geometry and cell type, kept aligned with S whenever the grid grows. Both store MRPT's int8
// log-odds of being FREE (16 units per nat): a larger cell value means "more likely free".
//
// One pass over each 2D scan updates both layers with the inverse sensor model conditioned on
// the cell's static state before the scan (docs/design.md, "The method"): hits are applied first,
// then the free space, and every cell is updated at most once per scan, so a hit in a cell beats a
// miss in the same cell.
//
// Free space is the area the scan swept: the wedge between two adjacent beams is free up to the
// shorter of the two ranges less one cell (filled row by row, each cell once), and each beam
// frees the cells it crosses beyond that (MRPT's ray, from where the wedges stop covering it
// to its end cell). Near the sensor, where hundreds of beams cross the same cells, each cell is
// touched once; at depth edges and for lone beams it is exactly MRPT's ray.

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "dynamap/base/range_data.h"
#include "dynamap/mapping/dynamic_map_options.h"
#include "dynamap/mapping/polygon_fill.h"

namespace dynamap {

/// The most beams a scan may have to be inserted, into S and D or into the plain MRPT grid
/// (PlainGrid): MRPT's own insertion keeps two ints per beam on the stack, and a scan of
/// 2,000,000 beams overflows a stack of 8 MB. A wider scan is skipped by both, and by the Mapper
/// before anything else looks at it, and counted as kTooManyBeams. 100,000 is the most a
/// simulated laser may have, some 30 times a real 2D laser's, and 0.8 MB of MRPT's stack.
constexpr std::size_t kMaxScanBeams = 100000;
constexpr const char* kTooManyBeams = "more than 100,000 beams";

/// What the last scan did, for summaries and the object tracker.
struct ScanInsertStats {
  bool inserted = false;  ///< false: see skip_reason
  /// Why the scan was not inserted: "not horizontal", "no beams", kTooManyBeams, "aperture not
  /// positive", "pose not finite", "sensor pose not finite", "beyond max_map_size_m", "no usable
  /// beam"; nullptr when it was.
  const char* skip_reason = nullptr;
  std::uint32_t beams_used = 0;  ///< beams that updated at least one cell
  std::uint32_t beams_bad = 0;   ///< NaN, infinite or negative ranges (not inserted)
  std::uint32_t hit_cells = 0;   ///< distinct cells updated as hits
  std::uint32_t free_cells = 0;  ///< distinct cells updated as crossed
};

/// [m] the widest side a grid under `options` reaches: max_map_size_m, plus the margin MRPT
/// adds each time a grid grows (a few metres on each side).
inline double maxGridSide(const DynamicMapOptions& options) {
  return options.max_map_size_m + 20.0;
}

class DynamicGridMap : public mrpt::maps::COccupancyGridMap2D {
 public:
  using cellType = mrpt::maps::COccupancyGridMap2D::cellType;

  /// An empty map of the options' resolution; it grows to fit what is inserted.
  explicit DynamicGridMap(const DynamicMapOptions& options = {},
                          const InsertionOptions& insertion = {}, float x_min = -10.f,
                          float x_max = 10.f, float y_min = -10.f, float y_max = 10.f);

  const DynamicMapOptions& options() const { return options_; }

  /// Inserts a scan already worked out as range data (the pipeline's route: the same geometry
  /// the matcher and the tracker read), taken with the robot at `robot`. MRPT's
  /// insertObservation() of a CObservation2DRangeScan works the range data out and comes here.
  /// False when the scan was skipped (lastInsertStats() says why). `rd` must come from
  /// makeRangeData() (std::invalid_argument when its beam directions are missing).
  bool insertRange(const RangeData& rd, const mrpt::poses::CPose2D& robot);
  /// While held, a hit in S's free space leaves D as it is (S is updated as always): the layer
  /// above holds D while the scans disagree with S, when a hit there is the pose's error and
  /// not something that moved in (DynamicMapOptions::d_hold_share). Misses still fade D.
  void holdDynamic(bool hold) { hold_dynamic_ = hold; }
  bool dynamicHeld() const { return hold_dynamic_; }
  const InsertionOptions& insertion() const { return insertion_; }

  /// Grows S and D together, keeping every cell's content (hides the base's non-virtual one).
  void resizeGrid(float new_x_min, float new_x_max, float new_y_min, float new_y_max,
                  float new_cells_default_value = 0.5f, bool additionalMargin = true) noexcept;
  /// Gives S and D a new geometry together (hides the base's non-virtual one): S is filled with
  /// `default_value` as MRPT does, D keeps what it held where the two geometries overlap.
  void setSize(float x_min, float x_max, float y_min, float y_max, float resolution,
               float default_value = 0.5f);
  /// Starts S from another session's map of the same building: the grid becomes `size_x` x
  /// `size_y` cells of `resolution` m from (x_min, y_min), S the given raw cells (row by row, as
  /// getRawMap()), D empty everywhere. Throws std::invalid_argument when the resolution is not
  /// this map's, the cells do not fill the grid, or a side is longer than maxGridSide().
  void loadStatic(double x_min, double y_min, double resolution, unsigned size_x,
                  unsigned size_y, const std::vector<std::int8_t>& cells);
  /// Whether D has S's geometry. The base's own resizing (through a base pointer, or loading a
  /// grid) changes S alone: D is then realigned at the next insertion, and until then the D
  /// accessors below answer from D's last geometry, never out of its bounds.
  bool layersAligned() const;

  // --- the dynamic layer -------------------------------------------------------------------
  /// P(occupied) of D at a cell; 0.5 outside the grid.
  float dynamicOccupancy(int cx, int cy) const;
  /// P(occupied) of S at a cell (1 - getCell()); 0.5 outside the grid.
  float staticOccupancy(int cx, int cy) const;
  /// staticOccupancy() of a cell of the grid whose raw value (getRawMap()) is `v`.
  static float staticOccupancyOfValue(cellType v) { return 1.0f - cellProbability(v); }
  /// MRPT's l2p and l2p_255 of a raw cell value, from tables of all 256 values: MRPT's own pass
  /// through a function call per cell, and a picture or a pass over the grid converts millions.
  static float cellProbability(cellType v) { return kCellProbability[static_cast<std::uint8_t>(v)]; }
  static std::uint8_t cellGrey(cellType v) { return kCellGrey[static_cast<std::uint8_t>(v)]; }
  /// S's state that conditions the model: Free when P(occ) < free_threshold.
  bool isStaticFree(int cx, int cy) const {
    if (static_cast<unsigned>(cx) >= m_size_x || static_cast<unsigned>(cy) >= m_size_y)
      return false;
    return m_map[cx + static_cast<std::size_t>(cy) * m_size_x] >= free_cell_;
  }
  /// S holds the cell occupied (staticOccupancy > 0.5: its log-odds of free below 0); false
  /// outside the grid. Inline: the people detector asks it for every cell around a detection.
  bool isStaticOccupied(int cx, int cy) const {
    if (static_cast<unsigned>(cx) >= m_size_x || static_cast<unsigned>(cy) >= m_size_y)
      return false;
    return isOccupiedValue(m_map[cx + static_cast<std::size_t>(cy) * m_size_x]);
  }
  /// isStaticOccupied's test of one raw S value (a cell of getRow(), say).
  static constexpr bool isOccupiedValue(cellType cell) { return cell < 0; }
  /// D cell above object_threshold.
  bool isObjectCell(int cx, int cy) const {
    if (static_cast<unsigned>(cx) >= layer_size_x_ || static_cast<unsigned>(cy) >= layer_size_y_)
      return false;
    return isObjectIndex(cx + static_cast<std::size_t>(cy) * layer_size_x_);
  }
  bool isObjectIndex(std::size_t index) const { return dyn_[index] < object_cell_; }
  /// Raw D cells, row by row like getRawMap() when layersAligned().
  const std::vector<cellType>& dynamicRaw() const { return dyn_; }

  /// Linear indices (x + y * getSizeX()) of the D cells that crossed object_threshold, either
  /// way, during the last insertion. Valid until the next insertion or resize.
  const std::vector<std::uint32_t>& changedObjectCells() const { return changed_; }
  const ScanInsertStats& lastInsertStats() const { return last_stats_; }

  /// The inner loop of every miss: the fastest this processor has (Auto: AVX2, else SSE2), or
  /// one forced, process-wide, so that the tests can compare the paths cell by cell and a
  /// benchmark can time each. Every path gives the same cells. A path the build or the processor
  /// lacks runs as Auto.
  enum class MissPath { Auto, Scalar, Sse2, Avx2 };
  static void forceMissPath(MissPath path);
  /// Whether this build on this processor runs `path` as itself.
  static bool missPathAvailable(MissPath path);

  /// Counts over the whole grid (O(cells): for summaries, not per scan).
  struct CellCounts {
    std::size_t static_occupied = 0;   ///< S P(occ) > 0.5
    std::size_t static_free = 0;       ///< S P(occ) < free_threshold
    std::size_t dynamic_occupied = 0;  ///< D above object_threshold
  };
  CellCounts countCells() const;

  /// The integer cell values the model uses (exposed for tests and tools).
  struct Deltas {
    int s_hit_notfree, s_hit_free, s_miss, d_hit_free, d_hit_notfree, d_miss;
  };
  const Deltas& deltas() const { return deltas_; }
  cellType freeThresholdCell() const { return free_cell_; }
  cellType objectThresholdCell() const { return object_cell_; }

 private:
  static const std::array<float, 256> kCellProbability;      // by the value's bits as uint8
  static const std::array<std::uint8_t, 256> kCellGrey;

  bool internal_insertObservation(
      const mrpt::obs::CObservation& obs,
      const std::optional<const mrpt::poses::CPose3D>& robotPose = std::nullopt) override;
  void internal_clear() override;

  // The per-scan steps of insertScan, in order.
  bool insertScan(const RangeData& rd, const mrpt::poses::CPose3D& robot_pose);
  mrpt::poses::CPose2D computeBeams(const RangeData& rd, const mrpt::poses::CPose3D& robot_pose);
  /// False (nothing grown) when the scan would take the grid past max_map_size_m.
  bool growToFit(const mrpt::poses::CPose2D& sensor);
  void nextStamp();
  void applyHits();
  void sweepFreeArea(const mrpt::poses::CPose2D& sensor);
  void traceBeamTails(const mrpt::poses::CPose2D& sensor);
  void guardSurfaces();
  void planWedges();
  /// Re-aligns D and the scan stamps with S after any change of S's geometry.
  void syncLayers();
  bool hitInFreeSpace(std::size_t index) const;
  void applyHit(std::size_t index, bool in_free_space);
  /// A miss's update as arithmetic, clamp(cell + delta, lo, hi) (the value its table holds),
  /// and the scan's mark, each repeated over 16 lanes: loaded as they are by span()'s blocks.
  struct alignas(16) MissLanes {
    cellType mark[16], object_cell[16];
    cellType s_delta[16], s_lo[16], s_hi[16], d_delta[16], d_lo[16], d_hi[16];
  };
  /// The miss update with everything it needs in locals: cells are int8, which may alias any
  /// member, so a loop over members would reload them at every cell.
  struct MissKernel {
    cellType* s;
    cellType* d;
    std::uint8_t* stamp;
    const cellType* miss_s;
    const cellType* miss_d;
    std::uint8_t mark;
    cellType object_cell;
    std::vector<std::uint32_t>* changed;
    /// The tables as arithmetic for span()'s blocks of 16 cells; nullptr when a step does not
    /// fit a cell (then spans use the tables).
    const MissLanes* lanes;
    std::size_t cells;  // of each layer: a block of 16 must end within them
    /// Updates cell `i` as crossed, unless this scan already updated it: returns 1 if it did,
    /// else 0. Branch-free but for the rare change of state: along a beam, cells already
    /// updated (by the swept area, by a neighbouring beam) and new ones alternate unpredictably.
    inline std::uint32_t visit(std::size_t i) const {
      const bool fresh = stamp[i] != mark;
      stamp[i] = mark;
      const cellType s_before = s[i], d_before = d[i];
      const cellType s_miss = miss_s[static_cast<std::uint8_t>(s_before)];
      const cellType d_miss = miss_d[static_cast<std::uint8_t>(d_before)];
      s[i] = fresh ? s_miss : s_before;
      d[i] = fresh ? d_miss : d_before;
      // A miss only ever lowers D's P(occ): only an object cell can change state.
      if (fresh && d_before < object_cell && d_miss >= object_cell)
        changed->push_back(static_cast<std::uint32_t>(i));
      return fresh ? 1u : 0u;
    }
    /// visit() for cells [begin, end) of a row, and for the cells of traceRay from (x0, y0) to
    /// (x1, y1) in a grid `size_x` wide; both return how many cells they updated. The kernel is
    /// copied into locals first: cells are int8, which may alias anything whose address was
    /// taken, so fields read through a reference would be reloaded at every cell.
    std::uint32_t span(std::size_t begin, std::size_t end) const;
    std::uint32_t ray(int x0, int y0, int x1, int y1, std::size_t size_x) const;
  };
  MissKernel missKernel();
  void noteChange(std::size_t index, cellType before);

  DynamicMapOptions options_;
  InsertionOptions insertion_;
  Deltas deltas_{};
  cellType free_cell_ = 0;    // S cell >= this <=>  P(occ) < free_threshold
  cellType object_cell_ = 0;  // D cell < this  <=>  P(occ) > object_threshold
  cellType d_floor_ = 0;      // D stays within [d_floor_, d_ceiling_]: d_max and d_min
  cellType d_ceiling_ = 0;

  std::vector<cellType> dyn_;
  // The scan that last updated each cell, modulo 255 (one byte, so that the cells a scan
  // touches stay in the first-level cache): when the marks wrap round, the cells scans marked
  // since the last wrap are cleared, a box bounded by how far 255 scans reach, not the map.
  std::vector<std::uint8_t> stamp_;
  std::uint8_t scan_stamp_ = 0;
  struct CellBox {
    int x0 = 0, y0 = 0, x1 = -1, y1 = -1;  // inclusive; empty when x1 < x0
    void add(const CellBox& b);
  };
  CellBox scan_box_;     // the cells this scan may touch
  CellBox stamped_box_;  // the cells marked since the marks last started again
  // Geometry D and stamp_ were laid out for.
  float layer_x_min_ = 0, layer_y_min_ = 0;
  std::uint32_t layer_size_x_ = 0, layer_size_y_ = 0;

  std::vector<std::uint32_t> changed_;
  ScanInsertStats last_stats_;
  std::array<cellType, 256> miss_s_{}, miss_d_{};  // a miss's update, by the cell's bits
  MissLanes lanes_{};                              // the same as arithmetic, and the scan's mark
  bool simd_steps_ = false;                        // both steps fit a cell: lanes_ holds them
  bool hold_dynamic_ = false;                      // holdDynamic()

  // Per-scan scratch, kept to avoid reallocations.
  enum RayKind : std::uint8_t { kBeamNone = 0, kBeamFreeOnly = 1, kBeamHit = 2 };
  struct Beam {
    double cos = 1, sin = 0;  // direction in the map frame
    float reach = 0;          // [m] how far the beam reaches (0: not used)
    float stop = 0;           // [m] how far it frees space: reach less the surface guard
    float end_x = 0, end_y = 0;
    RayKind kind = kBeamNone;
    double covered = 0;  // [m] the swept wedges free this beam's line up to here
  };
  struct Wedge {
    std::size_t first, last;  // the beams bounding it
    double radius;            // [m] free up to here
  };
  static constexpr std::size_t kWedgeBeams = 8;  // beam gaps per wedge
  std::vector<Beam> beams_;
  RangeData range_;                                 // the scan of insertObservation(), worked out
  std::vector<std::pair<std::size_t, bool>> hits_;  // cell, S Free there before the scan
  std::vector<Wedge> wedges_;
  std::vector<GridPoint> polygon_;
  PolygonFillScratch fill_scratch_;
};

/// The int8 log-odds-of-free step for an observation of occupancy probability p (MRPT's scale).
int logOddsFreeStep(double p_occupied);

}  // namespace dynamap
