#include "dynamap/base/ini.h"

#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace dynamap {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

std::string stripComment(const std::string& s) {
  const auto pos = s.find_first_of(";#");
  return trim(pos == std::string::npos ? s : s.substr(0, pos));
}

}  // namespace

void rejectValue(const std::string& source, const std::string& section, const std::string& key,
                 const std::string& why) {
  throw ConfigError(source + ": [" + section + "] " + key + ": " + why);
}

void requireInRange(const std::string& source, const std::string& section, const std::string& key,
                    double value, double lo, double hi, const std::string& range_text) {
  if (value >= lo && value <= hi) return;
  std::ostringstream m;
  m << value << " must be " << range_text;
  rejectValue(source, section, key, m.str());
}

bool parseDouble(const std::string& text, double& out) {
  const std::string t = trim(text);
  if (t.empty()) return false;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(t.c_str(), &end);
  if (errno != 0 || end != t.c_str() + t.size() || !std::isfinite(v)) return false;
  out = v;
  return true;
}

bool parseLong(const std::string& text, long& out) {
  const std::string t = trim(text);
  if (t.empty()) return false;
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(t.c_str(), &end, 10);
  if (errno != 0 || end != t.c_str() + t.size()) return false;
  out = v;
  return true;
}

IniFile IniFile::fromFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path + ": cannot open configuration file");
  std::stringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw ConfigError(path + ": cannot read configuration file");
  return fromText(ss.str(), path);
}

IniFile IniFile::fromText(const std::string& text, const std::string& name) {
  auto cfg = std::make_shared<mrpt::config::CConfigFileMemory>(text);
  return IniFile(cfg, name);
}

IniFile IniFile::fromMrptSection(const mrpt::config::CConfigFileBase& source,
                                 const std::string& section, const std::string& as_section) {
  std::vector<std::string> keys;
  source.getAllKeys(section, keys);
  std::ostringstream ini;
  ini << "[" << as_section << "]\n";
  for (const auto& k : keys) ini << k << " = " << source.read_string(section, k, "") << "\n";
  return fromText(ini.str(), "configuration [" + section + "]");
}

bool IniFile::hasSection(const std::string& section) const {
  return cfg_->sectionExists(section);
}

bool IniFile::hasKey(const std::string& section, const std::string& key) const {
  return cfg_->keyExists(section, key);
}

std::vector<std::string> IniFile::sections() const {
  std::vector<std::string> out;
  cfg_->getAllSections(out);
  // simpleini reports the unnamed leading section as "" when it holds keys.
  out.erase(std::remove(out.begin(), out.end(), std::string()), out.end());
  return out;
}

std::vector<std::string> IniFile::keys(const std::string& section) const {
  std::vector<std::string> out;
  cfg_->getAllKeys(section, out);
  return out;
}

std::string IniFile::where(const std::string& section, const std::string& key) const {
  std::string w = name_ + ": [" + section + "]";
  if (!key.empty()) w += " " + key;
  return w;
}

void IniFile::fail(const std::string& section, const std::string& key,
                   const std::string& what) const {
  throw ConfigError(where(section, key) + ": " + what);
}

void IniFile::requireKnownSections(const std::vector<std::string>& allowed) const {
  std::vector<std::string> all;
  cfg_->getAllSections(all);
  for (const auto& s : all) {
    if (s.empty()) {
      if (!keys("").empty()) {
        throw ConfigError(name_ + ": key '" + keys("").front() + "' stands before any [section]");
      }
      continue;
    }
    if (std::find(allowed.begin(), allowed.end(), s) == allowed.end()) {
      throw ConfigError(name_ + ": unknown section [" + s + "]");
    }
  }
}

void IniFile::requireKnownKeys(const std::string& section,
                               const std::vector<std::string>& allowed) const {
  for (const auto& k : keys(section)) {
    if (std::find(allowed.begin(), allowed.end(), k) == allowed.end()) {
      fail(section, k, "unknown key");
    }
  }
}

std::string IniFile::getString(const std::string& section, const std::string& key,
                               const std::string& fallback) const {
  if (!hasKey(section, key)) return fallback;
  return stripComment(cfg_->read_string(section, key, "", false));
}

std::string IniFile::requireString(const std::string& section, const std::string& key) const {
  if (!hasKey(section, key)) fail(section, key, "missing (required)");
  return getString(section, key, "");
}

double IniFile::getDouble(const std::string& section, const std::string& key,
                          double fallback) const {
  if (!hasKey(section, key)) return fallback;
  const std::string v = getString(section, key, "");
  double out = 0;
  if (!parseDouble(v, out)) fail(section, key, "'" + v + "' is not a number");
  return out;
}

long IniFile::getInt(const std::string& section, const std::string& key, long fallback) const {
  if (!hasKey(section, key)) return fallback;
  const std::string v = getString(section, key, "");
  long out = 0;
  if (!parseLong(v, out)) fail(section, key, "'" + v + "' is not an integer");
  return out;
}

bool IniFile::getBool(const std::string& section, const std::string& key, bool fallback) const {
  if (!hasKey(section, key)) return fallback;
  std::string v = getString(section, key, "");
  std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return std::tolower(c); });
  if (v == "true" || v == "1" || v == "yes") return true;
  if (v == "false" || v == "0" || v == "no") return false;
  fail(section, key, "'" + v + "' is not a boolean (true/false)");
}

std::vector<double> IniFile::getDoubles(const std::string& section, const std::string& key) const {
  std::istringstream in(getString(section, key, ""));
  std::vector<double> out;
  std::string tok;
  while (in >> tok) {
    double v = 0;
    if (!parseDouble(tok, v)) fail(section, key, "'" + tok + "' is not a number");
    out.push_back(v);
  }
  return out;
}

}  // namespace dynamap
