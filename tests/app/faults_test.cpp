// Bad input end to end: `dynamap map` on logs, scans, poses and configurations that are broken on
// purpose (made here, from the bundled tiny rawlog or from synthetic steps). Each test asserts the
// exit status, the message naming the record and byte (or the scan, or the key) and that the
// outputs of the good part exist and are right. The fuzzers' regression inputs:
// fuzz_regressions_test.cpp.

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileInputStream.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/serialization/CArchive.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>

#include "../test_util.h"
#include "dynamap/mapping/dynamic_grid_map.h"
#include "dynamap/pipeline/mapper.h"

namespace dynamap {
namespace {

namespace fs = std::filesystem;
using mrpt::poses::CPose2D;

const std::string kExe = DYNAMAP_EXE;
const std::string kSrc = DYNAMAP_SOURCE_DIR;
const std::string kTiny = kSrc + "/rawlogs/tiny/tiny.rawlog";

int map(const std::string& args, std::string* out = nullptr) {
  return test::run(kExe + " map --no-baseline " + args, out);
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

// The tiny rawlog, uncompressed (cuts and flips are then at known byte offsets).
std::string plainTiny(const std::string& dir) {
  const std::string path = dir + "/tiny-plain.rawlog";
  if (!fs::exists(path)) {
    EXPECT_EQ(test::run("gzip -dc " + kTiny + " > " + path), 0);
  }
  return test::readFile(path);
}

// The byte offset where each top-level record of a plain rawlog starts, and its end.
std::vector<std::uint64_t> recordStarts(const std::string& path) {
  mrpt::io::CFileInputStream in(path);
  std::vector<std::uint64_t> starts;
  const std::uint64_t size = fs::file_size(path);
  while (in.getPosition() < size) {
    starts.push_back(in.getPosition());
    mrpt::serialization::archiveFrom(in).ReadObject();
  }
  starts.push_back(size);
  return starts;
}

// A number of summary.json, by its (unique enough) key.
long summaryNumber(const std::string& summary, const std::string& key) {
  const auto pos = summary.find("\"" + key + "\": ");
  if (pos == std::string::npos) return -1;
  return std::stol(summary.substr(pos + key.size() + 4));
}

// The outputs that depend only on the scans mapped: equal when the same scans were mapped.
void expectSameMapOutputs(const std::string& a, const std::string& b) {
  for (const char* f : {"static.gridmap.gz", "dynamic.gridmap.gz", "static.png", "dynamic.png",
                        "overlay.png", "objects.csv", "events.csv", "tracks.csv", "static.pgm"}) {
    ASSERT_TRUE(fs::exists(a + "/" + f)) << a << "/" << f;
    EXPECT_EQ(test::readFile(a + "/" + f), test::readFile(b + "/" + f)) << f;
  }
}

// Maps a damaged copy of tiny whose fault is at record `k`, and its clean prefix (the records
// before k): the damaged run exits 4 naming record and byte, the clean one 0, same maps.
void expectPartialEqualsPrefix(const std::string& dir, const std::string& name,
                               const std::string& damaged, const std::string& plain,
                               const std::vector<std::uint64_t>& starts, std::size_t k,
                               const std::string& what) {
  SCOPED_TRACE(name);
  writeBytes(dir + "/" + name + ".rawlog", damaged);
  writeBytes(dir + "/" + name + "-prefix.rawlog", plain.substr(0, starts[k]));
  std::string out;
  ASSERT_EQ(map("--input " + dir + "/" + name + ".rawlog --out " + dir + "/" + name, &out), 4)
      << out;
  EXPECT_NE(out.find("dynamap map: warning: input ended in a fault, outputs cover the scans "
                     "before it: " +
                     dir + "/" + name + ".rawlog: record " + std::to_string(k) + " at byte " +
                     std::to_string(starts[k]) + " " + what),
            std::string::npos)
      << out;
  const std::string summary = test::readFile(dir + "/" + name + "/summary.json");
  EXPECT_NE(summary.find("\"complete_input\": false"), std::string::npos) << summary;
  EXPECT_EQ(summaryNumber(summary, "records_read"), static_cast<long>(k)) << summary;
  // The clean prefix maps to the same; it may end with a scan whose pose record was cut away,
  // which it names (the damaged log's fault takes precedence over that).
  std::string clean_out;
  const int clean_status =
      map("--input " + dir + "/" + name + "-prefix.rawlog --out " + dir + "/" + name + "-prefix",
          &clean_out);
  if (clean_status != 0) {
    EXPECT_EQ(clean_status, 4) << clean_out;
    EXPECT_NE(clean_out.find("has no ground_truth pose"), std::string::npos) << clean_out;
  }
  expectSameMapOutputs(dir + "/" + name, dir + "/" + name + "-prefix");
  const std::string clean = test::readFile(dir + "/" + name + "-prefix/summary.json");
  EXPECT_EQ(summaryNumber(summary, "used"), summaryNumber(clean, "used"));
  EXPECT_GT(summaryNumber(summary, "used"), 0);
}

TEST(Faults, ALogCutAtAnyOffsetMapsEveryCompleteRecordBeforeIt) {
  const std::string dir = test::tempDir("cut");
  const std::string plain = plainTiny(dir);
  const auto starts = recordStarts(dir + "/tiny-plain.rawlog");
  ASSERT_GT(starts.size(), 300u);
  for (const double f : {0.05, 0.31, 0.5, 0.77, 0.9999}) {
    std::size_t cut = static_cast<std::size_t>(f * plain.size());
    const std::size_t k = std::upper_bound(starts.begin(), starts.end(), cut) - starts.begin() - 1;
    if (starts[k] == cut) ++cut;  // a cut between records is a shorter, complete log
    expectPartialEqualsPrefix(dir, "cut" + std::to_string(static_cast<int>(f * 100)),
                              plain.substr(0, cut), plain, starts, k,
                              "is cut off (truncated file)");
  }
}

TEST(Faults, GarbageBytesInsideTheLogStopAtTheRecordTheyHit) {
  const std::string dir = test::tempDir("garbage");
  const std::string plain = plainTiny(dir);
  const auto starts = recordStarts(dir + "/tiny-plain.rawlog");
  const std::size_t n = starts.size() - 1;
  // Overwritten with 0xff; with a few bytes flipped; with zero bytes; each at a record's start.
  std::string ff = plain, flipped = plain, zeros = plain;
  for (std::size_t i = 0; i < 16; ++i) ff[starts[n / 3] + i] = '\xff';
  for (std::size_t i = 0; i < 3; ++i) flipped[starts[n / 2] + i] ^= '\x5a';
  for (std::size_t i = 0; i < 64; ++i) zeros[starts[2 * n / 3] + i] = '\0';
  expectPartialEqualsPrefix(dir, "ff", ff, plain, starts, n / 3, "is corrupt");
  expectPartialEqualsPrefix(dir, "flipped", flipped, plain, starts, n / 2, "is corrupt");
  expectPartialEqualsPrefix(dir, "zeros", zeros, plain, starts, 2 * n / 3, "is corrupt");
}

// A scan record that claims 2^31 - 1 beams: a corrupt record, never an allocation of 18 GB.
// Returns the byte offset of the beam count it changed.
std::size_t setHugeBeamCount(std::string& bytes, std::size_t from) {
  const std::size_t cls = bytes.find("CObservation2DRangeScan", from);
  // tiny's scans have 181 beams; the count is the first little-endian 181 after the class name
  // (aperture, maxRange and the zero mount pose before it hold no such bytes).
  const std::size_t count = bytes.find(std::string("\xb5\x00\x00\x00", 4), cls);
  bytes.replace(count, 4, std::string("\xff\xff\xff\x7f", 4));
  return count;
}

TEST(Faults, AScanClaimingTwoBillionBeamsIsACorruptRecordNotAnAllocation) {
  const std::string dir = test::tempDir("huge");
  const std::string plain = plainTiny(dir);
  const auto starts = recordStarts(dir + "/tiny-plain.rawlog");
  std::string huge = plain;
  const std::size_t at = setHugeBeamCount(huge, starts[starts.size() / 2]);
  const std::size_t k = std::upper_bound(starts.begin(), starts.end(), at) - starts.begin() - 1;
  expectPartialEqualsPrefix(dir, "huge", huge, plain, starts, k,
                            "is corrupt: it states a size no real record has");
}

// 60 million beams fit under the 256 MiB a record may ever allocate, but not in what is left of
// a 1 MB log: refused as a corrupt record before anything is allocated for them.
TEST(Faults, AScanClaimingMoreBeamsThanTheFileHoldsAllocatesNothingForThem) {
  const std::string dir = test::tempDir("beams");
  const std::string plain = plainTiny(dir);
  const auto starts = recordStarts(dir + "/tiny-plain.rawlog");
  std::string lying = plain;
  const std::size_t cls = lying.find("CObservation2DRangeScan", starts[starts.size() / 2]);
  const std::size_t count = lying.find(std::string("\xb5\x00\x00\x00", 4), cls);
  lying.replace(count, 4, std::string("\x00\x87\x93\x03", 4));  // 60,000,000
  const std::size_t k = std::upper_bound(starts.begin(), starts.end(), count) - starts.begin() - 1;
  expectPartialEqualsPrefix(dir, "lying", lying, plain, starts, k,
                            "is corrupt: it states a size no real record has");
}

TEST(Faults, EmptyFilesAndFilesThatAreNoLogAreErrorsNamingTheFile) {
  // Nothing in them can be mapped: an error (1), not a partial input (4), and no outputs.
  const std::string dir = test::tempDir("nolog");
  writeBytes(dir + "/empty.rawlog", "");
  writeBytes(dir + "/picture.rawlog", "\x89PNG\r\n\x1a\n" + std::string(500, '\x01'));
  std::string out;
  EXPECT_EQ(map("--input " + dir + "/empty.rawlog --out " + dir + "/o1", &out), 1);
  EXPECT_EQ(out, "dynamap map: " + dir + "/empty.rawlog: empty file\n");
  EXPECT_EQ(map("--input " + dir + "/picture.rawlog --out " + dir + "/o2", &out), 1);
  EXPECT_EQ(out, "dynamap map: " + dir +
                     "/picture.rawlog: not an MRPT rawlog, simplemap, CARMEN log or ROS bag\n");
  EXPECT_FALSE(fs::exists(dir + "/o2/summary.json"));
}

// Twenty steps along a 6 x 4 m room, 61 beams over 180 degrees, ground truth beside each scan.
std::vector<test::LogStep> roomSteps(int n = 20) {
  std::vector<test::LogStep> steps;
  for (int k = 0; k < n; ++k) {
    const double t = 1000.0 + 0.2 * k;
    const CPose2D pose(-1.0 + 0.1 * k, 0.2, 0.05 * k);
    steps.push_back(
        {t, pose, test::makeScan(test::roomRanges(-3, 3, -2, 2, pose, 61, M_PI), M_PI, t)});
  }
  return steps;
}

void setBeams(test::LogStep& s, int from, int count, float value) {
  for (int i = from; i < from + count; ++i) {
    s.scan->setScanRange(i, value);
    s.scan->setScanRangeValidity(i, true);  // "valid", as a faulty driver would say
  }
}

// A keyframe whose sensory frame states 67 million observations (each allocation a 512-byte
// block of a deque, under any single bound): a corrupt keyframe, not a gigabyte allocated.
TEST(Faults, AFrameStatingMillionsOfObservationsIsACorruptKeyframe) {
  const std::string dir = test::tempDir("smcount");
  const auto starts = test::writeSimplemap(dir + "/full.simplemap", roomSteps());
  std::string bytes = test::readFile(dir + "/full.simplemap");
  // The frame's version byte, then its count of observations: 1.
  const std::size_t count = bytes.find("CSensoryFrame", starts[5]) + 13 + 1;
  ASSERT_EQ(bytes.substr(count, 4), std::string("\x01\x00\x00\x00", 4));
  bytes.replace(count, 4, std::string("\x00\x00\x00\x04", 4));
  writeBytes(dir + "/lying.simplemap", bytes);
  std::string out;
  EXPECT_EQ(map("--input " + dir + "/lying.simplemap --out " + dir + "/lying", &out), 4) << out;
  EXPECT_NE(out.find("lying.simplemap: keyframe 5 of 20 at byte " + std::to_string(starts[5]) +
                     " is corrupt: it states a size no real record has"),
            std::string::npos)
      << out;
  EXPECT_EQ(summaryNumber(test::readFile(dir + "/lying/summary.json"), "used"), 5);
}

// A simplemap cut inside a keyframe: exit 4, the keyframes before it mapped exactly as a
// simplemap of those keyframes alone, every output written.
TEST(Faults, ASimplemapCutInsideAKeyframeMapsEveryKeyframeBeforeIt) {
  const std::string dir = test::tempDir("smcut");
  const auto steps = roomSteps();
  const auto starts = test::writeSimplemap(dir + "/full.simplemap", steps);
  test::writeSimplemap(dir + "/prefix.simplemap",
                       std::vector<test::LogStep>(steps.begin(), steps.begin() + 12));
  writeBytes(dir + "/cut.simplemap",
             test::readFile(dir + "/full.simplemap").substr(0, (starts[12] + starts[13]) / 2));
  std::string out;
  EXPECT_EQ(map("--input " + dir + "/cut.simplemap --out " + dir + "/cut", &out), 4) << out;
  EXPECT_NE(out.find("cut.simplemap: keyframe 12 of 20 at byte " + std::to_string(starts[12]) +
                     " is cut off (truncated file)"),
            std::string::npos)
      << out;
  ASSERT_EQ(map("--input " + dir + "/prefix.simplemap --out " + dir + "/prefix", &out), 0) << out;
  expectSameMapOutputs(dir + "/cut", dir + "/prefix");
  const std::string summary = test::readFile(dir + "/cut/summary.json");
  EXPECT_NE(summary.find("\"complete_input\": false"), std::string::npos) << summary;
  EXPECT_EQ(summaryNumber(summary, "used"), 12);
}

TEST(Faults, BadBeamsAndBadScansAreSkippedAndCountedByReason) {
  const std::string dir = test::tempDir("badscans");
  auto steps = roomSteps();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  setBeams(steps[3], 0, 5, nan);
  setBeams(steps[5], 10, 3, inf);
  setBeams(steps[7], 20, 2, -1.0f);
  steps[9].scan = test::makeScan({}, M_PI, steps[9].t);                             // zero beams
  steps[11].scan = test::makeScan(std::vector<float>(61, 1.0f), 0.0, steps[11].t);  // aperture 0
  setBeams(steps[13], 0, 61, nan);  // nothing usable
  test::writeObsRawlog(dir + "/bad.rawlog", steps);
  // The same log without those three scans and with the bad beams' cells never seen.
  std::string out;
  ASSERT_EQ(map("--input " + dir + "/bad.rawlog --out " + dir + "/o", &out), 0) << out;
  const std::string summary = test::readFile(dir + "/o/summary.json");
  EXPECT_EQ(summaryNumber(summary, "read"), 20) << summary;
  EXPECT_EQ(summaryNumber(summary, "used"), 17) << summary;
  EXPECT_EQ(summaryNumber(summary, "skipped"), 3) << summary;
  EXPECT_EQ(summaryNumber(summary, "no beams"), 1) << summary;
  EXPECT_EQ(summaryNumber(summary, "aperture not positive"), 1) << summary;
  EXPECT_EQ(summaryNumber(summary, "no usable beam"), 1) << summary;
  EXPECT_EQ(summaryNumber(summary, "bad_beams"), 5 + 3 + 2 + 61) << summary;
  EXPECT_NE(out.find("warning: 3 scans of 20 skipped"), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(dir + "/o/static.png"));
}

// Writes an observations-only rawlog: odometry and scan per step, ground truth only for the
// steps `gt(k)` says.
void writeLog(const std::string& path, const std::vector<test::LogStep>& steps,
              const std::function<bool(std::size_t)>& gt) {
  mrpt::io::CFileGZOutputStream f(path);
  auto arch = mrpt::serialization::archiveFrom(f);
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const auto& s = steps[k];
    const auto stamp = mrpt::Clock::fromDouble(s.t);
    auto odo = mrpt::obs::CObservationOdometry::Create();
    odo->timestamp = stamp;
    odo->odometry = s.pose;
    arch << *odo << *s.scan;
    if (gt(k)) {
      auto g = mrpt::obs::CObservationRobotPose::Create();
      g->timestamp = stamp;
      g->pose.mean = mrpt::poses::CPose3D(s.pose);
      arch << *g;
    }
  }
}

TEST(Faults, APoseJumpBeyondMaxMapSizeIsSkippedAndCountedNotAllocated) {
  const std::string dir = test::tempDir("jump");
  auto steps = roomSteps();
  steps[10].pose = CPose2D(5.0e6, -3.0e6, 0.0);  // a glitch of 5,000 km
  test::writeObsRawlog(dir + "/jump.rawlog", steps);
  std::string out;
  ASSERT_EQ(map("--input " + dir + "/jump.rawlog --out " + dir + "/o", &out), 0) << out;
  const std::string summary = test::readFile(dir + "/o/summary.json");
  EXPECT_EQ(summaryNumber(summary, "beyond max_map_size_m"), 1) << summary;
  EXPECT_EQ(summaryNumber(summary, "used"), 19) << summary;
  // The grid still has its initial 20 x 20 m (400 cells at 5 cm), nothing of the jump.
  EXPECT_EQ(nlohmann::json::parse(summary)["map"]["size_cells"], nlohmann::json::array({400, 400}))
      << summary;
  EXPECT_NE(out.find("beyond max_map_size_m"), std::string::npos) << out;
}

// The plain MRPT grid (on by default) once took every scan the mapper skipped: a pose 5,000 km
// away or a NaN range crashed the run (SIGSEGV after gigabytes) and lost every output.
TEST(Faults, TheBaselineSeesOnlyTheScansTheMapperInserted) {
  const std::string dir = test::tempDir("baseline");
  auto steps = roomSteps();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  steps[10].pose = CPose2D(5.0e6, -3.0e6, 0.0);
  setBeams(steps[3], 0, 5, nan);
  setBeams(steps[5], 10, 3, -std::numeric_limits<float>::infinity());
  setBeams(steps[13], 0, 61, nan);
  test::writeObsRawlog(dir + "/bad.rawlog", steps);
  std::string out;
  ASSERT_EQ(test::run(kExe + " map --input " + dir + "/bad.rawlog --out " + dir + "/o", &out), 0)
      << out;
  const std::string summary = test::readFile(dir + "/o/summary.json");
  EXPECT_EQ(summaryNumber(summary, "beyond max_map_size_m"), 1) << summary;
  EXPECT_EQ(summaryNumber(summary, "no usable beam"), 1) << summary;
  EXPECT_EQ(summaryNumber(summary, "used"), 18) << summary;
  EXPECT_NE(summary.find("\"mrpt_baseline\""), std::string::npos) << summary;
  EXPECT_TRUE(fs::exists(dir + "/o/mrpt_plain.png"));
  // A CARMEN line with a pose of 1e9 m, the smallest input that crashed it.
  const std::string carmen = kSrc + "/tests/fuzz_regressions/baseline/carmen_pose_of_1e9_m.log";
  ASSERT_EQ(test::run(kExe + " map --input " + carmen + " --out " + dir + "/c", &out), 0) << out;
  EXPECT_EQ(summaryNumber(test::readFile(dir + "/c/summary.json"), "beyond max_map_size_m"), 1);
  EXPECT_TRUE(fs::exists(dir + "/c/mrpt_plain.png"));
}

// One scan of 2,000,000 beams: dynamap's grid took it, MRPT's insertion in the plain grid (on by
// default) overflowed the stack on it (SIGSEGV, every output lost); its beams ending within reach
// (2 m), the people detector alone took hours. Both maps refuse it now, before anything else looks
// at it, counted once under the same reason, and every other scan is mapped by both.
TEST(Faults, AScanTooWideForMrptIsSkippedByBothMapsAndCounted) {
  for (const float range : {2.0f, 40.0f}) {  // hits in the room; every beam past the 15 m reach
    const std::string dir = test::tempDir("wide");
    auto steps = roomSteps();
    steps[7].scan = test::makeScan(std::vector<float>(2000000, range), M_PI, steps[7].t, 50.0f);
    test::writeObsRawlog(dir + "/wide.rawlog", steps);
    std::string out;
    ASSERT_EQ(test::run(kExe + " map --input " + dir + "/wide.rawlog --out " + dir + "/o", &out), 0)
        << out;
    const std::string summary = test::readFile(dir + "/o/summary.json");
    EXPECT_EQ(summaryNumber(summary, kTooManyBeams), 1) << summary;
    EXPECT_EQ(summaryNumber(summary, "used"), 19) << summary;
    EXPECT_NE(summary.find("\"mrpt_baseline\""), std::string::npos) << summary;
    EXPECT_TRUE(fs::exists(dir + "/o/mrpt_plain.png"));
    EXPECT_TRUE(fs::exists(dir + "/o/static.png"));
  }
}

// A line type of bytes that are not UTF-8, with a terminal escape in front: summary.json stays
// valid JSON and the terminal gets the bytes written out, not obeyed.
TEST(Faults, BytesFromTheFileAreEscapedInSummaryJsonAndOnTheTerminal) {
  const std::string dir = test::tempDir("bytes");
  const std::string log =
      test::readFile(kSrc + "/tests/fuzz_regressions/baseline/carmen_pose_of_1e9_m.log");
  const std::string first_line = log.substr(0, log.find('\n') + 1);
  writeBytes(dir + "/b.log", first_line +
                                 "\x1b[31m\xff\xfe"
                                 "FLASER 1 2 3\n" +
                                 first_line);
  std::string out;
  ASSERT_EQ(map("--input " + dir + "/b.log --out " + dir + "/o", &out), 0) << out;
  EXPECT_EQ(out.find('\x1b'), std::string::npos) << out;
  EXPECT_NE(out.find("\\x1b[31m\\xff\\xfeFLASER"), std::string::npos) << out;
  const auto json = nlohmann::json::parse(test::readFile(dir + "/o/summary.json"));
  EXPECT_EQ(json["scans"]["used"], 2);
  // A line that is no scan is a line skipped, not a scan skipped.
  const auto& lines = json["records_skipped"]["by_reason"];
  ASSERT_EQ(lines.size(), 1u) << json.dump();
  // What is not UTF-8 becomes U+FFFD; the escape character is \u001b in JSON.
  EXPECT_EQ(lines.begin().key(),
            "line type \x1b[31m\xef\xbf\xbd\xef\xbf\xbd"
            "FLASER");
}

TEST(Faults, MissingPosesAreAnErrorNamingTheFirstScanWithoutOne) {
  const std::string dir = test::tempDir("noposes");
  const auto steps = roomSteps();
  // Ground truth stops after step 9: scan 10 is 0.2 s past the last pose, too far to take it.
  writeLog(dir + "/half.rawlog", steps, [](std::size_t k) { return k < 10; });
  std::string out;
  ASSERT_EQ(map("--poses ground_truth --input " + dir + "/half.rawlog --out " + dir + "/o", &out),
            4)
      << out;
  EXPECT_NE(out.find(dir + "/half.rawlog: scan 10 (t="), std::string::npos) << out;
  EXPECT_NE(out.find("has no ground_truth pose"), std::string::npos) << out;
  EXPECT_EQ(summaryNumber(test::readFile(dir + "/o/summary.json"), "used"), 10);
  // No ground truth at all under --poses ground_truth: nothing to map, an error at once.
  writeLog(dir + "/none.rawlog", steps, [](std::size_t) { return false; });
  EXPECT_EQ(map("--poses ground_truth --input " + dir + "/none.rawlog --out " + dir + "/o2", &out),
            1);
  EXPECT_NE(out.find(dir + "/none.rawlog: no ground-truth poses"), std::string::npos) << out;
}

TEST(Faults, TimestampsGoingBackwardsAreCountedAndWarnedAbout) {
  const std::string dir = test::tempDir("backwards");
  auto steps = roomSteps();
  for (int k : {6, 14}) {  // two scans stamped 0.1 s before the one ahead of them
    steps[k].t = steps[k - 1].t - 0.1;
    steps[k].scan->timestamp = mrpt::Clock::fromDouble(steps[k].t);
  }
  test::writeObsRawlog(dir + "/back.rawlog", steps);
  std::string out;
  ASSERT_EQ(map("--input " + dir + "/back.rawlog --out " + dir + "/o", &out), 0) << out;
  const std::string summary = test::readFile(dir + "/o/summary.json");
  EXPECT_EQ(summaryNumber(summary, "timestamps_backwards"), 2) << summary;
  EXPECT_EQ(summaryNumber(summary, "used"), 20) << summary;
  EXPECT_NE(out.find("dynamap map: warning: 2 scans have a timestamp earlier than the scan "
                     "before them (first: scan 6)"),
            std::string::npos)
      << out;
}

TEST(Faults, BadConfigurationIsAOneLineErrorNamingTheKeyWithItsOwnStatus) {
  const std::string dir = test::tempDir("badconfig");
  const std::string in = " --input " + kTiny + " --out " + dir + "/o";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"[dynamic_map]\nresolution = fine\n", "[dynamic_map] resolution: "},
      {"[dynamic_map]\nresolution = -0.05\n",
       "[dynamic_map] resolution: -0.05 must be in [0.005, 10] m"},
      {"[dynamic_map]\nmax_map_size_m = 1e9\n",
       "[dynamic_map] max_map_size_m: 1e+09 must be in [1, 10000] m"},
      {"[dynamic_mapp]\nresolution = 0.05\n", "dynamic_mapp"},
      {"[input]\nposes = gps\n", "[input] poses: "},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string ini = dir + "/c" + std::to_string(i) + ".ini";
    writeBytes(ini, cases[i].first);
    std::string out;
    EXPECT_EQ(map("--config " + ini + in, &out), 3) << cases[i].first << out;
    EXPECT_EQ(out.rfind("dynamap map: " + ini + ": ", 0), 0u) << out;
    EXPECT_NE(out.find(cases[i].second), std::string::npos) << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  }
  std::string out;
  EXPECT_EQ(map("--config " + dir + "/missing.ini" + in, &out), 3);
  EXPECT_EQ(out, "dynamap map: " + dir + "/missing.ini: cannot open configuration file\n");
  EXPECT_FALSE(fs::exists(dir + "/o/summary.json"));
}

TEST(Faults, AnUnwritableOutputDirectoryFailsBeforeAnyWork) {
  const std::string dir = test::tempDir("unwritable");
  writeBytes(dir + "/file", "x");
  std::string out;
  // The input does not even exist: the output directory is checked first.
  EXPECT_EQ(map("--input " + dir + "/missing.rawlog --out " + dir + "/file/o", &out), 1);
  EXPECT_EQ(out.rfind("dynamap map: " + dir + "/file/o: cannot create output directory", 0), 0u)
      << out;
  EXPECT_EQ(map("--input " + kTiny + " --out /proc/dynamap-out", &out), 1);
  EXPECT_NE(out.find("/proc/dynamap-out: cannot create output directory"), std::string::npos)
      << out;
}

TEST(Faults, AForeignRecordWhereAScanWasExpectedIsSkippedAndCounted) {
  const std::string dir = test::tempDir("foreign");
  const auto steps = roomSteps();
  {
    mrpt::io::CFileGZOutputStream f(dir + "/foreign.rawlog");
    auto arch = mrpt::serialization::archiveFrom(f);
    for (std::size_t k = 0; k < steps.size(); ++k) {
      auto g = mrpt::obs::CObservationRobotPose::Create();
      g->timestamp = mrpt::Clock::fromDouble(steps[k].t);
      g->pose.mean = mrpt::poses::CPose3D(steps[k].pose);
      if (k == 7) {
        arch << steps[k].pose;  // a CPose2D object, no observation at all
      } else {
        arch << *steps[k].scan;
      }
      arch << *g;
    }
  }
  std::string out;
  ASSERT_EQ(map("--input " + dir + "/foreign.rawlog --out " + dir + "/o", &out), 0) << out;
  const std::string summary = test::readFile(dir + "/o/summary.json");
  EXPECT_EQ(summaryNumber(summary, "record of class mrpt::poses::CPose2D"), 1) << summary;
  EXPECT_EQ(summaryNumber(summary, "read"), 19) << summary;
  EXPECT_EQ(summaryNumber(summary, "used"), 19) << summary;
  EXPECT_NE(out.find("warning: 1 records of 40 skipped: record of class mrpt::poses::CPose2D (1)"),
            std::string::npos)
      << out;
}

// Every input the fuzzers once crashed on (or that guards a fixed fault), through the same entry
// point: they must all return. Under `make test-asan` the sanitizers check them too.
// Hours of driving: the path kept for the pictures is thinned, never grown without bound.
TEST(Faults, TheRobotsPathStaysBoundedHoweverLongTheRun) {
  MapConfig config;
  config.objects.enabled = false;
  Mapper mapper(config);
  // Back and forth along a 4 m line, 6 cm a scan (one path point each): 140,000 points' worth.
  const auto scan = test::makeScan({1.0f, 1.0f}, 0.1);
  const std::size_t steps = 2 * RobotPath::kMaxPoints + 9000;
  for (std::size_t i = 0; i < steps; ++i) {
    const std::size_t k = i % 132;
    const double x = 0.06 * static_cast<double>(k < 66 ? k : 132 - k);
    ScanRecord rec;
    rec.index = i;
    rec.t = 0.1 * static_cast<double>(i);
    rec.pose = CPose2D(x, 0, 0);
    rec.scan = scan;
    ASSERT_TRUE(mapper.process(rec).inserted) << "scan " << i;
  }
  EXPECT_LE(mapper.path().size(), RobotPath::kMaxPoints);
  EXPECT_GT(mapper.path().size(), RobotPath::kMaxPoints / 4);
  // Still the path: its points lie on the line driven.
  for (const PathPoint& p : mapper.path()) {
    EXPECT_NEAR(p.y, 0.0, 1e-9);
    EXPECT_GE(p.x, -1e-9);
    EXPECT_LE(p.x, 3.96 + 1e-9);
  }
}

}  // namespace
}  // namespace dynamap
