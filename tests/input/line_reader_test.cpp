// LineReader: lines of plain and gz files, each capped, and a damaged gz stream a fault at the
// last good line with nothing read twice.

#include "dynamap/input/line_reader.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <fstream>
#include <string>
#include <vector>

#include "../test_util.h"
#include "dynamap/input/scan_source.h"

namespace dynamap {
namespace {

std::string gzipped(const std::string& text) {
  z_stream z{};
  EXPECT_EQ(deflateInit2(&z, 9, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY), Z_OK);
  std::string out(deflateBound(&z, text.size()), '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(text.data()));
  z.avail_in = static_cast<uInt>(text.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  EXPECT_EQ(deflate(&z, Z_FINISH), Z_STREAM_END);
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

void writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

// Every line of `path`, and the error that ended it (empty when none).
std::vector<std::string> readLines(const std::string& path, std::string& error,
                                   std::size_t cap = LineReader::kMaxLineBytes) {
  std::vector<std::string> lines;
  try {
    LineReader in(path, cap);
    for (std::string l; in.next(l);) lines.push_back(l);
  } catch (const InputError& e) {
    error = e.what();
  }
  return lines;
}

// 20,000 numbered lines: far more than one read block, compressed or not.
std::string numberedLines() {
  std::string t;
  for (int i = 1; i <= 20000; ++i) t += "line " + std::to_string(i) + "\r\n";
  return t;
}

TEST(LineReader, PlainAndGzFilesGiveTheSameLines) {
  const std::string dir = test::tempDir("lines");
  writeFile(dir + "/a.txt", numberedLines() + "last without newline");
  writeFile(dir + "/a.txt.gz", gzipped(numberedLines() + "last without newline"));
  for (const char* name : {"/a.txt", "/a.txt.gz"}) {
    std::string error;
    const auto lines = readLines(dir + name, error);
    EXPECT_EQ(error, "") << name;
    ASSERT_EQ(lines.size(), 20001u) << name;
    EXPECT_EQ(lines[0], "line 1");  // '\r' dropped
    EXPECT_EQ(lines[19999], "line 20000");
    EXPECT_EQ(lines[20000], "last without newline");
  }
}

TEST(LineReader, SkipEmptyLinesCountsThemAsLinesAcrossBlocks) {
  const std::string dir = test::tempDir("lines");
  // 200,000 empty lines: several read blocks, plain and compressed.
  const std::string text = "first\n" + std::string(200000, '\n') + "last\n\n";
  writeFile(dir + "/plain.txt", text);
  writeFile(dir + "/packed.txt.gz", gzipped(text));
  for (const char* name : {"/plain.txt", "/packed.txt.gz"}) {
    LineReader in(dir + name);
    std::string line;
    EXPECT_EQ(in.skipEmptyLines(), 0u);  // "first" is no empty line
    ASSERT_TRUE(in.next(line));
    EXPECT_EQ(line, "first");
    EXPECT_EQ(in.skipEmptyLines(), 200000u);
    EXPECT_EQ(in.lineNumber(), 200001u);
    ASSERT_TRUE(in.next(line));
    EXPECT_EQ(line, "last");
    EXPECT_EQ(in.lineNumber(), 200002u);
    EXPECT_EQ(in.skipEmptyLines(), 1u);
    EXPECT_EQ(in.skipEmptyLines(), 0u);
    EXPECT_FALSE(in.next(line));
    EXPECT_EQ(in.position(), text.size());
  }
}

TEST(LineReader, ALineOverTheCapIsAnErrorNamingIt) {
  const std::string dir = test::tempDir("lines");
  writeFile(dir + "/long.txt", "short\n" + std::string(5000, 'x') + "\nnever read\n");
  std::string error;
  const auto lines = readLines(dir + "/long.txt", error, 4096);
  EXPECT_EQ(lines.size(), 1u);
  EXPECT_EQ(error, dir + "/long.txt:2: line longer than 4096 bytes");
  error.clear();
  readLines("/dev/zero", error);
  EXPECT_EQ(error, "/dev/zero:1: line longer than 1048576 bytes");
}

TEST(LineReader, DevNullIsEmptyAndADirectoryOrAMissingFileIsAnError) {
  std::string error;
  EXPECT_TRUE(readLines("/dev/null", error).empty());
  EXPECT_EQ(error, "");
  readLines("/", error);
  EXPECT_EQ(error, "/: is a directory");
  error.clear();
  readLines("/nonexistent/x.txt", error);
  EXPECT_EQ(error, "/nonexistent/x.txt: cannot open (No such file or directory)");
}

// A damaged CRC once replayed the last block's bytes after the end (923 scans of a 910-scan
// log): every line inflated comes once, then the fault at the last complete line.
TEST(LineReader, ADamagedCrcIsAFaultAfterTheLastLineNothingReadTwice) {
  const std::string dir = test::tempDir("lines");
  std::string gz = gzipped(numberedLines());
  gz[gz.size() - 6] ^= 0x55;  // the CRC-32 of the trailer
  writeFile(dir + "/crc.gz", gz);
  std::string error;
  const auto lines = readLines(dir + "/crc.gz", error);
  ASSERT_EQ(lines.size(), 20000u);
  EXPECT_EQ(lines.back(), "line 20000");
  EXPECT_EQ(error, dir + "/crc.gz: read error after line 20000: incorrect data check");
}

TEST(LineReader, AGzStreamCutShortDropsThePartialLine) {
  const std::string dir = test::tempDir("lines");
  const std::string gz = gzipped(numberedLines());
  writeFile(dir + "/cut.gz", gz.substr(0, gz.size() / 2));
  std::string error;
  const auto lines = readLines(dir + "/cut.gz", error);
  ASSERT_GT(lines.size(), 1000u);
  ASSERT_LT(lines.size(), 20000u);
  // Every line returned is whole and in order; the error names the last of them.
  EXPECT_EQ(lines.back(), "line " + std::to_string(lines.size()));
  EXPECT_EQ(error, dir + "/cut.gz: read error after line " + std::to_string(lines.size()) +
                       ": unexpected end of file");
}

}  // namespace
}  // namespace dynamap
