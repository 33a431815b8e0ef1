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

/// The gradients of an ancf_beam body (every node with r_x, r_y, r_z) as directions fixed in
/// it. Basis: the chords e_j = r_Bj - r_A of the basic points, completed to 3D by those
/// gradients of A that widen the span (a straight beam: r_y,A and r_z,A). The frame stays rigid
/// by the dot products of its vectors (chord pairs: the distances already there; pairs with a
/// gradient: quadratic BilinearConstraints), and every other gradient g_i = sum_j c_j e_j,
/// c = B^-1 g_i0 (linear). Local coordinates: 12 per node (positions and gradients).
void attachBeamGradients(Rigidization& R, const std::string& name, const std::vector<int>& nodes,
                         const std::vector<int>& basic, const Model& m, const MatX& X, const std::string& where) {
  const int w = 12, nb = static_cast<int>(basic.size());
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Node& A = m.nodes[nodes[basic[0]]];
  struct BasisVector {
    MatX S;              ///< 3 x (nb w): the vector from the basic nodes' local coordinates
    Eigen::Vector3d v0;  ///< at the undeformed state
    bool fixed;          ///< no free coordinate enters it
    int grad;            ///< the gradient of A it is (0, 1, 2), or -1 for a chord
  };
  std::vector<BasisVector> basis;
  MatX E(3, 0);  // orthonormal basis of the span so far
  auto widen = [&](const Eigen::Vector3d& v) {
    Eigen::Vector3d r = v;
    if (E.cols()) r -= E * (E.transpose() * v);
    if (!(r.norm() > 1e-9 * v.norm())) return false;
    E.conservativeResize(3, E.cols() + 1);
    E.col(E.cols() - 1) = r.normalized();
    return true;
  };
  for (int j = 1; j < nb; ++j) {
    const Node& Bj = m.nodes[nodes[basic[j]]];
    BasisVector b{MatX::Zero(3, nb * w), X.col(nodes[basic[j]]) - X.col(nodes[basic[0]]), A.ground && Bj.ground, -1};
    b.S.block(0, j * w, 3, 3) = I;
    b.S.block(0, 0, 3, 3) = -I;
    widen(b.v0);
    basis.push_back(b);
  }
  for (int g = 0; g < 3 && basis.size() < 3; ++g) {
    const Eigen::Vector3d v = A.slope.segment<3>(3 * g);
    if (!widen(v)) continue;
    BasisVector b{MatX::Zero(3, nb * w), v, !A.slopeFree(), g};
    b.S.block(0, 3 + 3 * g, 3, 3) = I;
    basis.push_back(b);
  }
  if (basis.size() < 3)
    throw InputError(where + ": the gradients of node '" + A.name + "' of '" + name + "' do not span space");
  std::vector<int> ids;
  for (int b : basic) ids.push_back(nodes[b]);
  for (size_t i = 0; i < basis.size(); ++i)
    for (size_t j = i; j < basis.size(); ++j) {
      if (basis[i].grad < 0 && basis[j].grad < 0) continue;  // two chords: a distance above
      if (basis[i].fixed && basis[j].fixed) continue;
      auto label = [&](const BasisVector& b) {
        return b.grad < 0 ? "chord" + std::to_string(&b - basis.data() + 1) : std::string("xyz").substr(b.grad, 1) + "(" + A.name + ")";
      };
      R.constraints.push_back(std::make_unique<BilinearConstraint>(
          name + ".rigid.frame(" + label(basis[i]) + "," + label(basis[j]) + ")", "rigid_frame", ids, basis[i].S,
          Eigen::Vector3d::Zero(), basis[j].S, Eigen::Vector3d::Zero(), basis[i].v0.dot(basis[j].v0), 3));
    }
  Eigen::Matrix3d B;
  for (int j = 0; j < 3; ++j) B.col(j) = basis[j].v0;
  const Eigen::PartialPivLU<Eigen::Matrix3d> lu(B);
  bool allFixed = true;
  for (const auto& b : basis) allFixed = allFixed && b.fixed;
  for (size_t i = 0; i < nodes.size(); ++i) {
    const Node& nd = m.nodes[nodes[i]];
    const auto it = std::find(basic.begin(), basic.end(), static_cast<int>(i));
    const int slot = it != basic.end() ? static_cast<int>(it - basic.begin()) : nb;  // local node
    std::vector<int> local = ids;
    if (slot == nb) local.push_back(nodes[i]);
    for (int g = 0; g < 3; ++g) {
      bool inBasis = false;
      for (const auto& b : basis) inBasis = inBasis || (slot == 0 && b.grad == g);
      if (inBasis || (!nd.slopeFree() && allFixed)) continue;
      const Eigen::Vector3d c = lu.solve(Eigen::Vector3d(nd.slope.segment<3>(3 * g)));
      MatX J = MatX::Zero(3, static_cast<int>(local.size()) * w);
      J.block(0, slot * w + 3 + 3 * g, 3, 3) = I;
      for (int j = 0; j < 3; ++j) J.leftCols(nb * w) -= c[j] * basis[j].S;
      R.constraints.push_back(std::make_unique<AttachedPointConstraint>(
          name + ".rigid.gradient(" + nd.name + "," + "xyz"[g] + ")", local, J, 3));
    }
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
  // ancf_beam bodies: every node carries r_x, r_y, r_z (a body mixing them with other nodes
  // is not supported: its frame would have no gradients on some basic points).
  int beamNodes = 0;
  for (int i : nodes) beamNodes += m.nodes[i].gradients(dim) == 3;
  if (beamNodes == static_cast<int>(nodes.size())) {
    attachBeamGradients(R, name, nodes, basic, m, X, where);
    return R;
  }
  if (beamNodes > 0)
    throw InputError(where + ": '" + name + "' mixes ancf_beam nodes (three gradients) with other nodes; "
                     "rigidizing such a body is not supported");
  bool basicSlopes = true;
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
