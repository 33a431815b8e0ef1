// Geometry and mesh file checks before Gmsh; see GeometryFile.hpp.
#include "meshes/GeometryFile.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/Types.hpp"
#include "elements/SimplexShape.hpp"  // fmtNumber

namespace flexsens {

std::string readGeometryFile(const std::string& file, const std::string& kind, const std::string& where) {
  const std::string what = "the " + kind + " '" + file + "'";
  struct stat st;
  if (::stat(file.c_str(), &st) != 0)
    throw InputError(where + ": cannot open " + what + " (does it exist and is it readable?)");
  if (!S_ISREG(st.st_mode)) throw InputError(where + ": " + what + " is not a regular file");
  const auto size = static_cast<std::uintmax_t>(st.st_size);
  if (size > kMaxGeometryBytes)
    throw InputError(where + ": " + what + " has " + std::to_string(size) + " bytes; expected at most " +
                     std::to_string(kMaxGeometryBytes) + " (64 MiB)");
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw InputError(where + ": cannot open " + what + " (does it exist and is it readable?)");
  // Read until EOF or past the size stat gave: a pseudo-file (/proc/self/pagemap: size 0,
  // endless contents, read in multiples of 8 bytes) shows itself by the bytes after it.
  std::string text;
  char buf[65536];
  ssize_t n = 0;
  while (text.size() <= size && ((n = ::read(fd, buf, sizeof buf)) > 0 || (n < 0 && errno == EINTR)))
    if (n > 0) text.append(buf, static_cast<std::size_t>(n));
  ::close(fd);
  if (text.size() > size)
    throw InputError(where + ": " + what + " holds more than the " + std::to_string(size) +
                     " bytes its size says (a /proc or /sys pseudo-file?); expected a regular file");
  if (n < 0) throw InputError(where + ": cannot read " + what + ": " + std::strerror(errno));
  return text;
}

namespace {

/// 1-based line of byte offset `pos`.
int lineOf(const std::string& s, std::size_t pos) {
  return 1 + static_cast<int>(std::count(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(pos), '\n'));
}

/// Offset just after the line "$<section>" (at the file's start or after a newline), or npos.
std::size_t sectionBody(const std::string& s, const std::string& section) {
  const std::string tag = "$" + section;
  for (std::size_t p = s.find(tag); p != std::string::npos; p = s.find(tag, p + 1)) {
    if (p != 0 && s[p - 1] != '\n') continue;
    std::size_t e = p + tag.size();
    if (e < s.size() && s[e] == '\r') ++e;
    if (e < s.size() && s[e] == '\n') return e + 1;
  }
  return std::string::npos;
}

/// The counts of a section header: MSH 4 binary (four size_t: blocks, count, min, max tag),
/// else the text line's numbers (MSH 4: the same four; MSH 2: the count alone).
std::vector<double> headerCounts(const std::string& s, std::size_t at, bool binary4) {
  std::vector<double> v;
  if (binary4) {
    for (int k = 0; k < 4 && at + 8 * (k + 1) <= s.size(); ++k) {
      std::uint64_t x;
      std::memcpy(&x, s.data() + at + 8 * k, 8);
      v.push_back(static_cast<double>(x));
    }
    return v;
  }
  std::istringstream line(s.substr(at, s.find('\n', at) - at));
  double x;
  while (line >> x) v.push_back(x);
  return v;
}

}  // namespace

void checkMshCounts(const std::string& file, const std::string& s, const std::string& where) {
  double version = 0.0;
  int fileType = 0;
  if (const std::size_t f = sectionBody(s, "MeshFormat"); f != std::string::npos) {
    std::istringstream line(s.substr(f, s.find('\n', f) - f));
    line >> version >> fileType;
  }
  const bool binary4 = version >= 4.0 && fileType == 1;
  const double bytes = static_cast<double>(s.size());
  for (const char* section : {"Nodes", "Elements"}) {
    const std::size_t at = sectionBody(s, section);
    if (at == std::string::npos) continue;
    const std::vector<double> c = headerCounts(s, at, binary4);
    // MSH 4: blocks and count (entries 0, 1); MSH 2: the count (entry 0).
    for (std::size_t k = 0; k < std::min<std::size_t>(c.size(), version >= 4.0 ? 2 : 1); ++k) {
      if (!(c[k] > bytes)) continue;
      const std::string what = std::string(section) == "Nodes" ? (k == 0 && version >= 4.0 ? "node blocks" : "nodes")
                                                               : (k == 0 && version >= 4.0 ? "element blocks" : "elements");
      throw InputError(where + ": the mesh file '" + file + "' line " + std::to_string(lineOf(s, at)) + ": $" + section +
                       " claims " + fmtNumber(c[k]) + " " + what + " in a file of " + fmtNumber(bytes) +
                       " bytes; expected at most one per byte (a damaged or forged header)");
    }
  }
}

}  // namespace flexsens
