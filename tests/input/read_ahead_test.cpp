// ReadAheadSource: the inner source's scans in order, then its end or its error, whatever the
// depth; stopping early neither hangs nor loses the inner source's counts.

#include "dynamap/input/read_ahead.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>

namespace dynamap {
namespace {

// `scans` scans numbered from 0, then the end or (with `fail`) an InputError naming the next one.
class CountingSource : public ScanSource {
 public:
  CountingSource(std::size_t scans, bool fail) : scans_(scans), fail_(fail) {}
  bool next(ScanRecord& out) override {
    if (read_ == scans_) {
      if (fail_) throw InputError("counting.log: record " + std::to_string(read_) + " is bad");
      return false;
    }
    out = {};
    out.index = read_;
    out.t = 0.2 * static_cast<double>(read_);
    out.pose = mrpt::poses::CPose2D(static_cast<double>(read_), 0, 0);
    out.scan = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
    ++read_;
    stats_.scans = stats_.records = read_;
    return true;
  }
  PoseSource poseSource() const override { return PoseSource::Odometry; }
  const SourceStats& stats() const override { return stats_; }
  const std::string& path() const override { return path_; }
  double fractionRead() const override {
    return static_cast<double>(read_) / static_cast<double>(scans_);
  }

 private:
  std::size_t scans_, read_ = 0;
  bool fail_;
  SourceStats stats_;
  std::string path_ = "counting.log";
};

TEST(ReadAhead, GivesTheInnerScansInOrderThenTheEnd) {
  for (const std::size_t depth : {1u, 2u, 3u, 64u}) {
    ReadAheadSource src(std::make_unique<CountingSource>(200, false), depth);
    EXPECT_EQ(src.poseSource(), PoseSource::Odometry);
    EXPECT_EQ(src.path(), "counting.log");
    ScanRecord rec;
    for (std::size_t i = 0; i < 200; ++i) {
      ASSERT_TRUE(src.next(rec)) << "depth " << depth << ", scan " << i;
      EXPECT_EQ(rec.index, i);
      EXPECT_DOUBLE_EQ(rec.pose.x(), static_cast<double>(i));
      EXPECT_DOUBLE_EQ(src.fractionRead(), static_cast<double>(i + 1) / 200.0);
    }
    EXPECT_FALSE(src.next(rec));
    EXPECT_FALSE(src.next(rec));
    EXPECT_EQ(src.stats().scans, 200u);
  }
}

TEST(ReadAhead, ThrowsTheInnerErrorAfterEveryScanBeforeIt) {
  ReadAheadSource src(std::make_unique<CountingSource>(5, true), 2);
  ScanRecord rec;
  for (std::size_t i = 0; i < 5; ++i) {
    ASSERT_TRUE(src.next(rec));
    EXPECT_EQ(rec.index, i);
  }
  try {
    src.next(rec);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "counting.log: record 5 is bad");
  }
  EXPECT_EQ(src.stats().scans, 5u);
}

TEST(ReadAhead, StopsEarlyWithoutHanging) {
  // A long source left after three scans, its reader blocked on a full queue.
  auto src = std::make_unique<ReadAheadSource>(std::make_unique<CountingSource>(100000, false), 4);
  ScanRecord rec;
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(src->next(rec));
  // Its counts stop where the reader stopped: at most the queue beyond what was taken.
  const std::size_t read = src->stats().scans;
  EXPECT_GE(read, 3u);
  EXPECT_LE(read, 3u + 4u + 1u);
  // Asked again, it gives what was queued, in order, then the end: it never waits for a reader
  // that has stopped.
  std::size_t taken = 3;
  while (src->next(rec)) EXPECT_EQ(rec.index, taken++);
  EXPECT_LE(taken, read);
  src.reset();  // the destructor returns: the test would time out otherwise
}

}  // namespace
}  // namespace dynamap
