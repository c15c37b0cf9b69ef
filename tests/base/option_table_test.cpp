// OptionTable: one row per key drives the load, the checks and the written section.

#include "dynamap/base/option_table.h"

#include <gtest/gtest.h>

#include <sstream>

namespace dynamap {
namespace {

struct Demo {
  double length = 1.5;
  int count = 3;
  bool on = true;
};

const OptionTable<Demo>& demoTable() {
  static const OptionTable<Demo> t(
      "demo", {
                  {"length", &Demo::length, Range::openClosed(0, 10), "m", "how long"},
                  {"count", &Demo::count, Range::closed(1, 5), "", "how many", 3},
                  {"on", &Demo::on, {}, "", "whether"},
              });
  return t;
}

std::string loadError(const std::string& text, Demo& d) {
  try {
    demoTable().load(IniFile::fromText(text, "d.ini"), d);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(OptionTable, LoadsOnlyTheKeysGivenAndKeepsTheOthers) {
  Demo d;
  EXPECT_EQ(loadError("[demo]\ncount = 5\non = false\n", d), "");
  EXPECT_DOUBLE_EQ(d.length, 1.5);
  EXPECT_EQ(d.count, 5);
  EXPECT_FALSE(d.on);
}

TEST(OptionTable, EveryFaultNamesFileSectionAndKey) {
  Demo d;
  EXPECT_EQ(loadError("[demo]\nlenght = 2\n", d), "d.ini: [demo] lenght: unknown key");
  EXPECT_EQ(loadError("[demo]\nlength = 0\n", d), "d.ini: [demo] length: 0 must be in (0, 10] m");
  EXPECT_EQ(loadError("[demo]\nlength = nan\n", d).substr(0, 22), "d.ini: [demo] length: ");
  EXPECT_EQ(loadError("[demo]\ncount = 6\n", d),
            "d.ini: [demo] count: 6 must be an integer in [1, 5]");
  // An integer past int's range is judged as read, not after wrapping round into the range.
  EXPECT_EQ(loadError("[demo]\ncount = 4294967297\n", d),
            "d.ini: [demo] count: 4.29497e+09 must be an integer in [1, 5]");
  EXPECT_EQ(d.count, 3);
}

TEST(OptionTable, ValuesSetInCodeAreCheckedToo) {
  Demo d;
  d.length = 11;
  try {
    demoTable().checkRanges(d, "code");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "code: [demo] length: 11 must be in (0, 10] m");
  }
}

TEST(OptionTable, WritesAReloadableSectionWithUnitsAndMeanings) {
  Demo d;
  d.length = 2.25;
  std::ostringstream out;
  demoTable().write(d, out);
  EXPECT_EQ(out.str(),
            "[demo]\nlength = 2.25 ; [m] how long\ncount = 3   ; how many\non = true ; whether\n");
  Demo back;
  back.length = 9;
  EXPECT_EQ(loadError(out.str(), back), "");
  EXPECT_DOUBLE_EQ(back.length, 2.25);
}

TEST(OptionTable, DescribesEveryRowWithItsDefault) {
  const auto docs = demoTable().describe(Demo{});
  ASSERT_EQ(docs.size(), 3u);
  EXPECT_EQ(docs[0].key, "length");
  EXPECT_EQ(docs[0].default_value, "1.5");
  EXPECT_EQ(docs[0].range, "(0, 10]");
  EXPECT_EQ(docs[2].default_value, "true");
  EXPECT_EQ(docs[2].range, "true or false");
}

TEST(Range, EndsOpenOrClosed) {
  EXPECT_TRUE(Range::closed(0, 1).contains(0));
  EXPECT_FALSE(Range::open(0, 1).contains(0));
  EXPECT_TRUE(Range::openClosed(0, 1).contains(1));
  EXPECT_FALSE(Range::closedOpen(0, 1).contains(1));
  EXPECT_FALSE(Range::closed(0, 1).contains(std::nan("")));
  EXPECT_EQ(Range::closedOpen(0.5, 2).text(), "[0.5, 2)");
}

}  // namespace
}  // namespace dynamap
