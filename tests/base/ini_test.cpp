// IniFile: strict, typed reading with errors that name file, section and key.

#include "dynamap/base/ini.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>

namespace dynamap {
namespace {

IniFile ini(const std::string& text) {
  return IniFile::fromText(text, "test.ini");
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(IniFile, ReadsTypedValuesAndStripsTrailingComments) {
  const IniFile f = ini("[a]\nx = 1.5   ; metres\nn = 7 # count\nb = true\nlist = 0 -3  3 0\n");
  EXPECT_DOUBLE_EQ(f.getDouble("a", "x", 0), 1.5);
  EXPECT_EQ(f.getInt("a", "n", 0), 7);
  EXPECT_TRUE(f.getBool("a", "b", false));
  EXPECT_EQ(f.getDoubles("a", "list"), (std::vector<double>{0, -3, 3, 0}));
  EXPECT_DOUBLE_EQ(f.getDouble("a", "missing", 4.25), 4.25);
}

TEST(IniFile, MalformedValuesNameFileSectionAndKey) {
  const IniFile f = ini("[a]\nx = 1.5m\nn = 2.5\nb = maybe\nlist = 1 two\n");
  EXPECT_EQ(errorOf([&] { f.getDouble("a", "x", 0); }), "test.ini: [a] x: '1.5m' is not a number");
  EXPECT_EQ(errorOf([&] { f.getInt("a", "n", 0); }), "test.ini: [a] n: '2.5' is not an integer");
  EXPECT_EQ(errorOf([&] { f.getBool("a", "b", false); }),
            "test.ini: [a] b: 'maybe' is not a boolean (true/false)");
  EXPECT_EQ(errorOf([&] { f.getDoubles("a", "list"); }),
            "test.ini: [a] list: 'two' is not a number");
}

TEST(IniFile, UnknownKeysAndSectionsAreErrors) {
  const IniFile f = ini("[a]\nresolutoin = 0.05\n[b]\n");
  EXPECT_EQ(errorOf([&] { f.requireKnownKeys("a", {"resolution"}); }),
            "test.ini: [a] resolutoin: unknown key");
  EXPECT_EQ(errorOf([&] { f.requireKnownSections({"a"}); }), "test.ini: unknown section [b]");
  EXPECT_EQ(errorOf([&] { f.requireString("a", "name"); }),
            "test.ini: [a] name: missing (required)");
}

TEST(IniFile, AMissingFileIsAnErrorNamingIt) {
  EXPECT_EQ(errorOf([] { IniFile::fromFile("/nonexistent/x.ini"); }),
            "/nonexistent/x.ini: cannot open configuration file");
}

TEST(IniFile, EveryLineIsBlankACommentASectionOrAKeyValue) {
  EXPECT_EQ(errorOf([] { ini("[a]\nresolution 0.05\n"); }),
            "test.ini:2: expected 'key = value' or '[section]'");
  EXPECT_EQ(errorOf([] { ini("[a\nx = 1\n"); }), "test.ini:1: a section header must end with ']'");
  EXPECT_EQ(errorOf([] { ini("[a]\n = 1\n"); }), "test.ini:2: a value without a key");
  EXPECT_EQ(errorOf([] { ini("; fine\n# fine\n\n[a]\nx = 1 ; fine\n"); }), "");
}

TEST(IniFile, AKeyGivenTwiceIsAnErrorNotASilentOverride) {
  EXPECT_EQ(errorOf([] { ini("[a]\nx = 1\n[b]\nx = 2\n[a]\nx = 3\n"); }),
            "test.ini:6: [a] x: given twice (first on line 2)");
}

TEST(IniFile, ValuesAreLiteralMrptExpansionsAreRefused) {
  for (const char* text : {"[a]\nx = ${HOME}\n", "[a]\nx = $env{HOME}\n", "[a]\nx = $eval{1+1}\n",
                           "[a]\nx = 1 ; MRPT expands $eval{ even in a comment\n",
                           "#define X 1\n[a]\nx = 1\n", "@include other.ini\n"}) {
    EXPECT_NE(errorOf([&] { ini(text); }).find("not supported: values are literal"),
              std::string::npos)
        << text;
  }
}

TEST(IniFile, BinariesDirectoriesAndEndlessFilesAreRefusedByName) {
  EXPECT_EQ(errorOf([] { ini(std::string("[a]\nx = 1\0\x01\n", 11)); }),
            "test.ini:2: not a text file");
  const std::string dir = std::filesystem::temp_directory_path().string();
  EXPECT_EQ(errorOf([&] { IniFile::fromFile(dir); }),
            dir + ": is a directory, not a configuration file");
  EXPECT_EQ(errorOf([] { IniFile::fromFile("/dev/zero"); }),
            "/dev/zero: larger than 1 MiB: not a configuration file");
}

TEST(ParseNumbers, TheWholeTextMustBeTheNumber) {
  double d = 0;
  long l = 0;
  EXPECT_TRUE(parseDouble(" -2.5e1 ", d));
  EXPECT_DOUBLE_EQ(d, -25);
  EXPECT_FALSE(parseDouble("", d));
  EXPECT_FALSE(parseDouble("nan", d));
  EXPECT_FALSE(parseDouble("1,5", d));
  EXPECT_TRUE(parseLong("42", l));
  EXPECT_EQ(l, 42);
  EXPECT_FALSE(parseLong("42x", l));
}

}  // namespace
}  // namespace dynamap
