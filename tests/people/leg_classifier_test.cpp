// The leg features, the forest that scores them and the built-in model: a leg is a leg, a wall
// and a wall's corner are not, a chair's thin leg never reaches the classifier.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <zlib.h>

#include "dynamap/people/leg_classifier.h"
#include "dynamap/people/leg_features.h"
#include "../test_util.h"

namespace dynamap {
namespace {

std::string gunzipFile(const std::string& path) {
  gzFile f = gzopen(path.c_str(), "rb");
  std::string out;
  char buf[4096];
  int n = 0;
  while (f != nullptr && (n = gzread(f, buf, sizeof buf)) > 0) out.append(buf, static_cast<std::size_t>(n));
  if (f != nullptr) gzclose(f);
  return out;
}

constexpr double kStep = 0.33 * M_PI / 180;  // the training data's beams
constexpr double kMax = 20.0;

/// Ranges of a scan of 181 beams (+-30 degrees) that sees `hit` (range or NaN for each beam
/// direction), nothing elsewhere.
template <typename F>
std::vector<float> rangesOf(F hit) {
  std::vector<float> r;
  for (int i = 0; i < 181; ++i) {
    const double d = hit(-90 * kStep + i * kStep);
    r.push_back(std::isnan(d) ? static_cast<float>(kMax) : static_cast<float>(d));
  }
  return r;
}

/// The near side of a disc of radius `radius` centred at (cx, cy), seen from the origin.
double discRange(double a, double cx, double cy, double radius) {
  const double b = cx * std::cos(a) + cy * std::sin(a), c = cx * cx + cy * cy - radius * radius;
  const double disc = b * b - c;
  return disc < 0 ? std::nan("") : b - std::sqrt(disc);
}

/// A straight wall x = `x` between y0 and y1.
double wallRange(double a, double x, double y0, double y1) {
  const double y = x * std::tan(a);
  return y >= y0 && y <= y1 ? x / std::cos(a) : std::nan("");
}

/// The straight side from (x0, y0) to (x1, y1).
double segmentRange(double a, double x0, double y0, double x1, double y1) {
  const double dx = std::cos(a), dy = std::sin(a), ex = x1 - x0, ey = y1 - y0;
  const double den = dx * ey - dy * ex;
  if (std::abs(den) < 1e-12) return std::nan("");
  const double t = (x0 * ey - y0 * ex) / den, u = (x0 * dy - y0 * dx) / den;
  return t > 0 && u >= 0 && u <= 1 ? t : std::nan("");
}

ScanHits hitsOf(const std::vector<float>& r) { return polarScanHits(-90 * kStep, kStep, r, 0.05, kMax); }

TEST(LegFeatures, SegmentsSplitAtJumpsAndShortRunsAreDropped) {
  // A disc at 1.5 m, a lone point, then a disc at 3 m: two segments.
  const auto r = rangesOf([](double a) {
    const double near = discRange(a, 1.5, -0.1, 0.06), far = discRange(a, 3.0, 0.1, 0.06);
    if (!std::isnan(near)) return near;
    if (std::abs(a - 0.02) < kStep / 2) return 2.0;
    return far;
  });
  const ScanHits h = hitsOf(r);
  const auto segs = segmentScan(h, kLegSegmentJump, kLegMinPoints);
  ASSERT_EQ(segs.size(), 2u);
  EXPECT_NEAR(h.points[segs[0].begin].x, 1.5, 0.1);
  EXPECT_NEAR(h.points[segs[1].begin].x, 3.0, 0.1);
}

TEST(LegFeatures, AnArcHasItsCirclesRadiusAndAWallIsStraight) {
  const ScanHits leg = hitsOf(rangesOf([](double a) { return discRange(a, 1.5, 0.0, 0.06); }));
  const auto s = segmentScan(leg, kLegSegmentJump, kLegMinPoints);
  ASSERT_EQ(s.size(), 1u);
  const LegFeatures f = legFeatures(leg, s[0]);
  EXPECT_NEAR(f[6], 0.06, 0.005);  // radius
  EXPECT_LT(f[5], 1e-6);           // circularity
  EXPECT_GT(f[3], 0.08);           // width: most of the near half of a 12 cm leg
  EXPECT_LT(f[3], 0.12);
  EXPECT_NEAR(f[13], 1.5, 0.06);   // distance
  EXPECT_LT(f[9], -5);             // curved, bulging towards the sensor

  const ScanHits wall = hitsOf(rangesOf([](double a) { return wallRange(a, 2.0, -0.15, 0.15); }));
  const auto w = segmentScan(wall, kLegSegmentJump, kLegMinPoints);
  ASSERT_EQ(w.size(), 1u);
  const LegFeatures g = legFeatures(wall, w[0]);
  EXPECT_LT(g[4], 1e-8);             // linearity
  EXPECT_FLOAT_EQ(g[6], 2.0f);       // no circle: the radius is capped
  EXPECT_NEAR(g[3], 0.3, 0.03);      // width
}

TEST(LegClassifier, TheBuiltInModelTakesALegForALegAndAWallOrItsCornerForNone) {
  const LegClassifier& c = LegClassifier::builtin();
  ASSERT_FALSE(c.empty());
  const auto score = [&](const ScanHits& h) {
    const auto s = segmentScan(h, kLegSegmentJump, kLegMinPoints);
    EXPECT_EQ(s.size(), 1u);
    return s.empty() ? -1.0 : c.legProbability(legFeatures(h, s[0]));
  };
  EXPECT_GE(score(hitsOf(rangesOf([](double a) { return discRange(a, 1.5, 0.0, 0.06); }))), 0.5);
  EXPECT_LT(score(hitsOf(rangesOf([](double a) { return wallRange(a, 2.0, -0.2, 0.2); }))), 0.5);
  // A box's corner pointing at the sensor: two straight sides meeting at a right angle.
  EXPECT_LT(score(hitsOf(rangesOf([](double a) {
              const double l = segmentRange(a, 1.8, 0.0, 2.0, -0.2), r = segmentRange(a, 1.8, 0.0, 2.0, 0.2);
              return std::isnan(l) ? r : l;
            }))),
            0.5);
  // A chair's leg, 2 cm thick at 3 m: fewer points than a cluster needs, never classified.
  const ScanHits chair = hitsOf(rangesOf([](double a) { return discRange(a, 3.0, 0.0, 0.01); }));
  EXPECT_TRUE(segmentScan(chair, kLegSegmentJump, kLegMinPoints).empty());
}

// 200 samples, half legs, told apart by their width alone (feature 3).
std::vector<LegSample> widthTellsThemApart() {
  std::vector<LegSample> samples;
  for (int i = 0; i < 200; ++i) {
    LegSample s;
    s.leg = i % 2 == 0;
    s.features.fill(static_cast<float>(i % 7));
    s.features[3] = s.leg ? 0.1f + 0.0001f * i : 0.5f + 0.0001f * i;
    samples.push_back(s);
  }
  return samples;
}

TEST(LegClassifier, AForestSurvivesSavingAndLoadingAndLearnsWhatItIsShown) {
  const std::vector<LegSample> samples = widthTellsThemApart();
  LegForestParams p;
  p.trees = 5;
  const LegClassifier c = LegClassifier::train(samples, p);
  const std::string path = test::tempDir("legs") + "/model.yml.gz";
  c.save(path);
  const LegClassifier back = LegClassifier::load(path);
  for (const LegSample& s : samples) {
    EXPECT_DOUBLE_EQ(back.legProbability(s.features), c.legProbability(s.features));
    EXPECT_EQ(back.legProbability(s.features) >= 0.5, s.leg);
  }
}

TEST(LegClassifier, TheBuiltInFlatTreesVoteAsOpenCvsOwnPredictionOfTheShippedModel) {
  // Features of discs, walls and corners at many ranges and sizes, and arbitrary ones around
  // them: every probability the same, to the vote.
  std::vector<LegFeatures> rows;
  for (double d = 0.5; d < 8; d += 0.25) {
    for (double r : {0.01, 0.04, 0.06, 0.1, 0.2}) {
      const ScanHits h = hitsOf(rangesOf([&](double a) {
        const double disc = discRange(a, d, 0.3, r);
        return std::isnan(disc) ? segmentRange(a, d + 1, -1.0, d + 1.3, 0.0) : disc;
      }));
      for (const Segment& s : segmentScan(h, kLegSegmentJump, kLegMinPoints)) {
        rows.push_back(legFeatures(h, s));
        LegFeatures odd = rows.back();
        for (std::size_t k = 0; k < odd.size(); ++k) odd[k] *= static_cast<float>(0.5 + 0.07 * k);
        rows.push_back(odd);
      }
    }
  }
  ASSERT_GT(rows.size(), 200u);
  // The built-in trees (config/legs.forest.gz) are those of config/legs.yml.gz: one regrown
  // without the other fails here.
  const LegClassifier shipped = LegClassifier::load(DYNAMAP_SOURCE_DIR "/config/legs.yml.gz");
  const std::vector<double> flat = LegClassifier::builtin().legProbability(rows),
                            cv = shipped.legProbabilityByOpenCv(rows);
  std::size_t legs = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_DOUBLE_EQ(flat[i], cv[i]) << "row " << i;
    for (double t : {0.0, 0.1, 0.5, 0.52, 0.9, 1.0})  // the trees it stops asking cannot change it
      EXPECT_EQ(LegClassifier::builtin().isLeg(rows[i], t), flat[i] >= t) << "row " << i << " at " << t;
    legs += flat[i] >= 0.5;
  }
  EXPECT_GT(legs, 0u);  // both answers are found among the rows
  EXPECT_LT(legs, rows.size());
}

TEST(LegClassifier, FlatTreesSurviveWritingAndReadingAndBadOnesAreRefusedByName) {
  const std::vector<LegSample> samples = widthTellsThemApart();
  LegForestParams p;
  p.trees = 3;
  const LegClassifier c = LegClassifier::train(samples, p);
  const std::string path = test::tempDir("legs_flat") + "/model.forest.gz";
  c.saveFlat(path);
  const std::string bytes = gunzipFile(path);
  const LegClassifier back = LegClassifier::fromFlat(bytes, "model");
  for (const LegSample& s : samples)
    EXPECT_DOUBLE_EQ(back.legProbability(s.features), c.legProbability(s.features));
  const auto refused = [](const std::string& b, const char* why) {
    try {
      LegClassifier::fromFlat(b, "model.forest");
      ADD_FAILURE() << "read: " << why;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("model.forest"), std::string::npos) << e.what();
    }
  };
  refused(bytes.substr(0, bytes.size() - 1), "cut short");
  refused("not a forest", "no magic");
  std::string loop = bytes;
  // The first node's left child made itself (a split node: the root of a trained tree).
  const std::size_t magic = 21, header = magic + 12, first = header + 4 * 3;
  std::memset(&loop[first + 10], 0, 4);
  refused(loop, "a child before its parent");
  std::string features = bytes;
  features[magic] = 16;
  refused(features, "16 features");
}

TEST(LegClassifier, ErrorsNameTheFileAndTheProblem) {
  const std::string dir = test::tempDir("legs_bad");
  std::ofstream(dir + "/junk.yml") << "%YAML:1.0\nnothing: 1\n";
  try {
    LegClassifier::load(dir + "/junk.yml");
    FAIL() << "a file without a forest was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("junk.yml"), std::string::npos) << e.what();
  }
  EXPECT_THROW(LegClassifier::load(dir + "/missing.yml"), std::runtime_error);
  std::vector<LegSample> one_class(10);
  EXPECT_THROW(LegClassifier::train(one_class, {}), std::invalid_argument);
}

TEST(LegClassifier, LabelsASegmentNearAMarkedLegAndLeavesOthersOut) {
  const ScanHits h = hitsOf(rangesOf([](double a) {
    const double leg = discRange(a, 1.5, -0.2, 0.06);
    return std::isnan(leg) ? wallRange(a, 3.0, 0.0, 0.4) : leg;
  }));
  const auto segs = segmentScan(h, kLegSegmentJump, kLegMinPoints);
  ASSERT_EQ(segs.size(), 2u);
  double mx = 0, my = 0;
  for (std::size_t i = segs[0].begin; i < segs[0].end; ++i) mx += h.points[i].x, my += h.points[i].y;
  mx /= static_cast<double>(segs[0].size());
  my /= static_cast<double>(segs[0].size());
  const auto marked = labelSegments(h, {{mx, my}}, false, kLegSegmentJump, 0.05);
  ASSERT_EQ(marked.size(), 1u);  // the wall, marked by nobody, is left out
  EXPECT_TRUE(marked[0].leg);
  const auto negative = labelSegments(h, {}, true, kLegSegmentJump, 0.05);
  ASSERT_EQ(negative.size(), 2u);
  EXPECT_FALSE(negative[0].leg || negative[1].leg);
}

}  // namespace
}  // namespace dynamap
