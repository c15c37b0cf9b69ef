// The files of a run: the ROS map, the MRPT gridmaps, atomic writes and the output directory.

#include "dynamap/outputs/map_outputs.h"

#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>

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
