// The files of a run: the ROS map, the MRPT gridmaps, atomic writes and the output directory.

#include "dynamap/outputs/map_outputs.h"

#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <random>

#include "dynamap/outputs/format.h"

#include "../test_util.h"

namespace dynamap {
namespace {

namespace fs = std::filesystem;
using mrpt::poses::CPose3D;

DynamicGridMap wallMap() {
  DynamicMapOptions o;
  o.resolution = 0.1;
  DynamicGridMap m(o, {}, -1, 2, -1, 1);
  for (int k = 0; k < 20; ++k)
    m.insertObservation(*test::makeScan({1.5f}, 0.001), CPose3D(0.05, 0.05, 0, 0, 0, 0));
  return m;
}

// The rows written every scan use appendFixed: it must give printf's characters exactly, or the
// CSVs would change with the speed-up.
TEST(Format, AppendFixedWritesWhatPrintfWrites) {
  std::vector<double> values = {0.0,    -0.0,   0.0005, -0.0005, 0.0015, 2.5e-4, 1e15, -1e15,
                                1e300,  -1e300, 5e-324, 123.4565, 1704067245.123456789,
                                std::numeric_limits<double>::infinity(),
                                -std::numeric_limits<double>::infinity(),
                                std::numeric_limits<double>::quiet_NaN()};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> metres(-500.0, 500.0), exponent(-12.0, 12.0);
  for (int i = 0; i < 20000; ++i) values.push_back(metres(rng));
  for (int i = 0; i < 5000; ++i) values.push_back(metres(rng) * std::pow(10.0, exponent(rng)));
  // Exact binary ties and their neighbours (x.5 units of the last decimal): printf rounds the
  // exact value half to even; the quick path must step aside there.
  for (int i = -4000; i <= 4000; ++i) {
    const double tie = i / 1024.0;
    values.insert(values.end(), {tie, std::nextafter(tie, 1e9), std::nextafter(tie, -1e9)});
  }
  std::size_t quick = 0;
  for (const double v : values) {
    for (int decimals = 0; decimals <= 9; ++decimals) {
      std::string got = "x";
      appendFixed(got, v, decimals);
      const char format[] = {'%', '.', static_cast<char>('0' + decimals), 'f', '\0'};
      EXPECT_EQ(got, "x" + fmt(format, v)) << v << " with " << decimals << " decimals";
      std::string scaled;
      quick += appendFixedScaled(scaled, v, decimals) ? 1 : 0;
    }
  }
  // Most of a run's values (metres, seconds) take the quick path: it is what is tested above.
  EXPECT_GT(quick, values.size() * 10 * 7 / 10);
  std::string ints;
  appendInt(ints, std::size_t{18446744073709551615u});
  appendInt(ints, -42);
  EXPECT_EQ(ints, "18446744073709551615-42");
}

TEST(MapOutputs, TheRosMapIsAPgmNorthUpWithItsOrigin) {
  const std::string dir = test::tempDir("rosmap");
  const DynamicGridMap m = wallMap();
  writeRosMap(m, dir, "static");
  const std::string pgm = test::readFile(dir + "/static.pgm");
  const std::string header = "P5\n# dynamap static map\n" + std::to_string(m.getSizeX()) + " " +
                             std::to_string(m.getSizeY()) + "\n255\n";
  ASSERT_EQ(pgm.substr(0, header.size()), header);
  ASSERT_EQ(pgm.size(), header.size() + m.getSizeX() * m.getSizeY());
  const unsigned row = m.getSizeY() - 1 - static_cast<unsigned>(m.y2idx(0.05));  // first row: top
  const auto pixel = [&](double x) {
    return static_cast<unsigned char>(pgm[header.size() + row * m.getSizeX() + m.x2idx(x)]);
  };
  EXPECT_LT(pixel(1.55), 40);  // the wall: dark (P(free) low)
  EXPECT_GT(pixel(0.6), 215);  // crossed: light
  const std::string yaml = test::readFile(dir + "/static.yaml");
  EXPECT_NE(yaml.find("image: static.pgm\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("resolution: 0.1"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("origin: [-1, -1, 0.0]"), std::string::npos) << yaml;
}

TEST(MapOutputs, GridmapsReloadInMrptWithSsCellsAndDsCells) {
  const std::string dir = test::tempDir("gridmaps");
  const DynamicGridMap m = wallMap();
  writeGridmap(m, dir, "static.gridmap.gz");
  writeDynamicGridmap(m, dir, "dynamic.gridmap.gz");
  for (const char* name : {"static.gridmap.gz", "dynamic.gridmap.gz"}) {
    mrpt::io::CFileGZInputStream in(dir + "/" + name);
    mrpt::maps::COccupancyGridMap2D back;
    mrpt::serialization::archiveFrom(in) >> back;
    ASSERT_EQ(back.getSizeX(), m.getSizeX()) << name;
    ASSERT_EQ(back.getSizeY(), m.getSizeY()) << name;
    const int cx = m.x2idx(1.55), cy = m.y2idx(0.05);
    if (std::string(name) == "static.gridmap.gz") {
      EXPECT_FLOAT_EQ(back.getCell(cx, cy), m.getCell(cx, cy));
    } else {
      EXPECT_FLOAT_EQ(back.getCell(cx, cy), 1.0f - m.dynamicOccupancy(cx, cy));
    }
  }
}

TEST(MapOutputs, AFailedWriteLeavesNeitherTheFileNorItsTemporary) {
  const std::string dir = test::tempDir("atomic");
  EXPECT_THROW(writeFileAtomically(dir, "a.txt",
                                   [](std::ostream& o) {
                                     o << "half";
                                     throw std::runtime_error("disk full");
                                   }),
               std::runtime_error);
  EXPECT_TRUE(fs::is_empty(dir));
  writeFileAtomically(dir, "a.txt", [](std::ostream& o) { o << "whole"; });
  EXPECT_EQ(test::readFile(dir + "/a.txt"), "whole");
}

TEST(MapOutputs, AnOutputDirectoryThatCannotBeWrittenIsAnErrorNamingIt) {
  const std::string dir = test::tempDir("outdir");
  const std::string file = dir + "/a-file";
  writeFileAtomically(dir, "a-file", [](std::ostream& o) { o << "x"; });
  try {
    prepareOutputDir(file + "/sub");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
  }
  prepareOutputDir(dir + "/new/deeper");
  EXPECT_TRUE(fs::is_directory(dir + "/new/deeper"));
}

}  // namespace
}  // namespace dynamap
