// dynamap train-legs: grows the leg classifier the people detector uses, from ROS bags of real
// laser data (leg_tracker's training bags: scans with their leg clusters marked, and scans of
// rooms with nobody in them), and scores it on bags kept aside for validation.

#include <cstdio>
#include <fstream>
#include <iostream>

#include "cli.h"
#include "commands.h"
#ifdef DYNAMAP_HAVE_ROSBAG
#include "dynamap/input/bag_annotations.h"
#endif
#include "dynamap/people/leg_classifier.h"

namespace dynamap::app {

#ifdef DYNAMAP_HAVE_ROSBAG
namespace {

const char* const kTrainLegsUsage =
    "usage: dynamap train-legs --positive BAG[:TOPIC]... --negative BAG[:TOPIC]... --out MODEL [--flat FOREST]\n"
    "                          [--validate-positive BAG[:TOPIC]...] [--validate-negative ...]\n\n"
    "Each --positive bag holds LaserScans (TOPIC, default /training_scan) and, recorded just\n"
    "before each, a geometry_msgs/PoseArray of its leg clusters (--positions-topic); each\n"
    "--negative bag holds scans with no person (TOPIC, default /scan). Every scan is also used\n"
    "with every k-th beam only, for each k of --subsample, so that the model knows coarser lasers\n"
    "than the one of the training data. Writes MODEL (.yml.gz) and prints the validation scores.\n"
    "The same bags give the same model.";

constexpr double kTolerance = 0.05;  // [m] a cluster this near a marked leg is that leg

struct BagSpec {
  std::string path, topic;
};

BagSpec parseSpec(const std::string& spec, const std::string& default_topic) {
  const auto colon = spec.rfind(":/");
  if (colon == std::string::npos) return {spec, default_topic};
  return {spec.substr(0, colon), spec.substr(colon + 1)};
}

// Every k-th beam of `s`, as a laser k times coarser would have seen the scene.
ScanHits subsampled(const PolarScan& s, std::size_t k) {
  std::vector<float> ranges;
  for (std::size_t i = 0; i < s.ranges.size(); i += k) ranges.push_back(s.ranges[i]);
  return polarScanHits(s.angle_min, s.angle_increment * static_cast<double>(k), ranges,
                       s.range_min, s.range_max);
}

void addSamples(const std::vector<std::string>& specs, bool negative, const std::string& positions,
                const std::vector<std::size_t>& factors, std::vector<LegSample>& out) {
  for (const std::string& spec : specs) {
    const BagSpec b = parseSpec(spec, negative ? "/scan" : "/training_scan");
    const std::size_t before = out.size();
    const auto scans = readLegTrainingBag(b.path, b.topic, negative ? "" : positions);
    for (const LegTrainingScan& s : scans) {
      std::vector<std::pair<double, double>> legs;
      for (const LaserPoint& p : s.legs) legs.emplace_back(p.x, p.y);
      for (std::size_t k : factors) {
        for (LegSample& x : labelSegments(subsampled(s.scan, k), legs, negative, kLegSegmentJump, kTolerance))
          out.push_back(x);
      }
    }
    std::cout << "  " << b.path << " " << b.topic << ": " << scans.size() << " scans, "
              << out.size() - before << (negative ? " other" : " leg") << " clusters\n";
  }
}

void writeSamples(const std::string& path, const std::vector<LegSample>& train,
                  const std::vector<LegSample>& validate) {
  std::ofstream o(path);
  o << "set,leg";
  for (const char* name : legFeatureNames()) o << ',' << name;
  o << '\n';
  for (const auto* set : {&train, &validate}) {
    for (const LegSample& s : *set) {
      o << (set == &train ? "train" : "validate") << ',' << (s.leg ? 1 : 0);
      for (float f : s.features) o << ',' << f;
      o << '\n';
    }
  }
  if (!o) throw std::runtime_error(path + ": cannot write the samples");
}

void report(const LegClassifier& c, const std::vector<LegSample>& samples, const char* what) {
  std::vector<LegFeatures> rows;
  for (const LegSample& s : samples) rows.push_back(s.features);
  const std::vector<double> p = c.legProbability(rows);
  std::size_t tp = 0, fp = 0, fn = 0, tn = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const bool said = p[i] >= 0.5;
    (samples[i].leg ? (said ? tp : fn) : (said ? fp : tn)) += 1;
  }
  const auto ratio = [](std::size_t a, std::size_t b) { return b ? double(a) / double(b) : 0.0; };
  std::printf("%s: %zu legs, %zu others: precision %.3f, recall %.3f, false-positive rate %.4f\n",
              what, tp + fn, fp + tn, ratio(tp, tp + fp), ratio(tp, tp + fn), ratio(fp, fp + tn));
}

}  // namespace

int runTrainLegs(const Args& args) {
  po::options_description opts("options");
  using Specs = std::vector<std::string>;
  opts.add_options()("help,h", "explain the options")(
      "positive", po::value<Specs>()->required(), "a bag of marked leg clusters (repeatable)")(
      "negative", po::value<Specs>()->required(), "a bag of scans without people (repeatable)")(
      "validate-positive", po::value<Specs>()->default_value({}, ""), "kept aside for scoring")(
      "validate-negative", po::value<Specs>()->default_value({}, ""), "kept aside for scoring")(
      "positions-topic", po::value<std::string>()->default_value("/leg_cluster_positions"),
      "the PoseArray topic of the marked legs")(
      "subsample", po::value<std::vector<std::size_t>>()->multitoken()->default_value({1, 2, 3}, "1 2 3"),
      "beam subsampling factors, each at least 1")(
      "trees", po::value<int>()->default_value(LegForestParams{}.trees), "trees of the forest")(
      "depth", po::value<int>()->default_value(LegForestParams{}.max_depth), "their depth")(
      "out,o", po::value<std::string>()->required(), "the model file to write (.yml.gz)")(
      "flat", po::value<std::string>(), "also write its trees laid out flat (what dynamap builds in)")(
      "samples", po::value<std::string>(), "also write every sample's features to this CSV");
  po::variables_map vm;
  if (!parseArgs(args, opts, {}, vm, kTrainLegsUsage)) return kExitOk;
  const auto factors = vm["subsample"].as<std::vector<std::size_t>>();
  for (std::size_t k : factors) {
    if (k < 1 || k > 10) throw UsageError("--subsample: each factor must be in [1, 10]");
  }
  LegForestParams params;
  params.trees = vm["trees"].as<int>();
  params.max_depth = vm["depth"].as<int>();
  if (params.trees < 1 || params.trees > 1000) throw UsageError("--trees: must be in [1, 1000]");
  if (params.max_depth < 1 || params.max_depth > 64) throw UsageError("--depth: must be in [1, 64]");
  const std::string positions = vm["positions-topic"].as<std::string>();
  std::vector<LegSample> train, validate;
  std::cout << "training data\n";
  addSamples(vm["positive"].as<Specs>(), false, positions, factors, train);
  addSamples(vm["negative"].as<Specs>(), true, positions, factors, train);
  std::cout << "validation data\n";
  addSamples(vm["validate-positive"].as<Specs>(), false, positions, factors, validate);
  addSamples(vm["validate-negative"].as<Specs>(), true, positions, factors, validate);
  if (vm.count("samples")) writeSamples(vm["samples"].as<std::string>(), train, validate);
  const LegClassifier model = LegClassifier::train(train, params);
  model.save(vm["out"].as<std::string>());
  if (vm.count("flat")) model.saveFlat(vm["flat"].as<std::string>());
  report(model, train, "training");
  if (!validate.empty()) report(model, validate, "validation");
  return kExitOk;
}

#else
int runTrainLegs(const Args&) {
  throw std::runtime_error("this dynamap was built without ROS bag support (DYNAMAP_ROSBAG=OFF)");
}
#endif

}  // namespace dynamap::app
