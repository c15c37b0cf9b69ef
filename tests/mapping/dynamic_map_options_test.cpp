// [dynamic_map], [insertion] and [input]: every validation rule fires and names its key.

#include "dynamap/mapping/dynamic_map_options.h"

#include <gtest/gtest.h>

#include <sstream>

#include "dynamap/base/ini.h"
#include "dynamap/pipeline/mapper.h"

namespace dynamap {
namespace {

std::string loadError(const std::string& text) {
  try {
    MapConfig::load(IniFile::fromText(text, "my.ini"));
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

void expectError(const std::string& text, const std::string& starts) {
  const std::string e = loadError(text);
  EXPECT_EQ(e.substr(0, starts.size()), starts) << "for: " << text << "\ngot: " << e;
}

TEST(MapOptions, DefaultsAreThePapersAndLoadFromTheShippedFile) {
  const MapConfig c = MapConfig::load(IniFile::fromFile(DYNAMAP_SOURCE_DIR "/config/default.ini"));
  EXPECT_DOUBLE_EQ(c.map.free_threshold, 0.1);
  EXPECT_DOUBLE_EQ(c.map.object_threshold, 0.85);
  EXPECT_DOUBLE_EQ(c.map.resolution, 0.05);
  const DynamicMapOptions d;
  EXPECT_DOUBLE_EQ(c.map.d_hit_free, d.d_hit_free);
  EXPECT_DOUBLE_EQ(c.insertion.max_distance_insertion, 15.0);
  EXPECT_EQ(c.poses, PoseSource::Auto);
}

TEST(MapOptions, EffectiveConfigReloadsToTheSameValues) {
  MapConfig c;
  c.map.resolution = 0.1;
  c.map.d_hit_free = 0.7;
  c.insertion.invalid_ranges_as_free = false;
  c.poses = PoseSource::Odometry;
  std::ostringstream out;
  c.writeIni(out);
  const MapConfig back = MapConfig::load(IniFile::fromText(out.str(), "dumped.ini"));
  EXPECT_DOUBLE_EQ(back.map.resolution, 0.1);
  EXPECT_DOUBLE_EQ(back.map.d_hit_free, 0.7);
  EXPECT_FALSE(back.insertion.invalid_ranges_as_free);
  EXPECT_EQ(back.poses, PoseSource::Odometry);
}

TEST(MapOptions, HighsMustBeAboveHalfAndLowsBelow) {
  for (const char* key : {"s_hit_notfree", "d_hit_free"}) {
    expectError(std::string("[dynamic_map]\n") + key + " = 0.4\n",
                std::string("my.ini: [dynamic_map] ") + key + ": 0.4 must be in (0.5, 1)");
    expectError(std::string("[dynamic_map]\n") + key + " = 1\n",
                std::string("my.ini: [dynamic_map] ") + key + ": 1 must be in (0.5, 1)");
  }
  for (const char* key : {"s_hit_free", "s_miss", "d_hit_notfree", "d_miss"}) {
    expectError(std::string("[dynamic_map]\n") + key + " = 0.6\n",
                std::string("my.ini: [dynamic_map] ") + key + ": 0.6 must be in (0, 0.5)");
    expectError(std::string("[dynamic_map]\n") + key + " = 0\n",
                std::string("my.ini: [dynamic_map] ") + key + ": 0 must be in (0, 0.5)");
  }
  expectError("[dynamic_map]\ns_miss = 0.499\n",
              "my.ini: [dynamic_map] s_miss: 0.499 is too close to 0.5");
}

TEST(MapOptions, ThresholdsAreInTheOpenUnitIntervalAndOrdered) {
  expectError("[dynamic_map]\nfree_threshold = 0\n",
              "my.ini: [dynamic_map] free_threshold: 0 must be in (0, 1)");
  expectError("[dynamic_map]\nobject_threshold = 1.2\n",
              "my.ini: [dynamic_map] object_threshold: 1.2 must be in (0, 1)");
  expectError("[dynamic_map]\nfree_threshold = 0.9\nobject_threshold = 0.8\n",
              "my.ini: [dynamic_map] free_threshold: must be below object_threshold");
  expectError("[dynamic_map]\nd_max = 0.8\n",
              "my.ini: [dynamic_map] d_max: must be above object_threshold");
  expectError("[dynamic_map]\nd_min = 0.9\n",
              "my.ini: [dynamic_map] d_min: must be below object_threshold");
}

TEST(MapOptions, ResolutionMustBePositive) {
  expectError("[dynamic_map]\nresolution = 0\n",
              "my.ini: [dynamic_map] resolution: 0 must be in [0.005, 10] m");
  expectError("[dynamic_map]\nresolution = -0.05\n",
              "my.ini: [dynamic_map] resolution: -0.05 must be in [0.005, 10] m");
  expectError("[dynamic_map]\nresolution = 0.001\n",
              "my.ini: [dynamic_map] resolution: 0.001 must be in [0.005, 10] m");
  expectError("[dynamic_map]\nmax_map_size_m = 0.5\n",
              "my.ini: [dynamic_map] max_map_size_m: 0.5 must be in [1, 10000] m");
  // Checked before it is narrowed to an int: 2^32 + 1 must not wrap round to 1.
  expectError("[dynamic_map]\nwall_guard_cells = 4294967297\n",
              "my.ini: [dynamic_map] wall_guard_cells: 4.29497e+09 must be an integer in [0, 3]");
  expectError("[dynamic_map]\nwall_guard_cells = 5\n",
              "my.ini: [dynamic_map] wall_guard_cells: 5 must be an integer in [0, 3]");
  expectError("[dynamic_map]\nwall_guard_cells = 1.5\n",
              "my.ini: [dynamic_map] wall_guard_cells: '1.5' is not an integer");
}

TEST(MapOptions, UnknownOrMisspelledKeysAndSectionsAreErrors) {
  expectError("[dynamic_map]\nobject_treshold = 0.8\n",
              "my.ini: [dynamic_map] object_treshold: unknown key");
  expectError("[insertion]\nmaxDistanceInsertion = 10\n",
              "my.ini: [insertion] maxDistanceInsertion: unknown key");
  expectError("[dynamic-map]\nresolution = 0.1\n", "my.ini: unknown section [dynamic-map]");
  expectError("[input]\nposes = gps\n", "my.ini: [input] poses: unknown pose source 'gps'");
  expectError("[dynamic_map]\nresolution = fine\n",
              "my.ini: [dynamic_map] resolution: 'fine' is not a number");
}

TEST(MapOptions, InsertionOptionsAreValidated) {
  expectError("[insertion]\nmax_distance_insertion = 0\n",
              "my.ini: [insertion] max_distance_insertion: 0 must be in (0, 1000] m");
  expectError("[insertion]\nhorizontal_tolerance_deg = -1\n",
              "my.ini: [insertion] horizontal_tolerance_deg: -1 must be in [0, 90] deg");
  expectError("[insertion]\ninvalid_ranges_as_free = sometimes\n",
              "my.ini: [insertion] invalid_ranges_as_free: 'sometimes' is not a boolean");
}

}  // namespace
}  // namespace dynamap
