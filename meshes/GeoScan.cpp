// Lexical scan of .geo files; see GeoScan.hpp.
#include "meshes/GeoScan.hpp"

#include <cctype>
#include <filesystem>
#include <map>
#include <set>

#include "core/Types.hpp"
#include "meshes/GeometryFile.hpp"

namespace flexsens {

namespace fs = std::filesystem;

namespace {

struct Token {
  enum Kind { Word, String, Other } kind;
  std::string text;
  int line;
};

/// Gmsh's lexer in brief: // and /* */ comments, strings in "..." or '...' (no escapes),
/// words [A-Za-z_][A-Za-z0-9_]*, ">>" as one token; numbers and other characters as Other.
std::vector<Token> tokenize(const std::string& s) {
  std::vector<Token> out;
  int line = 1;
  std::size_t i = 0;
  auto isWord = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  while (i < s.size()) {
    const char c = s[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else if (s.compare(i, 2, "//") == 0) {
      while (i < s.size() && s[i] != '\n') ++i;
    } else if (s.compare(i, 2, "/*") == 0) {
      const std::size_t e = s.find("*/", i + 2);
      const std::size_t stop = e == std::string::npos ? s.size() : e + 2;
      for (; i < stop; ++i) line += s[i] == '\n';
    } else if (c == '"' || c == '\'') {
      const int at = line;
      const std::size_t e = s.find(c, i + 1);
      const std::size_t stop = e == std::string::npos ? s.size() : e;
      std::string text = s.substr(i + 1, stop - i - 1);
      for (char ch : text) line += ch == '\n';
      out.push_back({Token::String, text, at});
      i = stop + 1;
    } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      std::size_t e = i;
      while (e < s.size() && isWord(s[e])) ++e;
      out.push_back({Token::Word, s.substr(i, e - i), line});
      i = e;
    } else if (s.compare(i, 2, ">>") == 0) {
      out.push_back({Token::Other, ">>", line});
      i += 2;
    } else {
      out.push_back({Token::Other, std::string(1, c), line});
      ++i;
    }
  }
  return out;
}

const std::map<std::string, std::string>& refusedCommands() {
  static const std::map<std::string, std::string> m = {
      {"SystemCall", "runs a shell command"}, {"System", "runs a shell command"},
      {"NonBlockingSystemCall", "runs a shell command"}, {"Shell", "runs a shell command"},
      {"OnelabRun", "runs a solver program"}, {"Save", "writes a file"}, {"Print", "writes a file"},
      {"CreateDir", "creates a folder"}, {"DeleteFile", "deletes a file"}, {"RenameFile", "renames a file"},
      {"Exit", "ends Gmsh before the geometry is returned"}, {"Abort", "ends Gmsh before the geometry is returned"},
      {"Sleep", "makes Gmsh wait"}};
  return m;
}

const std::set<std::string>& fileReadingCommands() {
  static const std::set<std::string> s = {"Include", "Merge", "MergeWithBoundingBox", "ShapeFromFile", "ListFromFile"};
  return s;
}

/// `p` (canonical) lies in `root` (canonical) or below.
bool inside(const fs::path& p, const fs::path& root) {
  auto r = root.begin();
  auto q = p.begin();
  for (; r != root.end(); ++r, ++q)
    if (q == p.end() || *q != *r) return false;
  return true;
}

class Scanner {
 public:
  Scanner(std::vector<fs::path> roots, std::string where) : roots_(std::move(roots)), where_(std::move(where)) {}

  void scan(const std::string& file, int depth) {
    if (!visited_.insert(fs::weakly_canonical(file).string()).second) return;
    if (depth > 20) fail(file, 1, "Include", "nests more than 20 levels deep (an Include cycle?)");
    const std::vector<Token> t = tokenize(readGeometryFile(file, "geometry file", where_));
    for (std::size_t i = 0; i < t.size(); ++i) {
      if (t[i].kind != Token::Word) continue;
      const bool optionName = (i > 0 && t[i - 1].text == ".") || (i + 1 < t.size() && t[i + 1].text == ".");
      if (optionName) continue;
      const std::string& w = t[i].text;
      if (const auto it = refusedCommands().find(w); it != refusedCommands().end()) fail(file, t[i].line, w, it->second);
      if (w == "Printf" || w == "Error" || w == "Warning") checkRedirect(file, t, i);
      if (fileReadingCommands().count(w)) checkFileArgument(file, t, i, depth);
    }
  }

 private:
  [[noreturn]] void fail(const std::string& file, int line, const std::string& cmd, const std::string& why) const {
    throw InputError(where_ + ": " + file + ":" + std::to_string(line) + ": " + cmd + " " + why +
                     "; flexsens refuses geometry commands that reach outside the scene (SystemCall, Printf > file, "
                     "Save, Include of a file outside the scene's folder, ...): remove it");
  }

  /// Printf(...) > "file" or >> "file".
  void checkRedirect(const std::string& file, const std::vector<Token>& t, std::size_t i) const {
    if (i + 1 >= t.size() || t[i + 1].text != "(") return;
    int depth = 0;
    std::size_t k = i + 1;
    for (; k < t.size(); ++k) {
      depth += t[k].text == "(" ? 1 : t[k].text == ")" ? -1 : 0;
      if (depth == 0) break;
    }
    if (k + 1 < t.size() && (t[k + 1].text == ">" || t[k + 1].text == ">>"))
      fail(file, t[k + 1].line, t[i].text + " " + t[k + 1].text, "writes to a file");
  }

  /// Include "name" (or ShapeFromFile("name")): a literal name inside the roots.
  void checkFileArgument(const std::string& file, const std::vector<Token>& t, std::size_t i, int depth) {
    const std::string& cmd = t[i].text;
    std::size_t k = i + 1;
    if (k < t.size() && (t[k].text == "(" || t[k].text == "[")) ++k;
    const bool literal = k < t.size() && t[k].kind == Token::String &&
                         (k + 1 >= t.size() || t[k + 1].text == ";" || t[k + 1].text == ")" || t[k + 1].text == "]");
    if (!literal) fail(file, t[i].line, cmd, "takes a file name built at run time, which cannot be checked; expected a quoted file name");
    fs::path named(t[k].text);
    if (named.is_relative()) named = fs::path(file).parent_path() / named;
    const fs::path real = fs::weakly_canonical(named);
    bool ok = false;
    for (const fs::path& r : roots_) ok = ok || inside(real, r);
    if (!ok)
      fail(file, t[k].line, cmd + " \"" + t[k].text + "\"", "names a file outside the scene's folder (" + roots_.front().string() + ")");
    const std::string ext = real.extension().string();
    if (cmd == "Include" || ext == ".geo")
      scan(real.string(), depth + 1);
    else
      readGeometryFile(real.string(), "file named by " + cmd + " in " + file + ":" + std::to_string(t[k].line), where_);
  }

  std::vector<fs::path> roots_;
  std::string where_;
  std::set<std::string> visited_;
};

}  // namespace

void scanGeoFile(const std::string& file, const std::vector<std::string>& roots, const std::string& where) {
  try {
    std::vector<fs::path> canon;
    auto add = [&](const fs::path& dir) {
      fs::path c = fs::weakly_canonical(fs::absolute(dir.empty() ? fs::path(".") : dir));
      if (c.filename().empty()) c = c.parent_path();  // "/a/b/" -> "/a/b"
      canon.push_back(c);
    };
    for (const std::string& r : roots)
      if (!r.empty()) add(r);
    add(fs::path(file).parent_path());  // the geometry file's own folder
    Scanner(canon, where).scan(file, 0);
  } catch (const fs::filesystem_error& e) {
    throw InputError(where + ": cannot check the geometry file '" + file + "': " + e.what());
  }
}

}  // namespace flexsens
