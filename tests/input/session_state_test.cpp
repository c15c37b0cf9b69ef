// session.json: what one session leaves for the next. Written and read back exactly; every
// fault of a hostile file is an InputError naming the file and the key, and the grid a file
// describes is refused before it is allocated when it exceeds the largest map.

#include "dynamap/input/session_state.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "dynamap/input/scan_source.h"
#include "../test_util.h"

namespace dynamap {
namespace {

SessionState sample() {
  SessionState s;
  s.sessions = 3;
  s.x_min = -2.5;
  s.y_min = 1.25;
  s.resolution = 0.05;
  s.size_x = 7;
  s.size_y = 5;
  for (int i = 0; i < 35; ++i) s.static_cells.push_back(static_cast<std::int8_t>(i * 7 - 120));
  s.objects = {{1, "present", 1.5, -0.25, 0.4, 2, 10.5, 99.25},
               {2, "withdrawn", 0, 0, 0.3, 0, 11, 12},
               {3, "absent", -3, 4, 0.61, 1, 20, 30}};
  s.last_x = 1;
  s.last_y = 2;
  s.last_phi = -0.5;
  s.last_t = 1234.5;
  return s;
}

std::string written(const SessionState& s) {
  std::ostringstream out;
  writeSessionState(s, out);
  return out.str();
}

TEST(SessionState, ReadsBackExactlyWhatWasWritten) {
  const SessionState a = sample();
  const SessionState b = parseSessionState(written(a), "x.json", 1000);
  EXPECT_EQ(b.sessions, 3);
  EXPECT_EQ(b.x_min, -2.5);
  EXPECT_EQ(b.y_min, 1.25);
  EXPECT_EQ(b.resolution, 0.05);
  EXPECT_EQ(b.size_x, 7u);
  EXPECT_EQ(b.size_y, 5u);
  EXPECT_EQ(b.static_cells, a.static_cells);
  ASSERT_EQ(b.objects.size(), 3u);
  EXPECT_EQ(b.objects[1].state, "withdrawn");
  EXPECT_EQ(b.objects[2].cx, -3);
  EXPECT_EQ(b.objects[2].size, 0.61);
  EXPECT_EQ(b.objects[0].n_moves, 2);
  EXPECT_EQ(b.objects[0].last_seen_t, 99.25);
  EXPECT_EQ(b.last_phi, -0.5);
  EXPECT_EQ(b.last_t, 1234.5);
  EXPECT_EQ(written(b), written(a));  // and the same bytes again
}

// The message of parsing `text`, expected to fail.
std::string failure(const std::string& text, std::uint64_t max_cells = 1000) {
  return test::inputError([&] { parseSessionState(text, "prior/session.json", max_cells); });
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

TEST(SessionState, EveryFaultNamesTheFileAndTheKey) {
  const std::string good = written(sample());
  EXPECT_EQ(failure("not json"), "prior/session.json: (file): not a JSON object");
  EXPECT_EQ(failure(replaced(good, "dynamap-session", "other")),
            "prior/session.json: format: not a dynamap session state");
  EXPECT_EQ(failure(replaced(good, "\"version\": 1", "\"version\": 2")),
            "prior/session.json: version: out of range [1, 1]");
  EXPECT_EQ(failure(replaced(good, "\"size_x\": 7", "\"size_x\": 8")),
            "prior/session.json: grid.static: not 40 zlib-compressed cells");
  EXPECT_EQ(failure(replaced(good, "\"size_x\": 7", "\"size_x\": -7")),
            "prior/session.json: grid.size_x: out of range [1, 16777216]");
  EXPECT_EQ(failure(replaced(good, "\"resolution\": 0.05", "\"resolution\": \"fine\"")),
            "prior/session.json: grid.resolution: not a number");
  EXPECT_EQ(failure(replaced(good, "\"static\": \"", "\"static\": \"%%%%")),
            "prior/session.json: grid.static: not base64");
  EXPECT_EQ(failure(replaced(good, "\"static\": \"", "\"static\": \"AA")),
            "prior/session.json: grid.static: not base64");
  EXPECT_EQ(failure(replaced(good, "\"static\": \"", "\"static\": \"AAAA")),
            "prior/session.json: grid.static: not 35 zlib-compressed cells");
  EXPECT_EQ(failure(replaced(good, "\"state\": \"absent\"", "\"state\": \"lost\"")),
            "prior/session.json: objects[2].state: unknown state 'lost'");
  EXPECT_EQ(failure(replaced(good, "\"id\": 3", "\"id\": 4")),
            "prior/session.json: objects[2].id: ids must be 1, 2, ... in order; found 4");
  EXPECT_EQ(failure(replaced(good, "\"last_pose\"", "\"other\"")),
            "prior/session.json: last_pose: missing");
}

TEST(SessionState, AGridLargerThanTheLargestMapIsRefusedBeforeItIsAllocated) {
  // 16 million x 16 million cells would be 256 TB: refused from the numbers alone.
  std::string big = replaced(written(sample()), "\"size_x\": 7", "\"size_x\": 16000000");
  big = replaced(big, "\"size_y\": 5", "\"size_y\": 16000000");
  EXPECT_EQ(failure(big, 1000000),
            "prior/session.json: grid.size_x: 16000000 x 16000000 cells exceed the largest map "
            "(1000000)");
}

TEST(SessionState, ADirectoryIsReadThroughItsSessionJson) {
  const std::string dir = test::tempDir("session_state");
  EXPECT_EQ(test::inputError([&] { readSessionState(dir, 1000); }),
            dir + "/session.json: no session state there (a dynamap map output directory holds "
                  "session.json)");
  std::ofstream(dir + "/session.json") << written(sample());
  EXPECT_EQ(readSessionState(dir, 1000).static_cells, sample().static_cells);
  EXPECT_EQ(readSessionState(dir + "/session.json", 1000).objects.size(), 3u);
}

}  // namespace
}  // namespace dynamap
