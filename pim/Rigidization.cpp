#include "pim/Rigidization.hpp"

#include <sstream>

#include "constraints/Bilinear.hpp"
#include "constraints/Distance.hpp"
#include "constraints/KernelConstraintAD.hpp"

namespace flexsens {

AttachedPointConstraint::AttachedPointConstraint(std::string name, std::vector<int> nodes,
                                                 VecX coefficients, int dim, bool slope)
    : KernelConstraint(std::move(name), std::move(nodes)), c_(std::move(coefficients)), dim_(dim), slope_(slope),
      gradients_(slope ? 1 : 0) {
  const int k = static_cast<int>(c_.size());
  const int w = slope ? 2 * dim : dim;  // local coordinates per node
  const MatX I = MatX::Identity(dim, dim);
  J_.setZero(dim, w * (k + 2));
  J_.block(0, 0, dim, dim) = (c_.sum() - (slope ? 0.0 : 1.0)) * I;  // A
  for (int j = 0; j < k; ++j) J_.block(0, w * (1 + j), dim, dim) = -c_[j] * I;  // basis ends
  J_.block(0, w * (k + 1) + (slope ? dim : 0), dim, dim) = I;  // the attached point or slope
}

// Value template: Lambda_i = J_ x (linear; J_ holds the coefficients, see the constructor).
template <class T>
VecT<T> AttachedPointConstraint::phiT(const LocalState&, const VecT<T>& x, const VecT<T>&) const {
  VecT<T> out(J_.rows());
  for (int r = 0; r < J_.rows(); ++r) {
    T sum = J_(r, 0) * x[0];
    for (int j = 1; j < J_.cols(); ++j) sum += J_(r, j) * x[j];
    out[r] = sum;
  }
  return out;
}

template class KernelConstraint<AttachedPointConstraint>;

void AttachedPointConstraint::jacobian(const LocalState&, MatX& J) const { J = J_; }
void AttachedPointConstraint::hessian(const LocalState&, int, MatX& H) const {
  H.setZero(J_.cols(), J_.cols());
}

namespace {

/// An ancf_beam body (every node with r_x, r_y, r_z): its frame is the gradient triad of the
/// first node A, g_j = (r_x, r_y, r_z)_A, kept rigid by its metric, g_i . g_j = G_ij (6
/// quadratic BilinearConstraints); every other point and every other gradient keeps its
/// coordinates in that frame, c = G^-1 J_A^T (r_i - r_A) or G^-1 J_A^T g (linear:
/// r_i - r_A - sum_j c_j g_j, g - sum_j c_j g_j). A straight beam's nodes alone would span a
/// line; the triad spans space at any shape. Rows among fixed coordinates only are left out
/// (a clamped A: its frame; with it every fixed target). Local coordinates: 12 per node.
void rigidizeBeamBody(Rigidization& R, const std::string& name, const std::vector<int>& nodes, const Model& m,
                      const MatX& X, const std::string& where) {
  const int w = 12;
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Node& A = m.nodes[nodes[0]];
  const Eigen::Matrix3d JA = Eigen::Map<const Eigen::Matrix3d>(A.slope.data());
  const Eigen::Matrix3d G = JA.transpose() * JA;
  const Eigen::LDLT<Eigen::Matrix3d> metric(G);
  if (!(std::abs(JA.determinant()) > 1e-9))
    throw InputError(where + ": the gradients of node '" + A.name + "' of '" + name + "' do not span space");
  const bool frameFixed = !A.slopeFree();
  if (!frameFixed)
    for (int i = 0; i < 3; ++i)
      for (int j = i; j < 3; ++j) {
        MatX Si = MatX::Zero(3, w), Sj = MatX::Zero(3, w);
        Si.block(0, 3 + 3 * i, 3, 3) = I;
        Sj.block(0, 3 + 3 * j, 3, 3) = I;
        R.constraints.push_back(std::make_unique<BilinearConstraint>(
            name + ".rigid.frame(" + "xyz"[i] + "," + "xyz"[j] + ")", "rigid_frame", std::vector<int>{nodes[0]}, Si,
            Eigen::Vector3d::Zero(), Sj, Eigen::Vector3d::Zero(), G(i, j), 3));
      }
  // target: local slot 0 (A) or 1 (node i); component 0 the position, 1 + g gradient g
  auto attach = [&](size_t i, int comp, const Eigen::Vector3d& rel, const std::string& label) {
    const Node& nd = m.nodes[nodes[i]];
    const bool fixedTarget = comp == 0 ? (nd.ground && A.ground) : !nd.slopeFree();
    if (fixedTarget && frameFixed) return;
    const Eigen::Vector3d c = metric.solve(JA.transpose() * rel);
    std::vector<int> local = {nodes[0]};
    if (i > 0) local.push_back(nodes[i]);
    const int slot = i > 0 ? 1 : 0;
    MatX J = MatX::Zero(3, static_cast<int>(local.size()) * w);
    J.block(0, slot * w + 3 * comp, 3, 3) += I;
    if (comp == 0) J.block(0, 0, 3, 3) -= I;  // r_i - r_A
    for (int j = 0; j < 3; ++j) J.block(0, 3 + 3 * j, 3, 3) -= c[j] * I;
    R.constraints.push_back(std::make_unique<AttachedPointConstraint>(name + label, local, J, 3));
  };
  for (size_t i = 0; i < nodes.size(); ++i) {
    const Node& nd = m.nodes[nodes[i]];
    if (i > 0) attach(i, 0, X.col(nodes[i]) - X.col(nodes[0]), ".rigid.point(" + nd.name + ")");
    if (i > 0)
      for (int g = 0; g < 3; ++g)
        attach(i, 1 + g, nd.slope.segment<3>(3 * g), ".rigid.gradient(" + nd.name + "," + "xyz"[g] + ")");
  }
}

}  // namespace

int Rigidization::rows() const {
  int r = 0;
  for (const auto& c : constraints) r += c->rows();
  return r;
}

Rigidization rigidize(const std::string& name, const std::vector<int>& nodes, const Model& m,
                      const MatX& X, const std::string& where, const Quantity* pairLength,
                      const RigidizeOptions& opt) {
  const int dim = m.dim;
  if (nodes.size() < 2) throw InputError(where + ": a rigid body needs at least two nodes");
  Rigidization R;
  auto pos = [&](int i) -> VecX { return X.col(nodes[i]); };
  double size = 0.0;
  for (size_t i = 1; i < nodes.size(); ++i) size = std::max(size, (pos(i) - pos(0)).norm());
  if (!(size > 0)) throw InputError(where + ": all nodes of '" + name + "' coincide");
  const double tol = 1e-9 * size;
  // Basic points: A = first node, then greedily the point farthest from the span so far
  // (or, inOrder, the first node outside it).
  std::vector<int> basic = {0};
  MatX E(dim, 0);  // orthonormal basis of the span, to measure distances from it
  for (int level = 0; level < dim; ++level) {
    int best = -1;
    double bestDist = tol;
    for (size_t i = 1; i < nodes.size(); ++i) {
      VecX r = pos(i) - pos(0);
      if (E.cols()) r -= E * (E.transpose() * r);
      if (r.norm() > bestDist) {
        bestDist = r.norm();
        best = static_cast<int>(i);
        if (opt.inOrder) break;
      }
    }
    if (best < 0) break;
    basic.push_back(best);
    VecX e = pos(best) - pos(0);
    if (E.cols()) e -= E * (E.transpose() * e);
    E.conservativeResize(dim, E.cols() + 1);
    E.col(E.cols() - 1) = e.normalized();
  }
  R.cloudDimension = static_cast<int>(basic.size()) - 1;
  for (int b : basic) R.basicPoints.push_back(nodes[b]);
  const auto ground = [&](int i) { return m.nodes[nodes[i]].ground; };
  // ancf_beam bodies: every node carries r_x, r_y, r_z (a body mixing them with other nodes
  // is not supported: its frame would be the gradients of some nodes only).
  int beamNodes = 0;
  for (int i : nodes) beamNodes += opt.slopes && m.nodes[i].gradients(dim) == 3;
  if (beamNodes == static_cast<int>(nodes.size())) {
    rigidizeBeamBody(R, name, nodes, m, X, where);
    return R;
  }
  if (beamNodes > 0)
    throw InputError(where + ": '" + name + "' mixes ancf_beam nodes (three gradients) with other nodes; "
                     "rigidizing such a body is not supported");
  // Distances among basic points (1, 3 or 6 quadratic constraints).
  for (size_t i = 0; i < basic.size(); ++i)
    for (size_t j = i + 1; j < basic.size(); ++j) {
      if (ground(basic[i]) && ground(basic[j])) continue;  // fixed already
      if (opt.linked && opt.linked(nodes[basic[i]], nodes[basic[j]])) continue;
      Quantity L{(pos(basic[j]) - pos(basic[i])).norm(), -1};
      if (pairLength && nodes.size() == 2) L = *pairLength;
      R.constraints.push_back(std::make_unique<DistanceConstraint>(
          name + ".rigid.d(" + m.nodes[nodes[basic[i]]].name + "," + m.nodes[nodes[basic[j]]].name + ")",
          nodes[basic[i]], nodes[basic[j]], L));
    }
  // Attached points: G c_i = b_i with G_jk = e_j . e_k, b_ij = r_Ai . e_j.
  const int k = R.cloudDimension;
  MatX B(dim, k);
  for (int j = 0; j < k; ++j) B.col(j) = pos(basic[j + 1]) - pos(0);
  const MatX G = B.transpose() * B;
  const Eigen::LDLT<MatX> metric(G);
  for (size_t i = 1; i < nodes.size(); ++i) {
    if (std::find(basic.begin(), basic.end(), static_cast<int>(i)) != basic.end()) continue;
    bool allGround = ground(static_cast<int>(i));
    for (int b : basic) allGround = allGround && ground(b);
    if (allGround) continue;
    const VecX c = metric.solve(B.transpose() * (pos(i) - pos(0)));
    std::vector<int> ids;
    for (int b : basic) ids.push_back(nodes[b]);
    ids.push_back(nodes[i]);
    R.constraints.push_back(std::make_unique<AttachedPointConstraint>(
        name + ".rigid.point(" + m.nodes[nodes[i]].name + ")", ids, c, dim));
  }
  // Free slopes (ANCF nodes), when every basic point carries a slope too (an ANCF body; a
  // node of another kind among them leaves the slopes free: pinned to the body).
  bool basicSlopes = opt.slopes;
  for (int b : basic) basicSlopes = basicSlopes && m.nodes[nodes[b]].hasSlope();
  for (size_t i = 0; i < nodes.size() && basicSlopes; ++i) {
    const Node& nd = m.nodes[nodes[i]];
    if (!nd.slopeFree()) continue;
    const VecX c = metric.solve(B.transpose() * nd.slope);
    if ((B * c - nd.slope).norm() > 1e-9 * nd.slope.norm())
      throw InputError(where + ": the slope of node '" + nd.name + "' is not a direction within the span of '" +
                       name + "' (a straight body's slopes must lie along it)");
    std::vector<int> ids;
    for (int b : basic) ids.push_back(nodes[b]);
    ids.push_back(nodes[i]);
    R.constraints.push_back(std::make_unique<AttachedPointConstraint>(
        name + ".rigid.slope(" + nd.name + ")", ids, c, dim, true));
  }
  return R;
}

}  // namespace flexsens
