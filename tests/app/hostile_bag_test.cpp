// ROS bags whose index or record lengths lie, end to end through `dynamap map`. Bags written here
// with rosbag (tf, odometry and scans, in chunks of 4 KB) are damaged at one offset or length the
// format states: an index entry's offset, a message record's header or data length inside its
// chunk, a chunk's size, a connection id, a count, a position. rosbag followed each of these
// without a check (a crash, every output lost); each run must now exit 0, 1 or 4 with no signal,
// and keep the outputs of the scans read before the fault.

#include <sys/wait.h>

#include <gtest/gtest.h>
#include <rosbag/bag.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>

#include "../bag_test_util.h"
#include "../test_util.h"
#include "fuzz_entries.h"
#include "structure_mutators.h"

namespace dynamap {
namespace {

namespace fs = std::filesystem;
using mrpt::poses::CPose2D;
using test::BagRecord;

const std::string kExe = DYNAMAP_EXE;
constexpr int kScans = 30;

/// 6 s of /tf at 20 Hz and kScans scans of 200 beams: a dozen chunks of 4 KB, each indexed.
std::string writeDrive(const std::string& path, int compression) {
  test::BagWriter bag(path, compression);
  bag.tf(100.0, "base_link", "laser", CPose2D(0.2, 0.0, 0.0), true);
  test::RosScan scan;
  scan.increment = 0.01f;
  scan.ranges.assign(200, 3.0f);
  for (int k = 0; k <= 120; ++k) {
    const double t = 100.0 + 0.05 * k;
    bag.tf(t, "odom", "base_link", CPose2D(0.01 * k, 0.0, 0.0));
    if (k % 4 == 2 && k / 4 < kScans) bag.scan("/scan", t, scan);
  }
  bag.close();
  return test::readFile(path);
}

struct MapRun {
  int status = -1;  // exit status; -1 when killed by a signal
  std::string output;
  long used = -1;  // scans mapped (summary.json), -1 when no summary
};

long summaryNumber(const std::string& summary, const std::string& key) {
  const auto pos = summary.find("\"" + key + "\": ");
  return pos == std::string::npos ? -1 : std::stol(summary.substr(pos + key.size() + 4));
}

/// `dynamap map` (baseline on, as by default) on `bytes` written to dir/name.bag.
MapRun mapBag(const std::string& dir, const std::string& name, const std::string& bytes) {
  const std::string bag = dir + "/" + name + ".bag", out = dir + "/" + name;
  std::ofstream(bag, std::ios::binary) << bytes;
  MapRun r;
  const int raw = std::system(
      (kExe + " map --input " + bag + " --out " + out + " > " + out + ".log 2>&1").c_str());
  r.output = test::readFile(out + ".log");
  if (WIFEXITED(raw)) r.status = WEXITSTATUS(raw);
  if (fs::exists(out + "/summary.json")) {
    r.used = summaryNumber(test::readFile(out + "/summary.json"), "used");
  }
  return r;
}

/// Exit 0, 1 or 4, never a signal; with 0 or 4 every output is there.
void expectHandled(const MapRun& r, const std::string& what) {
  SCOPED_TRACE(what);
  ASSERT_TRUE(r.status == 0 || r.status == 1 || r.status == 4) << r.status << "\n" << r.output;
  if (r.status != 1) {
    EXPECT_GE(r.used, 0) << r.output;
  }
}

class HostileBagTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::tempDir("hostile_bag"); }
  std::string dir_;
};

TEST_F(HostileBagTest, TheCleanBagsMapEveryScanThroughTheirIndex) {
  for (const int c : {0, 1, 2}) {
    const std::string bytes = writeDrive(dir_ + "/w.bag", c);
    const MapRun r = mapBag(dir_, "clean" + std::to_string(c), bytes);
    EXPECT_EQ(r.status, 0) << r.output;  // read through rosbag's index: no fault
    EXPECT_EQ(r.used, kScans) << r.output;
  }
}

// Four bytes of an index entry set to 0xFFFFFFFF: the entry points outside its chunk. rosbag
// read a record header there (SIGSEGV in the /tf pre-pass, nothing written). The bag is read in
// file order instead: every scan, and the fault says the index cannot be followed.
TEST_F(HostileBagTest, AnIndexEntryPointingOutsideItsChunkReadsTheBagInFileOrder) {
  for (const int c : {0, 2}) {
    const std::string clean = writeDrive(dir_ + "/w.bag", c);
    int damaged = 0;
    for (const BagRecord& rec : test::bagRecords(clean, 13, clean.size())) {
      if (rec.op() != 0x04 || damaged >= 4) continue;  // the first index records
      for (const std::uint32_t v : {0xFFFFFFFFu, 0x10000u}) {
        std::string bytes = clean;
        test::put32(bytes, rec.data_pos + 4 + 8, v);  // entry 0's offset
        const MapRun r = mapBag(dir_, "index" + std::to_string(damaged), bytes);
        expectHandled(r, "index record at byte " + std::to_string(rec.pos));
        EXPECT_EQ(r.status, 4) << r.output;
        EXPECT_NE(r.output.find("whose index cannot be followed (record at byte " +
                                std::to_string(rec.pos) + ": index entry 0 points at byte " +
                                std::to_string(v)),
                  std::string::npos)
            << r.output;
        EXPECT_EQ(r.used, kScans) << r.output;  // the records themselves are whole
      }
      ++damaged;
    }
    EXPECT_EQ(damaged, 4);
  }
}

/// The message records of the uncompressed chunks: where each one's header length is.
std::vector<BagRecord> chunkMessages(const std::string& bag) {
  std::vector<BagRecord> out;
  for (const BagRecord& c : test::bagRecords(bag, 13, bag.size())) {
    if (c.op() != 0x05) continue;
    for (const BagRecord& m : test::bagRecords(bag, c.data_pos + 4, c.data_pos + 4 + c.data_len)) {
      if (m.op() == 0x02) out.push_back(m);
    }
  }
  return out;
}

// A message record inside a chunk whose header length is 0xFFFFFFFF: rosbag handed it to
// ros::Header::parse, whose replacement then read 4 GB past the chunk (SIGSEGV). Every scan
// before that record is mapped and the run ends in a fault (exit 4) naming the record.
TEST_F(HostileBagTest, AMessageHeaderLengthRunningPastItsChunkKeepsTheScansBeforeIt) {
  const std::string clean = writeDrive(dir_ + "/w.bag", 0);
  const std::vector<BagRecord> messages = chunkMessages(clean);
  ASSERT_GT(messages.size(), 100u);
  for (const std::size_t k : {messages.size() / 2, messages.size() - 1}) {
    for (const bool header : {true, false}) {
      std::string bytes = clean;
      test::put32(bytes, header ? messages[k].pos : messages[k].data_pos, 0xFFFFFFFFu);
      const MapRun r = mapBag(dir_, "msg" + std::to_string(k) + (header ? "h" : "d"), bytes);
      expectHandled(r, "message " + std::to_string(k));
      EXPECT_EQ(r.status, 4) << r.output;
      EXPECT_NE(r.output.find("whose index cannot be followed"), std::string::npos) << r.output;
      EXPECT_GT(r.used, k == messages.size() - 1 ? kScans - 3 : 5) << r.output;
      EXPECT_LT(r.used, kScans + 1) << r.output;
    }
  }
}

/// Every 4-byte field named `key` in the header of records of kind `op`, set to each value.
void lieInField(const std::string& dir, const std::string& clean, char op, const std::string& key,
                const std::vector<std::uint32_t>& values) {
  int n = 0;
  for (const BagRecord& rec : test::bagRecords(clean, 13, clean.size())) {
    if (rec.op() != op || n >= 1) continue;
    const auto at = clean.find(key + "=", rec.pos + 4);
    ASSERT_LT(at, rec.data_pos);
    for (const std::uint32_t v : values) {
      std::string bytes = clean;
      test::put32(bytes, at + key.size() + 1, v);
      expectHandled(mapBag(dir, key + std::to_string(n) + "-" + std::to_string(v), bytes),
                    key + " of the record at byte " + std::to_string(rec.pos) + " set to " +
                        std::to_string(v));
    }
    ++n;
  }
  EXPECT_GT(n, 0) << key;
}

// Sizes, connection ids, counts and positions that lie: each handled, none followed blindly.
TEST_F(HostileBagTest, ChunkSizesConnectionIdsCountsAndPositionsThatLieAreHandled) {
  for (const int c : {0, 2}) {
    const std::string clean = writeDrive(dir_ + "/w.bag", c);
    lieInField(dir_, clean, 0x05, "size", {0u, 17u, 0x7FFFFFFFu, 0xFFFFFFFFu});
    lieInField(dir_, clean, 0x04, "conn", {1u, 7u, 0xFFFFFFFFu});
    lieInField(dir_, clean, 0x04, "count", {0u, 1000u, 0xFFFFFFFFu});
    lieInField(dir_, clean, 0x06, "chunk_pos", {13u, 4096u, 0xFFFFFFFFu});
    lieInField(dir_, clean, 0x03, "index_pos", {13u, 4109u, 0xFFFFFFFFu});
    lieInField(dir_, clean, 0x03, "chunk_count", {0u, 1000u, 0xFFFFFFFFu});
  }
}

// make fuzz's bag mutator: on the bags written here it always finds a number to change, and
// whatever it makes, the fuzzer's entry point (the reader with its poses and a fixed pose, every
// scan through the mapper) returns: a crash here ends the test.
TEST_F(HostileBagTest, TheBagMutatorsLiesAreHandledInProcess) {
  for (const int c : {0, 2}) {
    const std::string clean = writeDrive(dir_ + "/w.bag", c);
    int changed = 0, resized = 0;
    for (unsigned seed = 0; seed < 100; ++seed) {
      std::string b = clean + std::string(4096, '\0');
      auto* p = reinterpret_cast<std::uint8_t*>(b.data());
      const std::size_t n = fuzz::mutateBag(p, clean.size(), b.size(), seed);
      ASSERT_GT(n, 0u) << seed;
      b.resize(n);
      changed += b != clean;
      resized += n != clean.size();
      fuzz::bagInput(p, n);
    }
    EXPECT_GE(changed, 90);
    if (c == 0) {
      EXPECT_GE(resized, 10);  // messages of uncompressed chunks resized consistently
    }
  }
}

}  // namespace
}  // namespace dynamap
