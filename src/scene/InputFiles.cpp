#include "scene/InputFiles.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/Types.hpp"

namespace flexsens {

namespace fs = std::filesystem;

namespace {

std::string mebibytes(std::uintmax_t bytes) {
  std::ostringstream os;
  os << static_cast<double>(bytes) / (1u << 20) << " MiB";
  return os.str();
}

/// True if real path `p` is `dir` or lies below it (whole path components compared).
bool within(const fs::path& p, const fs::path& dir) {
  auto a = dir.begin(), b = p.begin();
  for (; a != dir.end(); ++a, ++b)
    if (b == p.end() || *a != *b) return false;
  return true;
}

/// Why `file` (a real path) may not be read as a data file of at most maxBytes, or "".
std::string refusal(const fs::path& file, std::uintmax_t maxBytes) {
  std::error_code ec;
  const fs::file_status st = fs::status(file, ec);
  if (ec) return std::string("cannot read it: ") + ec.message();
  if (!fs::is_regular_file(st)) return "it is not a regular file (a device, FIFO, socket or folder); expected a file";
  const std::uintmax_t size = fs::file_size(file, ec);
  if (ec) return std::string("cannot read its size: ") + ec.message();
  if (size > maxBytes)
    return "it holds " + mebibytes(size) + ", more than the limit of " + mebibytes(maxBytes) + " for such a file";
  return "";
}

}  // namespace

InputPolicy& inputPolicy() {
  static InputPolicy policy;
  return policy;
}

void allowInputDirectory(const std::string& dir, const std::string& option) {
  std::error_code ec;
  const fs::path real = fs::canonical(dir, ec);
  if (ec || !fs::is_directory(real, ec))
    throw InputError("option " + option + " '" + dir + "': expected an existing folder");
  inputPolicy().allowedDirs.push_back(real);
}

std::string sceneDataFile(const YamlReader& r, const YAML::Node& n, const std::string& key, const std::string& name,
                          std::uintmax_t maxBytes) {
  std::error_code ec;
  fs::path sceneDir = fs::path(r.file()).parent_path();
  if (sceneDir.empty()) sceneDir = ".";
  const fs::path sceneReal = fs::canonical(sceneDir, ec);
  if (ec) r.fail(n, key, "cannot resolve the scene's folder: " + ec.message());
  const fs::path real = fs::canonical(fs::path(name).is_absolute() ? fs::path(name) : sceneDir / name, ec);
  if (ec) r.fail(n, key, "cannot open '" + name + "': " + ec.message());
  bool allowed = within(real, sceneReal);
  for (const fs::path& d : inputPolicy().allowedDirs) allowed = allowed || within(real, d);
  if (!allowed)
    r.fail(n, key, "'" + name + "' lies outside the scene's folder " + sceneReal.string() +
                       " (symlinks and '..' resolved); a scene reads files only from its folder and below: copy "
                       "the file there, or allow its folder with --allow-path DIR");
  const std::string why = refusal(real, maxBytes);
  if (!why.empty()) r.fail(n, key, "'" + name + "': " + why);
  return real.string();
}

std::string readBoundedFile(const std::string& file, std::uintmax_t maxBytes, const std::string& shown) {
  const std::string why = refusal(fs::path(file), maxBytes);
  if (!why.empty()) throw std::runtime_error("'" + shown + "': " + why);
  errno = 0;
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open '" + shown + "': " + std::strerror(errno ? errno : ENOENT));
  // In chunks up to one byte past the limit: a /proc file reports size 0 and may be endless.
  std::string text;
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    text.append(chunk, static_cast<size_t>(in.gcount()));
    if (text.size() > maxBytes)
      throw std::runtime_error("'" + shown + "': it holds more than the limit of " + mebibytes(maxBytes));
  }
  return text;
}

}  // namespace flexsens
