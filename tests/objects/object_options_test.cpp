// The [objects] section: strict load and a written section that reloads.

#include "dynamap/objects/object_options.h"

#include <gtest/gtest.h>

#include <sstream>

#include "dynamap/base/ini.h"

namespace dynamap {
namespace {

TEST(ObjectOptions, StrictLoadNamesKeyAndFile) {
  ObjectOptions o;
  EXPECT_NO_THROW(o.load(IniFile::fromText("[objects]\nmin_cells = 3\n", "a.ini")));
  EXPECT_EQ(o.min_cells, 3);
  try {
    o.load(IniFile::fromText("[objects]\nmin_cell = 3\n", "a.ini"));
    FAIL() << "unknown key accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("min_cell"), std::string::npos);
  }
  try {
    o.load(IniFile::fromText("[objects]\nmin_size = 2\nmax_size = 1\n", "b.ini"));
    FAIL() << "min_size above max_size accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("b.ini: [objects] min_size"), std::string::npos);
  }
  try {
    ObjectOptions{}.load(IniFile::fromText("[objects]\nreport_scans = 11\n", "c.ini"));
    FAIL() << "report_scans above confirm_scans accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("c.ini: [objects] report_scans"), std::string::npos);
  }
}

TEST(ObjectOptions, WriteIniReloads) {
  ObjectOptions o;
  o.join_distance = 0.2;
  o.enabled = false;
  std::ostringstream out;
  o.writeIni(out);
  ObjectOptions back;
  back.load(IniFile::fromText(out.str(), "written"));
  EXPECT_DOUBLE_EQ(back.join_distance, 0.2);
  EXPECT_FALSE(back.enabled);
}

}  // namespace
}  // namespace dynamap
