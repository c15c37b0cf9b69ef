#pragma once
// OptionTable: every key of one .ini section declared once — its name, the struct member that
// holds it, its range, its unit and its one-line meaning — and everything else derived from that
// one row: the strict load (unknown keys, malformed numbers and out-of-range values are
// ConfigError naming file, section and key), the known-key list, the range checks of values set
// in code, the section as written into a run's config.ini, and the documentation tests.
//
// A field's default is its member initializer in the options struct, so `T{}` is the default
// configuration; rules that tie two fields together stay in the struct's own validate().

#include <cmath>
#include <iosfwd>
#include <string>
#include <variant>
#include <vector>

#include "dynamap/base/ini.h"

namespace dynamap {

/// The values a number may take: from lo to hi, either end open or closed.
struct Range {
  double lo = -HUGE_VAL, hi = HUGE_VAL;
  bool lo_open = false, hi_open = false;

  static Range closed(double lo, double hi) { return {lo, hi, false, false}; }
  static Range open(double lo, double hi) { return {lo, hi, true, true}; }
  static Range openClosed(double lo, double hi) { return {lo, hi, true, false}; }
  static Range closedOpen(double lo, double hi) { return {lo, hi, false, true}; }
  /// False for NaN.
  bool contains(double v) const;
  /// "[0, 1)", "(0, 10]", ...
  std::string text() const;
};

/// One row of a table: the key `key` of the section, held in `member` of T.
template <typename T>
struct Option {
  const char* key;
  std::variant<double T::*, int T::*, bool T::*, std::string T::*> member;
  Range range;          ///< ignored for bools and strings; ints must also be whole numbers
  const char* unit;     ///< "m", "deg", "s", or "" for none
  const char* meaning;  ///< one line: the comment written after the value in config.ini
  int pad = 1;          ///< spaces between the value and the ';' of its comment in config.ini
};

/// What a row says, without the struct: for documentation and its tests.
struct OptionDoc {
  std::string section, key;
  std::string default_value;  ///< as config.ini writes it
  std::string unit, meaning, range;
};

template <typename T>
class OptionTable {
 public:
  OptionTable(const char* section, std::vector<Option<T>> rows)
      : section_(section), rows_(std::move(rows)) {}

  const char* section() const { return section_; }
  const std::vector<Option<T>>& rows() const { return rows_; }
  std::vector<std::string> keys() const;

  /// Reads the keys `ini` sets into `out` (the others keep their value), checking each range.
  /// Throws ConfigError for an unknown key, a malformed value or a value out of range.
  void load(const IniFile& ini, T& out) const;
  /// Throws ConfigError "<source>: [section] key: <value> must be in <range> <unit>" for the
  /// first field of `v` out of its range.
  void checkRanges(const T& v, const std::string& source) const;
  /// "[section]" and one "key = value ; [unit] meaning" line per row, reloadable.
  void write(const T& v, std::ostream& out) const;
  /// One OptionDoc per row, the defaults taken from `defaults`.
  std::vector<OptionDoc> describe(const T& defaults) const;

 private:
  const char* section_;
  std::vector<Option<T>> rows_;
};

/// The rows as a Markdown table (section, key, default, range, unit, meaning): the README's
/// table of configuration keys is this text, checked by a test.
std::string optionsMarkdown(const std::vector<OptionDoc>& docs);

// --- implementation (the table is a template over the options struct) --------------------------

namespace option_detail {
std::string formatNumber(double v);
/// The range error of one value: "<value> must be [an integer ]in <range>[ <unit>]".
[[noreturn]] void rejectRange(const std::string& source, const char* section, const char* key,
                              double value, const Range& range, const char* unit, bool integer);
void writeLine(std::ostream& out, const char* key, const std::string& value, const char* unit,
               const char* meaning, int pad);
}  // namespace option_detail

template <typename T>
std::vector<std::string> OptionTable<T>::keys() const {
  std::vector<std::string> k;
  for (const Option<T>& r : rows_) k.emplace_back(r.key);
  return k;
}

template <typename T>
void OptionTable<T>::load(const IniFile& ini, T& out) const {
  ini.requireKnownKeys(section_, keys());
  for (const Option<T>& r : rows_) {
    if (!ini.hasKey(section_, r.key)) continue;
    if (auto d = std::get_if<double T::*>(&r.member)) {
      out.** d = ini.getDouble(section_, r.key, out.**d);
    } else if (auto i = std::get_if<int T::*>(&r.member)) {
      // Checked as the long it was read as: a value past int's range must not wrap into it.
      const long v = ini.getInt(section_, r.key, out.**i);
      if (!r.range.contains(static_cast<double>(v)))
        option_detail::rejectRange(ini.name(), section_, r.key, static_cast<double>(v), r.range,
                                   r.unit, true);
      out.** i = static_cast<int>(v);
    } else if (auto str = std::get_if<std::string T::*>(&r.member)) {
      out.**str = ini.getString(section_, r.key, out.**str);
    } else {
      out.*std::get<bool T::*>(r.member) =
          ini.getBool(section_, r.key, out.*std::get<bool T::*>(r.member));
    }
  }
  checkRanges(out, ini.name());
}

template <typename T>
void OptionTable<T>::checkRanges(const T& v, const std::string& source) const {
  for (const Option<T>& r : rows_) {
    if (auto d = std::get_if<double T::*>(&r.member)) {
      if (!r.range.contains(v.**d))
        option_detail::rejectRange(source, section_, r.key, v.**d, r.range, r.unit, false);
    } else if (auto i = std::get_if<int T::*>(&r.member)) {
      if (!r.range.contains(v.**i))
        option_detail::rejectRange(source, section_, r.key, v.**i, r.range, r.unit, true);
    }
  }
}

template <typename T>
void OptionTable<T>::write(const T& v, std::ostream& out) const {
  out << "[" << section_ << "]\n";
  for (const Option<T>& r : rows_) {
    std::string value;
    if (auto d = std::get_if<double T::*>(&r.member)) {
      value = option_detail::formatNumber(v.**d);
    } else if (auto i = std::get_if<int T::*>(&r.member)) {
      value = std::to_string(v.**i);
    } else if (auto str = std::get_if<std::string T::*>(&r.member)) {
      value = v.**str;
    } else {
      value = v.*std::get<bool T::*>(r.member) ? "true" : "false";
    }
    option_detail::writeLine(out, r.key, value, r.unit, r.meaning, r.pad);
  }
}

template <typename T>
std::vector<OptionDoc> OptionTable<T>::describe(const T& defaults) const {
  std::vector<OptionDoc> docs;
  for (const Option<T>& r : rows_) {
    OptionDoc d{section_, r.key, "", r.unit, r.meaning, r.range.text()};
    if (auto p = std::get_if<double T::*>(&r.member)) {
      d.default_value = option_detail::formatNumber(defaults.**p);
    } else if (auto i = std::get_if<int T::*>(&r.member)) {
      d.default_value = std::to_string(defaults.**i);
    } else if (auto str = std::get_if<std::string T::*>(&r.member)) {
      d.default_value = defaults.**str;
      d.range = "text";
    } else {
      d.default_value = defaults.*std::get<bool T::*>(r.member) ? "true" : "false";
      d.range = "true or false";
    }
    docs.push_back(std::move(d));
  }
  return docs;
}

}  // namespace dynamap
