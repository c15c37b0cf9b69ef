// The layout's own rules, checked on the sources: every function fits on a screen (60 lines) and
// no header includes itself through others. (That no layer includes a layer above it is checked
// by the build itself: each layer compiles against a view of its own and its lower layers'
// headers only.)

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace dynamap {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kMaxFunctionLines = 60;

std::vector<fs::path> sources(const std::vector<std::string>& roots) {
  std::vector<fs::path> files;
  for (const std::string& r : roots) {
    for (const auto& e : fs::recursive_directory_iterator(fs::path(DYNAMAP_SOURCE_DIR) / r)) {
      const std::string ext = e.path().extension().string();
      if (e.is_regular_file() && (ext == ".h" || ext == ".cpp")) files.push_back(e.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

// The text with comments, string and character literals blanked (newlines kept).
std::string codeOnly(const std::string& text) {
  std::string out = text;
  enum { Code, Line, Block, Str, Chr } st = Code;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const char c = out[i], n = i + 1 < out.size() ? out[i + 1] : '\0';
    if (st == Code) {
      if (c == '/' && n == '/')
        st = Line;
      else if (c == '/' && n == '*')
        st = Block;
      else if (c == '"')
        st = Str;
      else if (c == '\'')
        st = Chr;
      else
        continue;
      out[i] = ' ';
      continue;
    }
    const bool escaped = (st == Str || st == Chr) && c == '\\';
    if ((st == Line && c == '\n') || (st == Block && c == '*' && n == '/') ||
        (st == Str && c == '"') || (st == Chr && c == '\'')) {
      if (st == Block) out[i + 1] = ' ';
      st = Code;
    }
    if (c != '\n') out[i] = ' ';
    if (escaped && n != '\n') out[++i] = ' ';
  }
  return out;
}

struct LongFunction {
  std::string where;
  std::size_t lines;
};

// Function bodies: a '{' outside any function whose head (the code since the last ';', '{' or
// '}') has a parameter list and is not a namespace, a type or an initialiser.
std::vector<LongFunction> longFunctions(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  const std::string code = codeOnly(s.str());
  const std::regex type_head(R"(\b(namespace|class|struct|union|enum)\b[^()]*$)");
  std::vector<LongFunction> found;
  std::vector<bool> is_function;  // per open brace
  std::size_t line = 1, start_line = 0, head_from = 0;
  int function_depth = -1;  // depth of the open function's brace, -1: none
  for (std::size_t i = 0; i < code.size(); ++i) {
    const char c = code[i];
    if (c == '\n') ++line;
    if (c == ';') head_from = i + 1;
    if (c == '{') {
      const std::string head = code.substr(head_from, i - head_from);
      const bool fn = function_depth < 0 && head.find('(') != std::string::npos &&
                      !std::regex_search(head, type_head) && head.find('=') == std::string::npos;
      if (fn) {
        function_depth = static_cast<int>(is_function.size());
        start_line = line;
      }
      is_function.push_back(fn);
      head_from = i + 1;
    } else if (c == '}' && !is_function.empty()) {
      is_function.pop_back();
      if (static_cast<int>(is_function.size()) == function_depth) {
        const std::size_t n = line - start_line + 1;
        if (n > kMaxFunctionLines) {
          found.push_back({file.lexically_relative(DYNAMAP_SOURCE_DIR).string() + ":" +
                               std::to_string(start_line),
                           n});
        }
        function_depth = -1;
      }
      head_from = i + 1;
    }
  }
  return found;
}

TEST(Layout, NoFunctionIsLongerThanAScreen) {
  for (const fs::path& f : sources({"src", "include"})) {
    for (const LongFunction& lf : longFunctions(f)) {
      ADD_FAILURE() << lf.where << ": a function of " << lf.lines << " lines (at most "
                    << kMaxFunctionLines << ")";
    }
  }
}

TEST(Layout, TheCheckerSeesALongFunction) {
  // The rule above must be able to fail: a 61-line function is found, a 60-line one is not.
  const fs::path dir = fs::temp_directory_path() / "dynamap-layout-test";
  fs::create_directories(dir);
  for (int body : {57, 58}) {
    std::ofstream out(dir / "f.cpp");
    out << "namespace x {\nint f(int a) {\n";
    for (int k = 0; k < body; ++k) out << "  a += 1;  // {\n";
    out << "  return a;\n}\n}  // namespace x\n";
    out.close();
    EXPECT_EQ(longFunctions(dir / "f.cpp").size(), body == 58 ? 1u : 0u) << body;
  }
}

TEST(Layout, NoIncludeCycle) {
  const std::regex include_line(R"re(#include "(dynamap/[^"]+)")re");
  std::map<std::string, std::set<std::string>> edges;
  for (const fs::path& f : sources({"include"})) {
    const std::string name =
        f.lexically_relative(fs::path(DYNAMAP_SOURCE_DIR) / "include").string();
    std::ifstream in(f);
    for (std::string l; std::getline(in, l);) {
      std::smatch m;
      if (std::regex_search(l, m, include_line)) edges[name].insert(m[1]);
    }
  }
  std::map<std::string, int> state;  // 1: on the path, 2: done
  std::function<void(const std::string&, std::vector<std::string>&)> visit =
      [&](const std::string& h, std::vector<std::string>& path) {
        if (state[h] == 2) return;
        path.push_back(h);
        if (state[h] == 1) {
          std::string cycle;
          for (const std::string& p : path) cycle += p + " -> ";
          ADD_FAILURE() << "include cycle: " << cycle;
        } else {
          state[h] = 1;
          for (const std::string& next : edges[h]) visit(next, path);
          state[h] = 2;
        }
        path.pop_back();
      };
  for (const auto& kv : edges) {
    std::vector<std::string> path;
    visit(kv.first, path);
  }
}

}  // namespace
}  // namespace dynamap
