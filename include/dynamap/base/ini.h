#pragma once
// Strict reading of .ini files: every key is known, every value well formed and in range, and
// every error names the file, the section and the key. MRPT's own loaders accept misspelled keys
// and malformed numbers silently; everything dynamap reads goes through IniFile instead.

#include <mrpt/config/CConfigFileBase.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace dynamap {

/// Any problem with a configuration or scenario file. The message names file, section and key.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// An ini file (on disk or in memory) with strict, typed accessors.
/// Values may carry a trailing comment introduced by ';' or '#'. Every line must be blank, a
/// comment, a [section] or key = value; a key given twice in a section, a binary file, a file over
/// kMaxFileBytes and MRPT's own ${VAR} / $env{} / $eval{} / #define / @include are ConfigErrors
/// naming the file and line: values are taken literally.
class IniFile {
 public:
  /// The largest configuration or scenario file read [bytes].
  static constexpr std::size_t kMaxFileBytes = std::size_t{1} << 20;

  /// Loads `path`; throws ConfigError when it is missing or unreadable.
  static IniFile fromFile(const std::string& path);
  /// Parses `text`; `name` stands for the file in error messages.
  static IniFile fromText(const std::string& text, const std::string& name);
  /// Section `section` of an MRPT configuration, renamed `as_section`: how the options structs'
  /// MRPT-style loadFromConfigFile() goes through the same strict checks as an ini file.
  static IniFile fromMrptSection(const mrpt::config::CConfigFileBase& source,
                                 const std::string& section, const std::string& as_section);

  const std::string& name() const { return name_; }
  const mrpt::config::CConfigFileBase& mrptConfig() const { return *cfg_; }

  bool hasSection(const std::string& section) const;
  bool hasKey(const std::string& section, const std::string& key) const;
  std::vector<std::string> sections() const;
  std::vector<std::string> keys(const std::string& section) const;

  /// Throws ConfigError naming the first section not in `allowed`.
  void requireKnownSections(const std::vector<std::string>& allowed) const;
  /// Throws ConfigError naming the first key of `section` not in `allowed`.
  void requireKnownKeys(const std::string& section, const std::vector<std::string>& allowed) const;

  /// The value with any trailing comment and surrounding blanks removed; `fallback` if absent.
  std::string getString(const std::string& section, const std::string& key,
                        const std::string& fallback) const;
  /// Throws ConfigError if the key is absent.
  std::string requireString(const std::string& section, const std::string& key) const;
  double getDouble(const std::string& section, const std::string& key, double fallback) const;
  long getInt(const std::string& section, const std::string& key, long fallback) const;
  bool getBool(const std::string& section, const std::string& key, bool fallback) const;
  /// A whitespace-separated list of numbers (e.g. "0 -3  3 0").
  std::vector<double> getDoubles(const std::string& section, const std::string& key) const;

  /// "<file>: [section] key: what" — the one format every config error uses.
  std::string where(const std::string& section, const std::string& key) const;
  [[noreturn]] void fail(const std::string& section, const std::string& key,
                         const std::string& what) const;

 private:
  IniFile(std::shared_ptr<mrpt::config::CConfigFileBase> cfg, std::string name)
      : cfg_(std::move(cfg)), name_(std::move(name)) {}
  std::shared_ptr<mrpt::config::CConfigFileBase> cfg_;
  std::string name_;
};

/// Throws ConfigError "<source>: [section] key: why" — for checks on values already loaded.
[[noreturn]] void rejectValue(const std::string& source, const std::string& section,
                              const std::string& key, const std::string& why);
/// Throws unless lo <= value <= hi: "<source>: [section] key: <value> must be <range_text>".
void requireInRange(const std::string& source, const std::string& section, const std::string& key,
                    double value, double lo, double hi, const std::string& range_text);

/// Strict number parsing shared by every reader: the whole text must be the number.
bool parseDouble(const std::string& text, double& out);
bool parseLong(const std::string& text, long& out);
/// `s` without the blanks (space, tab, CR, LF) at either end.
std::string trim(const std::string& s);

}  // namespace dynamap
