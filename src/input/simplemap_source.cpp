#include "dynamap/input/simplemap_source.h"

#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CSensoryFrame.h>

#include "dynamap/base/allocation_limit.h"
#include "dynamap/input/mrpt_records.h"

namespace dynamap {
namespace {

using mrpt::obs::CObservation2DRangeScan;

class SimplemapSource : public ScanSource {
 public:
  explicit SimplemapSource(const std::string& path) : path_(path) {
    bool loaded = false;
    try {
      const AllocationLimit limit;
      loaded = map_.loadFromFile(path);
    } catch (const std::exception& e) {
      throw InputError(path + ": cannot read simplemap: " + std::string(e.what()).substr(0, 200));
    }
    if (!loaded) throw InputError(path + ": cannot read simplemap");
    stats_.records = map_.size();
    it_ = map_.begin();
  }

  bool next(ScanRecord& out) override {
    while (it_ != map_.end()) {
      if (obs_index_ < it_->sf->size()) {
        auto o = it_->sf->getObservationByIndex(obs_index_++);
        auto scan = std::dynamic_pointer_cast<CObservation2DRangeScan>(o);
        if (!scan) continue;
        normalizeFlags(*scan);
        out.index = stats_.scans++;
        out.t = scan->timestamp == INVALID_TIMESTAMP ? 0.0 : toSeconds(scan->timestamp);
        out.pose = mrpt::poses::CPose2D(it_->pose->getMeanVal());
        out.scan = scan;
        return true;
      }
      ++it_;
      obs_index_ = 0;
    }
    return false;
  }

  PoseSource poseSource() const override { return PoseSource::Simplemap; }
  double fractionRead() const override {
    return map_.size() ? static_cast<double>(it_ - map_.begin()) / map_.size() : 1.0;
  }
  const SourceStats& stats() const override { return stats_; }
  const std::string& path() const override { return path_; }

 private:
  std::string path_;
  mrpt::maps::CSimpleMap map_;
  mrpt::maps::CSimpleMap::const_iterator it_;
  std::size_t obs_index_ = 0;
  SourceStats stats_;
};

}  // namespace

std::unique_ptr<ScanSource> openSimplemapSource(const std::string& path) {
  return std::make_unique<SimplemapSource>(path);
}

}  // namespace dynamap
