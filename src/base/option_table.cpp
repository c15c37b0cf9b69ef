#include "dynamap/base/option_table.h"

#include <iomanip>
#include <ostream>
#include <sstream>

namespace dynamap {

bool Range::contains(double v) const {
  if (std::isnan(v)) return false;
  const bool above = lo_open ? v > lo : v >= lo;
  const bool below = hi_open ? v < hi : v <= hi;
  return above && below;
}

std::string Range::text() const {
  std::ostringstream o;
  o << (lo_open ? "(" : "[") << lo << ", " << hi << (hi_open ? ")" : "]");
  return o.str();
}

std::string optionsMarkdown(const std::vector<OptionDoc>& docs) {
  std::ostringstream o;
  o << "| section | key | default | range | meaning |\n|---|---|---|---|---|\n";
  std::string section;
  for (const OptionDoc& d : docs) {
    o << "| " << (d.section == section ? std::string() : "`[" + d.section + "]`") << " | `" << d.key
      << "` | " << d.default_value << (d.unit.empty() ? "" : " " + d.unit) << " | " << d.range
      << " | " << d.meaning << " |\n";
    section = d.section;
  }
  return o.str();
}

namespace option_detail {

std::string formatNumber(double v) {
  std::ostringstream o;
  o << std::setprecision(10) << v;
  return o.str();
}

void rejectRange(const std::string& source, const char* section, const char* key, double value,
                 const Range& range, const char* unit, bool integer) {
  std::ostringstream m;
  m << value << " must be " << (integer ? "an integer " : "") << "in " << range.text();
  if (unit && *unit) m << " " << unit;
  rejectValue(source, section, key, m.str());
}

void writeLine(std::ostream& out, const char* key, const std::string& value, const char* unit,
               const char* meaning, int pad) {
  out << key << " = " << value << std::string(static_cast<std::size_t>(pad), ' ') << "; ";
  if (unit && *unit) out << "[" << unit << "] ";
  out << meaning << "\n";
}

}  // namespace option_detail
}  // namespace dynamap
