// Encoding of meshes for the pipe from the Gmsh child; see MeshWire.hpp.
#include "meshes/MeshWire.hpp"

#include <cstdint>
#include <cstring>
#include <stdexcept>

namespace flexsens {

namespace {

class Writer {
 public:
  void u64(std::uint64_t v) { raw(&v, sizeof v); }
  void f64(double v) { raw(&v, sizeof v); }
  void str(const std::string& s) {
    u64(s.size());
    bytes_ += s;
  }
  void vec3(const Eigen::Vector3d& x) {
    for (int c = 0; c < 3; ++c) f64(x[c]);
  }
  void ints(const std::vector<int>& v) {
    u64(v.size());
    for (int i : v) u64(static_cast<std::uint64_t>(static_cast<std::int64_t>(i)));
  }
  std::string take() { return std::move(bytes_); }

 private:
  void raw(const void* p, std::size_t n) { bytes_.append(static_cast<const char*>(p), n); }
  std::string bytes_;
};

class Reader {
 public:
  explicit Reader(const std::string& b) : b_(b) {}
  std::uint64_t u64() {
    std::uint64_t v;
    raw(&v, sizeof v);
    return v;
  }
  double f64() {
    double v;
    raw(&v, sizeof v);
    return v;
  }
  /// A count of items of at least `itemBytes` each: no more than the bytes left allow.
  std::size_t count(std::size_t itemBytes) {
    const std::uint64_t n = u64();
    if (n > (b_.size() - pos_) / std::max<std::size_t>(itemBytes, 1)) bad();
    return static_cast<std::size_t>(n);
  }
  std::string str() {
    const std::size_t n = count(1);
    std::string s = b_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  Eigen::Vector3d vec3() {
    Eigen::Vector3d x;
    for (int c = 0; c < 3; ++c) x[c] = f64();
    return x;
  }
  /// Node indices below `nodes`.
  std::vector<int> ints(std::size_t nodes) {
    std::vector<int> v(count(8));
    for (int& i : v) {
      const std::uint64_t k = u64();
      if (k >= nodes) bad();
      i = static_cast<int>(k);
    }
    return v;
  }
  void end() const {
    if (pos_ != b_.size()) bad();
  }
  [[noreturn]] static void bad() { throw std::logic_error("malformed mesh message from the Gmsh child process"); }

 private:
  void raw(void* p, std::size_t n) {
    if (b_.size() - pos_ < n) bad();
    std::memcpy(p, b_.data() + pos_, n);
    pos_ += n;
  }
  const std::string& b_;
  std::size_t pos_ = 0;
};

}  // namespace

std::string encodeBodyMesh(const BodyMesh& m) {
  Writer w;
  w.u64(static_cast<std::uint64_t>(m.shape));
  w.u64(m.positions.size());
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    w.vec3(m.positions[i]);
    w.u64(m.gmshTags.at(i));
  }
  w.u64(m.cells.size());
  for (const auto& c : m.cells) w.ints(c);
  w.u64(m.points.size());
  for (const auto& [name, i] : m.points) {
    w.str(name);
    w.u64(static_cast<std::uint64_t>(i));
  }
  w.u64(m.groups.size());
  for (const auto& [name, nodes] : m.groups) {
    w.str(name);
    w.ints(nodes);
  }
  w.u64(m.facets.size());
  for (const auto& [name, facets] : m.facets) {
    w.str(name);
    w.u64(facets.size());
    for (const auto& f : facets) w.ints(f);
  }
  return w.take();
}

BodyMesh decodeBodyMesh(const std::string& bytes) {
  Reader r(bytes);
  BodyMesh m;
  const std::uint64_t shape = r.u64();
  if (shape > static_cast<std::uint64_t>(Simplex::Tet10)) Reader::bad();
  m.shape = static_cast<Simplex>(shape);
  const std::size_t n = r.count(32);
  for (std::size_t i = 0; i < n; ++i) {
    m.positions.push_back(r.vec3());
    m.gmshTags.push_back(static_cast<std::size_t>(r.u64()));
  }
  const std::size_t cells = r.count(8);
  for (std::size_t c = 0; c < cells; ++c) {
    m.cells.push_back(r.ints(n));
    if (static_cast<int>(m.cells.back().size()) != simplexNodes(m.shape)) Reader::bad();
  }
  for (std::size_t k = r.count(16); k > 0; --k) {
    const std::string name = r.str();
    const std::uint64_t i = r.u64();
    if (i >= n) Reader::bad();
    m.points[name] = static_cast<int>(i);
  }
  for (std::size_t k = r.count(16); k > 0; --k) {
    const std::string name = r.str();
    m.groups[name] = r.ints(n);
  }
  for (std::size_t k = r.count(16); k > 0; --k) {
    auto& facets = m.facets[r.str()];
    for (std::size_t f = r.count(8); f > 0; --f) facets.push_back(r.ints(n));
  }
  r.end();
  return m;
}

std::string encodeCurveMesh(const CurveMesh& m) {
  Writer w;
  w.u64(m.chains.size());
  for (const NodeChain& c : m.chains) {
    w.str(c.group);
    w.u64(c.names.size());
    for (std::size_t i = 0; i < c.names.size(); ++i) {
      w.str(c.names[i]);
      w.vec3(c.positions.at(i));
      w.vec3(c.tangents.at(i));
    }
  }
  w.u64(m.points.size());
  for (const auto& [name, x] : m.points) {
    w.str(name);
    w.vec3(x);
  }
  return w.take();
}

CurveMesh decodeCurveMesh(const std::string& bytes) {
  Reader r(bytes);
  CurveMesh m;
  for (std::size_t k = r.count(16); k > 0; --k) {
    NodeChain c;
    c.group = r.str();
    for (std::size_t i = r.count(32); i > 0; --i) {
      c.names.push_back(r.str());
      c.positions.push_back(r.vec3());
      c.tangents.push_back(r.vec3());
    }
    m.chains.push_back(std::move(c));
  }
  for (std::size_t k = r.count(32); k > 0; --k) {
    const std::string name = r.str();
    m.points[name] = r.vec3();
  }
  r.end();
  return m;
}

}  // namespace flexsens
