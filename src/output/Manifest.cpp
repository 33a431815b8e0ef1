#include "output/Manifest.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/Types.hpp"

namespace flexsens {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFormatLine = "flexsens-manifest 1";

bool plainName(const std::string& n) {
  return !n.empty() && n != "." && n != ".." && n.find_first_of(std::string("/\n\r\0", 4)) == std::string::npos;
}

bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

fs::file_status entryStatus(const fs::path& p) {
  std::error_code ec;
  return fs::symlink_status(p, ec);  // never follows a link: a listed name must be the thing itself
}

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() > tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

/// An empty `.<name>.lock` (output/OutputLock.hpp) or a marked `.<name>.staging-<pid>` folder
/// of a killed run (output/RunDirectory.hpp).
bool housekeeping(const fs::path& p) {
  const std::string n = p.filename().string();
  if (n.size() < 2 || n[0] != '.') return false;
  const fs::file_status st = entryStatus(p);
  std::error_code ec;
  if (endsWith(n, ".lock")) return fs::is_regular_file(st) && fs::file_size(p, ec) == 0 && !ec;
  return n.find(".staging-") != std::string::npos && fs::is_directory(st) &&
         fs::is_regular_file(entryStatus(p / kStagingMarker));
}

void collectForeign(const fs::path& dir, const std::string& prefix, ForeignEntries& out) {
  std::string problem;
  const bool hasManifest = fs::exists(entryStatus(dir / kManifestName));
  const std::optional<Manifest> m = hasManifest ? readManifest(dir, problem) : std::nullopt;
  if (hasManifest && !m && out.note.empty()) out.note = prefix + kManifestName + ": " + problem;
  bool looksLikeResults = false;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    const fs::file_status st = entryStatus(e.path());
    looksLikeResults = looksLikeResults || name == "summary.json";
    if (name == kManifestName && m) continue;
    if (m && fs::is_regular_file(st) && contains(m->files, name)) continue;
    if (m && (fs::is_regular_file(st) || fs::is_directory(st)) && contains(m->keep, name)) continue;  // never deleted
    if (m && fs::is_directory(st) && contains(m->dirs, name)) {
      collectForeign(e.path(), prefix + name + "/", out);
      continue;
    }
    if (housekeeping(e.path())) continue;
    out.entries.push_back(prefix + name + (fs::is_directory(st) ? "/" : ""));
  }
  if (ec) out.entries.push_back(prefix + " (unreadable: " + ec.message() + ")");
  if (!hasManifest && looksLikeResults && out.note.empty())
    out.note = prefix + "summary.json without a " + std::string(kManifestName) +
               ": results of a flexsens version that did not list its files; move or delete them yourself";
}

}  // namespace

std::string manifestText(const Manifest& m) {
  std::ostringstream os;
  os << kFormatLine << "\nkind " << m.kind << "\n";
  for (const auto& f : m.files) os << "file " << f << "\n";
  for (const auto& d : m.dirs) os << "dir " << d << "\n";
  for (const auto& k : m.keep) os << "keep " << k << "\n";
  return os.str();
}

std::optional<Manifest> readManifest(const fs::path& dir, std::string& problem) {
  const fs::path path = dir / kManifestName;
  if (!fs::is_regular_file(entryStatus(path))) {
    problem = "missing or not a regular file";
    return std::nullopt;
  }
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line) || line != kFormatLine) {
    problem = "line 1: expected '" + std::string(kFormatLine) + "' (another format is not ours to replace)";
    return std::nullopt;
  }
  Manifest m;
  for (int no = 2; std::getline(in, line); ++no) {
    const size_t sp = line.find(' ');
    const std::string tag = line.substr(0, sp), name = sp == std::string::npos ? "" : line.substr(sp + 1);
    std::vector<std::string>* list = tag == "file" ? &m.files : tag == "dir" ? &m.dirs : tag == "keep" ? &m.keep : nullptr;
    if (tag == "kind" && !name.empty()) {
      m.kind = name;
    } else if (list && plainName(name) && name != kManifestName) {
      list->push_back(name);
    } else {
      problem = "line " + std::to_string(no) + ": expected 'kind K', 'file NAME', 'dir NAME' or 'keep NAME' with a "
                "plain name, got '" + line.substr(0, 80) + "'";
      return std::nullopt;
    }
  }
  return m;
}

ForeignEntries foreignEntries(const fs::path& dir) {
  ForeignEntries f;
  collectForeign(dir, "", f);
  return f;
}

std::string describeEntries(const std::vector<std::string>& entries) {
  constexpr size_t kShown = 4;
  std::string r;
  for (size_t i = 0; i < entries.size() && i < kShown; ++i) r += (i ? ", " : "") + entries[i];
  if (entries.size() > kShown) r += " and " + std::to_string(entries.size() - kShown) + " more";
  return r;
}

bool removeListed(const fs::path& dir) {
  std::error_code ec;
  std::string problem;
  if (const std::optional<Manifest> m = readManifest(dir, problem)) {
    for (const auto& f : m->files)
      if (fs::is_regular_file(entryStatus(dir / f))) fs::remove(dir / f, ec);
    for (const auto& d : m->dirs)
      if (fs::is_directory(entryStatus(dir / d))) removeListed(dir / d);
    fs::remove(dir / kManifestName, ec);
  }
  std::vector<fs::path> ours;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (housekeeping(e.path())) ours.push_back(e.path());
  for (const auto& p : ours) fs::remove_all(p, ec);  // an empty lock file, a marked staging folder
  return ::rmdir(dir.c_str()) == 0 || !fs::exists(entryStatus(dir));
}

void writeManifestOfContents(const fs::path& dir, const std::string& shownDir, const std::string& kind,
                             const std::vector<std::string>& keep) {
  Manifest m;
  m.kind = kind;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name == kManifestName || name == kStagingMarker) continue;
    const fs::file_status st = entryStatus(e.path());
    if (fs::is_directory(st)) m.dirs.push_back(name);
    else if (fs::is_regular_file(st)) m.files.push_back(name);
  }
  if (ec) throw OutputError("cannot list " + shownDir + ": " + ec.message());
  std::sort(m.files.begin(), m.files.end());
  std::sort(m.dirs.begin(), m.dirs.end());
  for (const auto& k : keep)
    if (!contains(m.files, k)) m.keep.push_back(k);
  writeFileChecked((dir / kManifestName).string(), shownDir + "/" + kManifestName, manifestText(m));
}

void writeFileChecked(const std::string& path, const std::string& shownPath, const std::string& text) {
  auto fail = [&](int err) { throw OutputError("cannot write " + shownPath + ": " + std::strerror(err)); };
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail(errno);
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = n < 0 ? errno : EIO;
      ::close(fd);
      fail(err);
    }
    done += static_cast<size_t>(n);
  }
  if (::close(fd) != 0) fail(errno);
}

}  // namespace flexsens
