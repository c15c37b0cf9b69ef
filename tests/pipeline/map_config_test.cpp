// MapConfig: the option tables are the one declaration of every key; config/default.ini, the
// key table of docs/configuration.md and a run's config.ini must agree with them key for key.

#include "dynamap/pipeline/mapper.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "dynamap/base/ini.h"
#include "dynamap/base/option_table.h"

namespace dynamap {
namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(MapConfig, DefaultIniHoldsExactlyTheDeclaredDefaults) {
  const IniFile ini = IniFile::fromFile(DYNAMAP_SOURCE_DIR "/config/default.ini");
  std::map<std::string, std::set<std::string>> declared;
  for (const OptionDoc& d : MapConfig::describe()) {
    declared[d.section].insert(d.key);
    ASSERT_TRUE(ini.hasKey(d.section, d.key))
        << "default.ini lacks [" << d.section << "] " << d.key;
    const std::string shipped = ini.getString(d.section, d.key, "");
    double a = 0, b = 0;
    if (parseDouble(shipped, a) && parseDouble(d.default_value, b)) {
      EXPECT_DOUBLE_EQ(a, b) << "[" << d.section << "] " << d.key;
    } else {
      EXPECT_EQ(shipped, d.default_value) << "[" << d.section << "] " << d.key;
    }
  }
  // ... and nothing else: a key dropped from a table but left in the file fails here.
  for (const std::string& section : ini.sections()) {
    for (const std::string& key : ini.keys(section)) {
      EXPECT_TRUE(declared[section].count(key)) << "[" << section << "] " << key << " undeclared";
    }
  }
}

TEST(MapConfig, ConfigurationPageHoldsTheTableOfEveryKeyAsTheTablesDeclareThem) {
  const std::string page = readFile(DYNAMAP_SOURCE_DIR "/docs/configuration.md");
  const std::string table = optionsMarkdown(MapConfig::describe());
  EXPECT_NE(page.find(table), std::string::npos)
      << "docs/configuration.md's table of keys is not `dynamap config --markdown`'s:\n"
      << table;
  for (const OptionDoc& d : MapConfig::describe()) {
    EXPECT_NE(table.find("`" + d.key + "`"), std::string::npos) << d.key;
  }
}

// Every field moved off its default, written and read back: a key the writer drops, or the
// loader ignores, comes back as its default and fails.
template <typename T>
void expectRoundTrip(const OptionTable<T>& table) {
  T changed;
  for (const Option<T>& r : table.rows()) {
    const double lo = std::isfinite(r.range.lo) ? r.range.lo : -1e3;
    const double hi = std::isfinite(r.range.hi) ? r.range.hi : 1e3;
    if (auto d = std::get_if<double T::*>(&r.member)) {
      const double v = lo + 0.3 * (hi - lo);
      changed.** d = v == changed.**d ? lo + 0.7 * (hi - lo) : v;
    } else if (auto i = std::get_if<int T::*>(&r.member)) {
      const int v = static_cast<int>(std::ceil(lo));
      changed.** i = v == changed.**i ? static_cast<int>(std::floor(hi)) : v;
    } else {
      changed.*std::get<bool T::*>(r.member) = !(changed.*std::get<bool T::*>(r.member));
    }
  }
  std::ostringstream written;
  table.write(changed, written);
  T back;
  table.load(IniFile::fromText(written.str(), "written.ini"), back);
  std::ostringstream rewritten;
  table.write(back, rewritten);
  EXPECT_EQ(rewritten.str(), written.str());
  std::ostringstream defaults;
  table.write(T{}, defaults);
  EXPECT_NE(written.str(), defaults.str());
}

TEST(MapConfig, EverySectionRoundTripsThroughItsWrittenForm) {
  expectRoundTrip(DynamicMapOptions::table());
  expectRoundTrip(InsertionOptions::table());
  expectRoundTrip(ObjectOptions::table());
  expectRoundTrip(ScanMatchOptions::table());
}

TEST(MapConfig, TheWrittenConfigurationReloadsToItself) {
  MapConfig c;
  c.poses = PoseSource::Odometry;
  c.map.resolution = 0.1;
  std::ostringstream a;
  c.writeIni(a);
  std::ostringstream b;
  MapConfig::load(IniFile::fromText(a.str(), "config.ini")).writeIni(b);
  EXPECT_EQ(a.str(), b.str());
}

}  // namespace
}  // namespace dynamap
