#include "dynamap/people/leg_classifier.h"

#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>
#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <cstring>
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

// The flat layout: kFlatMagic, then little-endian u32 features, trees and nodes, each tree's
// root (i32), and each node as i32 var, f32 threshold, u8 inversed, u8 leg, i32 left, i32 right.
constexpr char kFlatMagic[] = "dynamap leg forest 1\n";
constexpr std::size_t kFlatNodeBytes = 4 + 4 + 1 + 1 + 4 + 4;
constexpr std::uint32_t kMaxFlatNodes = 1u << 24;

template <typename T>
void put(std::string& out, T v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

template <typename T>
T take(const std::string& in, std::size_t& at) {
  T v{};
  std::memcpy(&v, in.data() + at, sizeof v);
  at += sizeof v;
  return v;
}

std::string flatBytes(const std::vector<FlatNode>& nodes, const std::vector<int>& roots) {
  std::string out(kFlatMagic);
  put<std::uint32_t>(out, static_cast<std::uint32_t>(kLegFeatureCount));
  put<std::uint32_t>(out, static_cast<std::uint32_t>(roots.size()));
  put<std::uint32_t>(out, static_cast<std::uint32_t>(nodes.size()));
  for (const int r : roots) put<std::int32_t>(out, r);
  for (const FlatNode& n : nodes) {
    put<std::int32_t>(out, n.var);
    put<float>(out, n.threshold);
    put<std::uint8_t>(out, n.inversed ? 1 : 0);
    put<std::uint8_t>(out, n.leg ? 1 : 0);
    put<std::int32_t>(out, n.left);
    put<std::int32_t>(out, n.right);
  }
  return out;
}

// Every index checked before it is followed, and every child after its parent: a walk from a
// root ends at a leaf within the node count whatever the bytes say.
void readFlat(const std::string& in, const std::string& name, std::vector<FlatNode>& nodes,
              std::vector<int>& roots) {
  const std::size_t magic = sizeof kFlatMagic - 1;
  const auto bad = [&](const std::string& why) { return std::runtime_error(name + ": " + why); };
  if (in.size() < magic + 12 || in.compare(0, magic, kFlatMagic) != 0) throw bad("not a flat leg forest");
  std::size_t at = magic;
  const auto features = take<std::uint32_t>(in, at), trees = take<std::uint32_t>(in, at),
             count = take<std::uint32_t>(in, at);
  if (features != kLegFeatureCount) throw bad("a forest of another number of features");
  if (trees == 0 || count == 0 || count > kMaxFlatNodes || trees > count) throw bad("no forest in it");
  if (in.size() != at + 4 * std::size_t{trees} + kFlatNodeBytes * count) throw bad("cut short or too long");
  roots.resize(trees);
  for (int& r : roots) {
    r = take<std::int32_t>(in, at);
    if (r < 0 || static_cast<std::uint32_t>(r) >= count) throw bad("a tree's root out of range");
  }
  nodes.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    FlatNode& n = nodes[i];
    n.var = take<std::int32_t>(in, at);
    n.threshold = take<float>(in, at);
    n.inversed = take<std::uint8_t>(in, at) != 0;
    n.leg = take<std::uint8_t>(in, at) != 0;
    n.left = take<std::int32_t>(in, at);
    n.right = take<std::int32_t>(in, at);
    if (n.var < 0) continue;
    const auto after = [&](int c) { return c > static_cast<int>(i) && static_cast<std::uint32_t>(c) < count; };
    if (n.var >= static_cast<int>(features) || !after(n.left) || !after(n.right))
      throw bad("node " + std::to_string(i) + " points outside the forest");
  }
}

}  // namespace

const LegClassifier& LegClassifier::builtin() {
  // Read once per process, on first use: a run without people tracking never pays for it. The
  // trees are built in laid out flat (config/legs.forest): parsing OpenCV's YAML for the same
  // trees cost a tenth of a whole run of Freiburg 079.
  static const LegClassifier model = [] {
    const std::string flat = gunzip(dynamap_leg_model_begin, static_cast<std::size_t>(
                                                                 dynamap_leg_model_end - dynamap_leg_model_begin));
    return fromFlat(flat, "the built-in leg classifier");
  }();
  return model;
}

LegClassifier LegClassifier::fromFlat(const std::string& bytes, const std::string& name) {
  LegClassifier c;
  readFlat(bytes, name, c.impl_->nodes, c.impl_->roots);
  return c;
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
  if (impl_->forest.empty() || !impl_->forest->isTrained()) throw std::runtime_error(path + ": no trained classifier to write");
  try {
    impl_->forest->save(path);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(path + ": cannot write the leg classifier (" + e.err + ")");
  }
}

void LegClassifier::saveFlat(const std::string& path) const {
  if (empty()) throw std::runtime_error(path + ": no trained classifier to write");
  const std::string bytes = flatBytes(impl_->nodes, impl_->roots);
  gzFile f = gzopen(path.c_str(), "wb9");
  const bool ok = f != nullptr &&
                  gzwrite(f, bytes.data(), static_cast<unsigned>(bytes.size())) == static_cast<int>(bytes.size());
  if (f == nullptr || gzclose(f) != Z_OK || !ok)
    throw std::runtime_error(path + ": cannot write the flat leg forest");
}

bool LegClassifier::empty() const { return impl_->roots.empty(); }

namespace {

// Tree `root`'s vote for x.
bool treeVote(const std::vector<FlatNode>& nodes, int root, const LegFeatures& x) {
  const FlatNode* n = &nodes[static_cast<std::size_t>(root)];
  while (n->var >= 0) {
    // OpenCV's rule for an ordered variable: left when the value is at most the threshold.
    const bool left = (x[static_cast<std::size_t>(n->var)] <= n->threshold) != n->inversed;
    n = &nodes[static_cast<std::size_t>(left ? n->left : n->right)];
  }
  return n->leg;
}

}  // namespace

double LegClassifier::legProbability(const LegFeatures& x) const {
  if (impl_->roots.empty()) return 0.0;
  std::size_t legs = 0;
  for (const int root : impl_->roots) legs += treeVote(impl_->nodes, root, x) ? 1 : 0;
  return static_cast<double>(legs) / static_cast<double>(impl_->roots.size());
}

bool LegClassifier::isLeg(const LegFeatures& x, double threshold) const {
  const std::size_t trees = impl_->roots.size();
  if (trees == 0) return false;
  const double all = static_cast<double>(trees);
  std::size_t legs = 0;
  // Stops once the trees left cannot change the answer: most clusters are walls, settled
  // by about half of the trees. The same comparison as legProbability(x) >= threshold.
  for (std::size_t t = 0; t < trees; ++t) {
    legs += treeVote(impl_->nodes, impl_->roots[t], x) ? 1 : 0;
    if (static_cast<double>(legs) / all >= threshold) return true;
    if (static_cast<double>(legs + trees - 1 - t) / all < threshold) return false;
  }
  return static_cast<double>(legs) / all >= threshold;
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
