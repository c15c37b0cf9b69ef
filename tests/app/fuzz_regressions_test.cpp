// The fuzzers' regression inputs (tests/fuzz_regressions/) replayed through their entry points,
// and make fuzz's seeds cut, flipped and mutated: whatever the readers make of them, the entry
// points return (a crash ends the test).

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "../test_util.h"
#include "fuzz_entries.h"
#include "structure_mutators.h"

namespace dynamap {
namespace {

namespace fs = std::filesystem;

const std::string kSrc = DYNAMAP_SOURCE_DIR;

TEST(FuzzRegressions, EveryKeptInputRunsThroughItsEntryPoint) {
  const std::vector<std::pair<std::string, void (*)(const std::uint8_t*, std::size_t)>> targets = {
      {"scenario", fuzz::scenarioInput},
      {"carmen", fuzz::carmenInput},
      {"rawlog", fuzz::rawlogInput},
      {"simplemap", fuzz::simplemapInput},
      {"bag", fuzz::bagInput},
      {"baseline", fuzz::baselineInput},
      {"config", fuzz::configInput},
      {"session", fuzz::sessionInput},
      {"mcap", fuzz::mcapInput},
      {"db3", fuzz::db3Input}};
  std::size_t files = 0;
  for (const auto& [name, entry] : targets) {
    const fs::path dir = fs::path(kSrc) / "tests/fuzz_regressions" / name;
    if (!fs::exists(dir)) continue;
    for (const auto& e : fs::directory_iterator(dir)) {
      SCOPED_TRACE(e.path().string());
      const std::string bytes = test::readFile(e.path().string());
      entry(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
      ++files;
    }
  }
  EXPECT_GE(files, 3u);  // at least one per target
}

// The ROS 2 seeds of make fuzz cut at 40 places and with 150 bytes flipped, one at a time:
// whatever the readers make of them, the entry points return (a crash ends the test).
TEST(FuzzRegressions, Ros2SeedsCutOrFlippedAreHandled) {
  std::size_t runs = 0;
  for (const char* seed :
       {"mcap/small.mcap", "mcap/small_none.mcap", "mcap/odometry.mcap", "db3/small.db3"}) {
    const std::string clean = test::readFile(kSrc + "/fuzz/seeds/" + seed);
    const bool mcap = std::string(seed).rfind("mcap/", 0) == 0;
    const auto entry = mcap ? fuzz::mcapInput : fuzz::db3Input;
    for (std::size_t k = 1; k <= 40; ++k) {
      entry(reinterpret_cast<const std::uint8_t*>(clean.data()), clean.size() * k / 41);
      ++runs;
    }
    std::uint32_t x = 12345;
    for (int k = 0; k < 150; ++k) {
      x = x * 1664525u + 1013904223u;  // the same flips on every run
      std::string b = clean;
      b[x % b.size()] = static_cast<char>(b[x % b.size()] ^ (1 << (x >> 29)));
      entry(reinterpret_cast<const std::uint8_t*>(b.data()), b.size());
      ++runs;
    }
  }
  EXPECT_EQ(runs, 4u * 190u);
}

// make fuzz's rawlog mutator on its seed: it changes a record (dropped, repeated, swapped, a scan's
// beams or a length made to lie, a pose no robot reaches) and whatever it makes, the fuzzer's entry
// point returns: a crash here ends the test.
TEST(FuzzRegressions, TheRawlogMutatorsChangesAreHandled) {
  const std::string seed_log = test::readFile(kSrc + "/fuzz/seeds/rawlog/tiny_head.rawlog");
  int made = 0, changed = 0;
  for (unsigned seed = 0; seed < 200; ++seed) {
    std::string b = seed_log + std::string(16384 - seed_log.size(), '\0');
    auto* p = reinterpret_cast<std::uint8_t*>(b.data());
    const std::size_t n = fuzz::mutateRawlog(p, seed_log.size(), b.size(), seed);
    if (n == 0) continue;  // nothing to change in the record drawn
    ++made;
    b.resize(n);
    changed += b != seed_log;
    fuzz::rawlogInput(p, n);
  }
  EXPECT_GE(made, 100);
  EXPECT_GE(changed, made * 9 / 10);
}

}  // namespace
}  // namespace dynamap
