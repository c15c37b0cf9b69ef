#pragma once
// A random forest (OpenCV's ml module) that tells a leg's cluster from everything else by its
// shape (leg_features.h). dynamap ships one trained on real laser data of walking people
// (config/legs.yml.gz, made by `dynamap train-legs`); a user can train their own.

#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "dynamap/people/leg_features.h"

namespace dynamap {

/// How a forest is grown (dynamap train-legs). Defaults keep the model file small. OpenCV seeds
/// the forest's random generator itself: the same samples give the same forest.
struct LegForestParams {
  int trees = 60;            ///< how many trees
  int max_depth = 12;        ///< the deepest a tree grows
  int min_samples = 2;       ///< a node with fewer samples is not split
  int active_features = 4;   ///< features tried at each split (about sqrt of the count)
};

/// One labelled cluster.
struct LegSample {
  LegFeatures features{};
  bool leg = false;
};

/// The samples of one training scan: each segment (segmentScan with `jump`, at least 3 points)
/// whose mean point lies within `tolerance` of one of `legs` is a leg; with `negative`, every
/// segment is not one (a scan of a room without people); otherwise a segment near no leg is left
/// out (a person's bag also sees walls nobody marked).
std::vector<LegSample> labelSegments(const ScanHits& hits, const std::vector<std::pair<double, double>>& legs,
                                     bool negative, double jump, double tolerance);

class LegClassifier {
 public:
  LegClassifier();
  ~LegClassifier();
  LegClassifier(LegClassifier&&) noexcept;
  LegClassifier& operator=(LegClassifier&&) noexcept;

  /// The model dynamap ships (config/legs.yml.gz, trained by `make legs`), built in as its
  /// trees laid out flat (config/legs.forest, written beside it), read on first use. It has
  /// no OpenCV forest: legProbabilityByOpenCv answers 0 and save() throws; saveFlat() works.
  static const LegClassifier& builtin();
  /// The trees of saveFlat()'s file, uncompressed, as `bytes`. Throws std::runtime_error naming
  /// `name` when they are cut short, take another number of features or point outside the
  /// forest (every walk from a root ends at a leaf).
  static LegClassifier fromFlat(const std::string& bytes, const std::string& name);
  /// Reads a model written by save() (.yml, .yml.gz, .xml). Throws std::runtime_error naming
  /// the file when it cannot be read, is no forest, or takes another number of features.
  static LegClassifier load(const std::string& path);
  /// Grows a forest on `samples` (both classes needed; std::invalid_argument otherwise), the
  /// two classes weighed equally whatever their counts.
  static LegClassifier train(const std::vector<LegSample>& samples, const LegForestParams& params);
  /// Writes the model (gzip-compressed when `path` ends in .gz). Throws naming the file.
  void save(const std::string& path) const;

  /// Writes the trees laid out flat, gzip-compressed: what dynamap builds in. Throws naming the
  /// file.
  void saveFlat(const std::string& path) const;

  bool empty() const;
  /// The share of the trees that vote "leg" for each row of `features`, in [0, 1], from the
  /// trees laid out flat once (no allocation per call).
  std::vector<double> legProbability(const std::vector<LegFeatures>& features) const;
  double legProbability(const LegFeatures& features) const;
  /// legProbability(features) >= threshold, with only as many trees asked as it takes.
  bool isLeg(const LegFeatures& features, double threshold) const;
  /// The same through OpenCV's own prediction (slower): the flat trees must agree with it.
  std::vector<double> legProbabilityByOpenCv(const std::vector<LegFeatures>& features) const;

 private:
  static LegClassifier loadForest(const std::string& path);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dynamap
