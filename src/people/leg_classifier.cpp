#include "dynamap/people/leg_classifier.h"

#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>
#include <zlib.h>

#include <cmath>
#include <fstream>
#include <stdexcept>

namespace dynamap {

// The forest's trees laid out flat once (OpenCV's predict copies each sample into a new matrix
// and walks its own structures per call: most of a scan's classification cost).
struct FlatNode {
  int var = -1;  // < 0: a leaf
  float threshold = 0;
  bool inversed = false;
  int left = -1, right = -1;
  bool leg = false;  // a leaf's vote
};

struct LegClassifier::Impl {
  cv::Ptr<cv::ml::RTrees> forest;
  std::vector<FlatNode> nodes;  // OpenCV's node order
  std::vector<int> roots;

  void flatten() {
    const auto& cv_nodes = forest->getNodes();
    const auto& splits = forest->getSplits();
    nodes.assign(cv_nodes.size(), {});
    for (std::size_t i = 0; i < cv_nodes.size(); ++i) {
      const cv::ml::DTrees::Node& n = cv_nodes[i];
      FlatNode& f = nodes[i];
      f.leg = n.value == 1;
      if (n.split < 0) continue;
      const cv::ml::DTrees::Split& sp = splits[static_cast<std::size_t>(n.split)];
      f.var = sp.varIdx;
      f.threshold = sp.c;
      f.inversed = sp.inversed;
      f.left = n.left;
      f.right = n.right;
    }
    roots = forest->getRoots();
  }
};

std::vector<LegSample> labelSegments(const ScanHits& hits,
                                     const std::vector<std::pair<double, double>>& legs,
                                     bool negative, double jump, double tolerance) {
  std::vector<LegSample> out;
  for (const Segment& s : segmentScan(hits, jump, kLegMinPoints)) {
    double mx = 0, my = 0;
    for (std::size_t i = s.begin; i < s.end; ++i) mx += hits.points[i].x, my += hits.points[i].y;
    mx /= static_cast<double>(s.size());
    my /= static_cast<double>(s.size());
    bool leg = false;
    for (const auto& [x, y] : legs) leg = leg || std::hypot(x - mx, y - my) <= tolerance;
    if (negative || leg) out.push_back({legFeatures(hits, s), leg && !negative});
  }
  return out;
}

LegClassifier::LegClassifier() : impl_(std::make_unique<Impl>()) {}
LegClassifier::~LegClassifier() = default;
LegClassifier::LegClassifier(LegClassifier&&) noexcept = default;
LegClassifier& LegClassifier::operator=(LegClassifier&&) noexcept = default;

namespace {

cv::Mat featureRows(const std::vector<LegFeatures>& rows) {
  cv::Mat m(static_cast<int>(rows.size()), static_cast<int>(kLegFeatureCount), CV_32F);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (std::size_t k = 0; k < kLegFeatureCount; ++k)
      m.at<float>(static_cast<int>(i), static_cast<int>(k)) = rows[i][k];
  }
  return m;
}

}  // namespace

namespace {

// The gzip-compressed model built into the library (cmake/leg_model.S.in).
extern "C" const unsigned char dynamap_leg_model_begin[];
extern "C" const unsigned char dynamap_leg_model_end[];

std::string gunzip(const unsigned char* data, std::size_t size) {
  z_stream z{};
  if (inflateInit2(&z, 16 + MAX_WBITS) != Z_OK) throw std::runtime_error("zlib failed to start");
  z.next_in = const_cast<unsigned char*>(data);
  z.avail_in = static_cast<uInt>(size);
  std::string out;
  char buf[1 << 16];
  int rc = Z_OK;
  while (rc == Z_OK) {
    z.next_out = reinterpret_cast<unsigned char*>(buf);
    z.avail_out = sizeof buf;
    rc = inflate(&z, Z_NO_FLUSH);
    out.append(buf, sizeof buf - z.avail_out);
  }
  inflateEnd(&z);
  if (rc != Z_STREAM_END) throw std::runtime_error("the built-in leg classifier is corrupt");
  return out;
}

}  // namespace

const LegClassifier& LegClassifier::builtin() {
  // Read once per process (a few tenths of a second), on first use: a run without people
  // tracking never pays for it.
  static const LegClassifier model = [] {
    const std::string text = gunzip(dynamap_leg_model_begin, static_cast<std::size_t>(
                                                                 dynamap_leg_model_end - dynamap_leg_model_begin));
    cv::FileStorage fs(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
    LegClassifier c;
    c.impl_->forest = cv::ml::RTrees::create();
    c.impl_->forest->read(fs.getFirstTopLevelNode());
    if (!c.impl_->forest->isTrained()) throw std::runtime_error("the built-in leg classifier is corrupt");
    c.impl_->flatten();
    return c;
  }();
  return model;
}

LegClassifier LegClassifier::load(const std::string& path) {
  LegClassifier c = loadForest(path);
  c.impl_->flatten();
  return c;
}

LegClassifier LegClassifier::loadForest(const std::string& path) {
  if (!std::ifstream(path).good()) throw std::runtime_error(path + ": cannot open the leg classifier");
  LegClassifier c;
  try {
    c.impl_->forest = cv::Algorithm::load<cv::ml::RTrees>(path);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(path + ": not a leg classifier (" + e.err + ")");
  }
  if (c.impl_->forest.empty() || !c.impl_->forest->isTrained())
    throw std::runtime_error(path + ": cannot read a leg classifier from it");
  if (c.impl_->forest->getVarCount() != static_cast<int>(kLegFeatureCount))
    throw std::runtime_error(path + ": the classifier takes " +
                             std::to_string(c.impl_->forest->getVarCount()) + " features, not " +
                             std::to_string(kLegFeatureCount));
  return c;
}

LegClassifier LegClassifier::train(const std::vector<LegSample>& samples,
                                   const LegForestParams& p) {
  std::size_t legs = 0;
  for (const LegSample& s : samples) legs += s.leg ? 1 : 0;
  if (legs == 0 || legs == samples.size())
    throw std::invalid_argument("training a leg classifier needs legs and other clusters");
  std::vector<LegFeatures> rows;
  cv::Mat labels(static_cast<int>(samples.size()), 1, CV_32S);
  cv::Mat weights(static_cast<int>(samples.size()), 1, CV_32F);
  const double n_leg = static_cast<double>(legs), n_other = static_cast<double>(samples.size() - legs);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    rows.push_back(samples[i].features);
    labels.at<int>(static_cast<int>(i)) = samples[i].leg ? 1 : 0;
    // Each class weighs the same in all: there are far more clusters of walls than of legs.
    weights.at<float>(static_cast<int>(i)) = static_cast<float>(samples[i].leg ? 1.0 / n_leg : 1.0 / n_other);
  }
  cv::Mat var_type(1, static_cast<int>(kLegFeatureCount) + 1, CV_8U, cv::Scalar(cv::ml::VAR_ORDERED));
  var_type.at<uchar>(static_cast<int>(kLegFeatureCount)) = cv::ml::VAR_CATEGORICAL;
  auto data = cv::ml::TrainData::create(featureRows(rows), cv::ml::ROW_SAMPLE, labels, cv::noArray(),
                                        cv::noArray(), weights, var_type);
  LegClassifier c;
  c.impl_->forest = cv::ml::RTrees::create();
  cv::ml::RTrees& f = *c.impl_->forest;
  f.setMaxDepth(p.max_depth);
  f.setMinSampleCount(p.min_samples);
  f.setActiveVarCount(p.active_features);
  f.setUseSurrogates(false);
  f.setCalculateVarImportance(false);
  f.setTermCriteria(cv::TermCriteria(cv::TermCriteria::MAX_ITER, p.trees, 0));
  if (!f.train(data)) throw std::runtime_error("the leg classifier did not train");
  c.impl_->flatten();
  return c;
}

void LegClassifier::save(const std::string& path) const {
  if (empty()) throw std::runtime_error(path + ": no trained classifier to write");
  try {
    impl_->forest->save(path);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(path + ": cannot write the leg classifier (" + e.err + ")");
  }
}

bool LegClassifier::empty() const { return impl_->forest.empty() || !impl_->forest->isTrained(); }

double LegClassifier::legProbability(const LegFeatures& x) const {
  if (impl_->roots.empty()) return 0.0;
  std::size_t legs = 0;
  for (const int root : impl_->roots) {
    const FlatNode* n = &impl_->nodes[static_cast<std::size_t>(root)];
    while (n->var >= 0) {
      // OpenCV's rule for an ordered variable: left when the value is at most the threshold.
      const bool left = (x[static_cast<std::size_t>(n->var)] <= n->threshold) != n->inversed;
      n = &impl_->nodes[static_cast<std::size_t>(left ? n->left : n->right)];
    }
    legs += n->leg ? 1 : 0;
  }
  return static_cast<double>(legs) / static_cast<double>(impl_->roots.size());
}

std::vector<double> LegClassifier::legProbability(const std::vector<LegFeatures>& rows) const {
  std::vector<double> out;
  out.reserve(rows.size());
  for (const LegFeatures& x : rows) out.push_back(legProbability(x));
  return out;
}

std::vector<double> LegClassifier::legProbabilityByOpenCv(const std::vector<LegFeatures>& rows) const {
  std::vector<double> out(rows.size(), 0.0);
  if (rows.empty() || empty()) return out;
  cv::Mat votes;
  impl_->forest->getVotes(featureRows(rows), votes, 0);
  // Row 0 holds the class labels; row i + 1 the votes of sample i per class.
  int leg_col = -1;
  for (int k = 0; k < votes.cols; ++k) {
    if (votes.at<int>(0, k) == 1) leg_col = k;
  }
  if (leg_col < 0) return out;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    double total = 0;
    for (int k = 0; k < votes.cols; ++k) total += votes.at<int>(static_cast<int>(i) + 1, k);
    out[i] = total > 0 ? votes.at<int>(static_cast<int>(i) + 1, leg_col) / total : 0.0;
  }
  return out;
}


}  // namespace dynamap
