// [people]: every key loads, every rule rejects with the file, section and key named.

#include "dynamap/people/people_options.h"

#include <gtest/gtest.h>

#include <sstream>

#include "dynamap/base/ini.h"

namespace dynamap {
namespace {

PeopleOptions load(const std::string& body) {
  PeopleOptions o;
  o.load(IniFile::fromText("[people]\n" + body, "p.ini"));
  return o;
}

std::string errorOf(const std::string& body) {
  try {
    load(body);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(PeopleOptions, WrittenSectionReloadsToTheSameValues) {
  PeopleOptions o;
  o.gate = 0.7;
  o.confirm_s = 4.5;
  o.enabled = false;
  std::ostringstream out;
  o.writeIni(out);
  PeopleOptions back;
  back.load(IniFile::fromText(out.str(), "w.ini"));
  EXPECT_EQ(back.gate, 0.7);
  EXPECT_EQ(back.confirm_s, 4.5);
  EXPECT_FALSE(back.enabled);
  EXPECT_EQ(back.empty_scans, o.empty_scans);
}

TEST(PeopleOptions, EveryRuleNamesItsKey) {
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"cluster_distance = 0", "cluster_distance"},
      {"cluster_distance = 1.5", "cluster_distance"},
      {"min_points = 0", "min_points"},
      {"min_points = 101", "min_points"},
      {"max_leg_width = 0", "max_leg_width"},
      {"max_person_width = 0.1", "max_person_width"},  // below max_leg_width
      {"max_person_width = 6", "max_person_width"},
      {"leg_pair_distance = -0.1", "leg_pair_distance"},
      {"wall_guard_cells = 6", "wall_guard_cells"},
      {"gate = 0", "gate"},
      {"gate = 5.5", "gate"},
      {"accel_std = 0", "accel_std"},
      {"measurement_std = 0", "measurement_std"},
      {"confirm_s = -1", "confirm_s"},
      {"moving_speed = 11", "moving_speed"},
      {"confirm_travel = -1", "confirm_travel"},
      {"tentative_miss_s = 0", "tentative_miss_s"},
      {"coast_s = 0", "coast_s"},
      {"hold_radius = 3", "hold_radius"},
      {"empty_scans = 0", "empty_scans"},
      {"exclusion_radius = -1", "exclusion_radius"},
      {"object_max_extent = 11", "object_max_extent"},
      {"lost_s = -1", "lost_s"},
      {"lost_s = 3601", "lost_s"},
      {"reid_distance = 101", "reid_distance"},
      {"max_speed = 0", "max_speed"},
      {"reacquire_s = 0.7", "reacquire_s"},          // above confirm_s
      {"reacquire_travel = 0.6", "reacquire_travel"},  // above confirm_travel
      {"reacquire_travel = -0.1", "reacquire_travel"},
      {"reacquire_unseen_speed = 2.5", "reacquire_unseen_speed"},  // above max_speed
      {"reacquire_unseen_speed = -0.1", "reacquire_unseen_speed"},
      {"gate = fast", "gate"},
      {"enabled = maybe", "enabled"},
      {"gait = 1", "gait"},
  };
  for (const auto& [line, key] : bad) {
    const std::string e = errorOf(line + "\n");
    EXPECT_NE(e.find("p.ini"), std::string::npos) << line << ": " << e;
    EXPECT_NE(e.find("[people] " + key), std::string::npos) << line << ": " << e;
  }
}

TEST(PeopleOptions, DefaultsValidate) {
  EXPECT_NO_THROW(PeopleOptions{}.validate("x"));
  EXPECT_EQ(errorOf(""), "");
}

}  // namespace
}  // namespace dynamap
