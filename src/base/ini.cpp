#include "dynamap/base/ini.h"

#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace dynamap {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

namespace {

std::string stripComment(const std::string& s) {
  const auto pos = s.find_first_of(";#");
  return trim(pos == std::string::npos ? s : s.substr(0, pos));
}

[[noreturn]] void failLine(const std::string& name, std::size_t line, const std::string& what) {
  throw ConfigError(name + ":" + std::to_string(line) + ": " + what);
}

// MRPT's reader expands ${VAR}, $env{VAR} and $eval{...} and obeys #define and @include: a
// configuration would then depend on the environment and could read other files. dynamap takes
// every value literally, so such a line is refused instead of silently meaning something else.
bool hasMrptDirective(const std::string& line) {
  const std::string t = trim(line);
  for (const char* d : {"#define", "#undef", "#if", "#else", "#endif", "@include"}) {
    if (t.rfind(d, 0) == 0) return true;
  }
  // MRPT expands them anywhere on the line, comments included.
  return t.find("${") != std::string::npos || t.find("$env{") != std::string::npos ||
         t.find("$eval{") != std::string::npos;
}

// One line of an ini file: blank, a comment, [section] or key = value. Records keys per section
// to refuse a key given twice (the later value would silently win).
void checkLine(const std::string& name, std::size_t n, const std::string& raw, std::string& section,
               std::map<std::string, std::size_t>& first_seen) {
  for (const char c : raw) {
    const auto u = static_cast<unsigned char>(c);
    if (u == 0 || (u < 0x20 && c != '\t' && c != '\r')) failLine(name, n, "not a text file");
  }
  if (hasMrptDirective(raw)) {
    failLine(name, n, "variables, #define and @include are not supported: values are literal");
  }
  const std::string t = trim(raw);
  if (t.empty() || t[0] == ';' || t[0] == '#') return;
  if (t[0] == '[') {
    if (t.back() != ']') failLine(name, n, "a section header must end with ']'");
    section = trim(t.substr(1, t.size() - 2));
    return;
  }
  const auto eq = t.find('=');
  if (eq == std::string::npos) failLine(name, n, "expected 'key = value' or '[section]'");
  const std::string key = trim(t.substr(0, eq));
  if (key.empty()) failLine(name, n, "a value without a key");
  const auto [it, fresh] = first_seen.emplace(section + "\n" + key, n);
  if (!fresh) {
    failLine(name, n,
             "[" + section + "] " + key + ": given twice (first on line " +
                 std::to_string(it->second) + ")");
  }
}

// Every line of `text` well formed, before MRPT's lenient parser sees it.
void checkIniText(const std::string& text, const std::string& name) {
  std::istringstream in(text);
  std::string section;
  std::map<std::string, std::size_t> first_seen;
  std::size_t n = 0;
  for (std::string line; std::getline(in, line);) checkLine(name, ++n, line, section, first_seen);
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
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw ConfigError(path + ": is a directory, not a configuration file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path + ": cannot open configuration file");
  // Read at most one byte past the cap: a configuration is small, /dev/zero is not.
  std::string text(kMaxFileBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) throw ConfigError(path + ": cannot read configuration file");
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > kMaxFileBytes) {
    throw ConfigError(path + ": larger than " + std::to_string(kMaxFileBytes >> 20) +
                      " MiB: not a configuration file");
  }
  return fromText(text, path);
}

IniFile IniFile::fromText(const std::string& text, const std::string& name) {
  checkIniText(text, name);
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
