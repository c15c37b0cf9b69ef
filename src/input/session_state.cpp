#include "dynamap/input/session_state.h"

#include <sys/stat.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <ostream>
#include <sstream>

#include "dynamap/input/scan_source.h"

namespace dynamap {
namespace {

using nlohmann::json;

constexpr const char* kFormat = "dynamap-session";
constexpr std::uint64_t kMaxFileBytes = std::uint64_t{1} << 30;
// Coordinates and sizes beyond these are no building's: a file that says so is corrupt.
constexpr double kMaxCoordinate = 1e7, kMaxSize = 1e3;

const char* const kStates[] = {"present", "absent", "withdrawn", "relabeled", "retracted"};

const char kBase64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

// Base64 (RFC 4648, padded), on one line.
std::string encodeBase64(const std::vector<std::uint8_t>& in) {
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < in.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, in.size() - i);
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 3; ++k) v = (v << 8) | (k < n ? in[i + k] : 0u);
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? kBase64[(v >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

std::string compressCells(const std::vector<std::int8_t>& cells) {
  uLongf len = compressBound(static_cast<uLong>(cells.size()));
  std::vector<std::uint8_t> buf(len);
  if (compress2(buf.data(), &len, reinterpret_cast<const Bytef*>(cells.data()),
                static_cast<uLong>(cells.size()), 6) != Z_OK) {
    throw std::runtime_error("session state: cannot compress the grid");
  }
  buf.resize(len);
  return encodeBase64(buf);
}

// Reads what the caller checks: the file's name and the key in every message.
struct Reader {
  const std::string& name;
  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw InputError(name + ": " + key + ": " + what);
  }
  const json& at(const json& obj, const char* key, const std::string& where) const {
    const auto it = obj.find(key);
    if (it == obj.end()) fail(where + key, "missing");
    return *it;
  }
  double number(const json& obj, const char* key, const std::string& where, double lo,
                double hi) const {
    const json& v = at(obj, key, where);
    if (!v.is_number()) fail(where + key, "not a number");
    const double d = v.get<double>();
    if (!std::isfinite(d) || d < lo || d > hi) {
      fail(where + key, "out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    return d;
  }
  long integer(const json& obj, const char* key, const std::string& where, long lo,
               long hi) const {
    const json& v = at(obj, key, where);
    if (!v.is_number_integer()) fail(where + key, "not an integer");
    const long long i = v.get<long long>();
    if (i < lo || i > hi) {
      fail(where + key, "out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    return static_cast<long>(i);
  }
  std::string text(const json& obj, const char* key, const std::string& where) const {
    const json& v = at(obj, key, where);
    if (!v.is_string()) fail(where + key, "not a string");
    return v.get<std::string>();
  }
};

// Strict base64 (RFC 4648, padded; line breaks skipped): false on any other character or
// length. MRPT's decoder would do, but prints its complaints on the console.
bool decodeBase64(const std::string& text, std::vector<std::uint8_t>& out) {
  std::string in;
  for (const char c : text) {
    if (c != '\n' && c != '\r') in += c;
  }
  if (in.size() % 4 != 0) return false;
  const auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    return c == '+' ? 62 : c == '/' ? 63 : -1;
  };
  out.clear();
  out.reserve(in.size() / 4 * 3);
  for (std::size_t i = 0; i < in.size(); i += 4) {
    const bool last = i + 4 == in.size();
    const int pad = last ? (in[i + 3] == '=') + (in[i + 2] == '=' && in[i + 3] == '=') : 0;
    std::uint32_t v = 0;
    for (int k = 0; k < 4; ++k) {
      const int d = k >= 4 - pad ? 0 : value(in[i + k]);
      if (d < 0) return false;
      v = (v << 6) | static_cast<std::uint32_t>(d);
    }
    for (int k = 0; k < 3 - pad; ++k) out.push_back(static_cast<std::uint8_t>(v >> (16 - 8 * k)));
  }
  return true;
}

std::vector<std::int8_t> cellsOf(const Reader& r, const std::string& coded, std::size_t count) {
  std::vector<std::uint8_t> packed;
  if (!decodeBase64(coded, packed)) r.fail("grid.static", "not base64");
  std::vector<std::int8_t> cells(count);
  uLongf len = static_cast<uLongf>(count);
  if (uncompress(reinterpret_cast<Bytef*>(cells.data()), &len, packed.data(),
                 static_cast<uLong>(packed.size())) != Z_OK ||
      len != count) {
    r.fail("grid.static", "not " + std::to_string(count) + " zlib-compressed cells");
  }
  return cells;
}

void readGrid(const Reader& r, const json& root, std::uint64_t max_cells, SessionState& s) {
  const json& g = r.at(root, "grid", "");
  if (!g.is_object()) r.fail("grid", "not an object");
  s.resolution = r.number(g, "resolution", "grid.", 0.005, 10);
  s.x_min = r.number(g, "x_min", "grid.", -kMaxCoordinate, kMaxCoordinate);
  s.y_min = r.number(g, "y_min", "grid.", -kMaxCoordinate, kMaxCoordinate);
  constexpr long kMaxSide = 1 << 24;
  s.size_x = static_cast<unsigned>(r.integer(g, "size_x", "grid.", 1, kMaxSide));
  s.size_y = static_cast<unsigned>(r.integer(g, "size_y", "grid.", 1, kMaxSide));
  const std::uint64_t n = std::uint64_t{s.size_x} * s.size_y;
  if (n > max_cells) {
    r.fail("grid.size_x", std::to_string(s.size_x) + " x " + std::to_string(s.size_y) +
                              " cells exceed the largest map (" + std::to_string(max_cells) + ")");
  }
  s.static_cells = cellsOf(r, r.text(g, "static", "grid."), static_cast<std::size_t>(n));
}

SessionObject readObject(const Reader& r, const json& o, std::size_t index) {
  const std::string where = "objects[" + std::to_string(index) + "].";
  if (!o.is_object()) r.fail(where.substr(0, where.size() - 1), "not an object");
  SessionObject row;
  row.id = static_cast<int>(r.integer(o, "id", where, 1, std::numeric_limits<int>::max()));
  if (static_cast<std::size_t>(row.id) != index + 1) {
    r.fail(where + "id", "ids must be 1, 2, ... in order; found " + std::to_string(row.id));
  }
  row.state = r.text(o, "state", where);
  bool known = false;
  for (const char* k : kStates) known = known || row.state == k;
  if (!known) r.fail(where + "state", "unknown state '" + row.state.substr(0, 40) + "'");
  row.cx = r.number(o, "x", where, -kMaxCoordinate, kMaxCoordinate);
  row.cy = r.number(o, "y", where, -kMaxCoordinate, kMaxCoordinate);
  row.size = r.number(o, "size", where, 0, kMaxSize);
  row.n_moves = static_cast<int>(r.integer(o, "moves", where, 0, 1 << 30));
  row.first_seen_t = r.number(o, "first_seen_t", where, -1e12, 1e12);
  row.last_seen_t = r.number(o, "last_seen_t", where, -1e12, 1e12);
  return row;
}

}  // namespace

void writeSessionState(const SessionState& s, std::ostream& out) {
  if (s.static_cells.size() != std::size_t{s.size_x} * s.size_y) {
    throw std::runtime_error("session state: the grid's cells do not match its size");
  }
  json objects = json::array();
  for (const SessionObject& o : s.objects) {
    objects.push_back({{"id", o.id}, {"state", o.state}, {"x", o.cx}, {"y", o.cy},
                       {"size", o.size}, {"moves", o.n_moves},
                       {"first_seen_t", o.first_seen_t}, {"last_seen_t", o.last_seen_t}});
  }
  const json root = {
      {"format", kFormat},
      {"version", SessionState::kVersion},
      {"sessions", s.sessions},
      {"grid",
       {{"resolution", s.resolution}, {"x_min", s.x_min}, {"y_min", s.y_min},
        {"size_x", s.size_x}, {"size_y", s.size_y}, {"static", compressCells(s.static_cells)}}},
      {"objects", objects},
      {"last_pose", {{"x", s.last_x}, {"y", s.last_y}, {"phi", s.last_phi}, {"t", s.last_t}}}};
  out << root.dump(1) << "\n";
}

SessionState parseSessionState(const std::string& text, const std::string& name,
                               std::uint64_t max_cells) {
  const Reader r{name};
  const json root = json::parse(text, nullptr, false);
  if (root.is_discarded() || !root.is_object()) r.fail("(file)", "not a JSON object");
  if (r.text(root, "format", "") != kFormat) r.fail("format", "not a dynamap session state");
  r.integer(root, "version", "", SessionState::kVersion, SessionState::kVersion);
  SessionState s;
  s.sessions = static_cast<int>(r.integer(root, "sessions", "", 1, 1 << 30));
  readGrid(r, root, max_cells, s);
  const json& objects = r.at(root, "objects", "");
  if (!objects.is_array()) r.fail("objects", "not an array");
  for (std::size_t i = 0; i < objects.size(); ++i) s.objects.push_back(readObject(r, objects[i], i));
  const json& last = r.at(root, "last_pose", "");
  if (!last.is_object()) r.fail("last_pose", "not an object");
  s.last_x = r.number(last, "x", "last_pose.", -kMaxCoordinate, kMaxCoordinate);
  s.last_y = r.number(last, "y", "last_pose.", -kMaxCoordinate, kMaxCoordinate);
  s.last_phi = r.number(last, "phi", "last_pose.", -10, 10);
  s.last_t = r.number(last, "t", "last_pose.", -1e12, 1e12);
  return s;
}

SessionState readSessionState(const std::string& path, std::uint64_t max_cells) {
  struct stat st {};
  std::string file = path;
  if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) file = path + "/session.json";
  if (::stat(file.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) {
    throw InputError(file + ": no session state there (a dynamap map output directory holds "
                            "session.json)");
  }
  if (static_cast<std::uint64_t>(st.st_size) > kMaxFileBytes) {
    throw InputError(file + ": larger than 1 GiB: no session state is");
  }
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) throw InputError(file + ": cannot be read");
  return parseSessionState(text.str(), file, max_cells);
}

}  // namespace dynamap
