#include "dynamap/localization/submap.h"

namespace dynamap {

Submap::Submap(std::size_t anchor, const DynamicMapOptions& map, const InsertionOptions& insertion)
    : anchor_(anchor),
      last_node_(anchor),
      // The grid grows to fit each scan inserted.
      grid_(std::make_unique<DynamicGridMap>(map, insertion, -2.f, 2.f, -2.f, 2.f)) {}

void Submap::insert(const RangeData& rd, const mrpt::poses::CPose2D& local_pose) {
  if (!grid_) return;
  grid_->insertRange(rd, local_pose);
  ++scans_;
}

void Submap::finish(double occupied_threshold, double sigma_m) {
  if (!grid_) return;
  // The base grid of a DynamicGridMap is S.
  field_ = LikelihoodField::fromGrid(*grid_, occupied_threshold, sigma_m);
  grid_.reset();
}

}  // namespace dynamap
