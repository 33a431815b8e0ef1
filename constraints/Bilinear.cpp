#include "constraints/Bilinear.hpp"

#include "constraints/KernelConstraintAD.hpp"

namespace flexsens {

template <class T>
VecT<T> BilinearConstraint::phiT(const LocalState&, const VecT<T>& x, const VecT<T>&) const {
  // Fixed-size 3-vectors: no heap traffic per call (the satellite evaluates ~80 of these per
  // Newton iteration).
  Eigen::Matrix<T, 3, 1> a = N_.cast<T>().lazyProduct(x), b = W_.cast<T>().lazyProduct(x);
  for (int i = 0; i < 3; ++i) {
    a[i] += a0_[i];
    b[i] += b0_[i];
  }
  VecT<T> out(1);
  out[0] = a.dot(b) - c0_;
  return out;
}

namespace {
/// c with N = [c_0 I, c_1 I, ...] (3 x 3 blocks), or empty when N is not of that form.
VecX blockScalars(const MatX& N) {
  if (N.rows() != 3 || N.cols() % 3 != 0) return VecX();
  VecX c(N.cols() / 3);
  for (Eigen::Index k = 0; k < c.size(); ++k) {
    c[k] = N(0, 3 * k);
    if (N.block(0, 3 * k, 3, 3) != c[k] * Eigen::Matrix3d::Identity()) return VecX();
  }
  return c;
}
}  // namespace

BilinearConstraint::BilinearConstraint(std::string name, std::string kind, std::vector<int> nodes, MatX N,
                                       Eigen::Vector3d a0, MatX W, Eigen::Vector3d b0, double c0, int gradients)
    : KernelConstraint(std::move(name), std::move(nodes)), kind_(std::move(kind)), N_(std::move(N)),
      W_(std::move(W)), a0_(a0), b0_(b0), c0_(c0), H_(N_.transpose() * W_ + W_.transpose() * N_),
      gradients_(gradients), nc_(blockScalars(N_)), wc_(blockScalars(W_)) {
  if (nc_.size() == 0 || wc_.size() == 0) nc_.resize(0), wc_.resize(0);
}

void BilinearConstraint::factors(const VecX& x, Eigen::Vector3d& a, Eigen::Vector3d& b) const {
  if (nc_.size() == 0) {
    a = N_.lazyProduct(x) + a0_;
    b = W_.lazyProduct(x) + b0_;
    return;
  }
  a = a0_;
  b = b0_;
  for (Eigen::Index k = 0; k < nc_.size(); ++k) {
    a += nc_[k] * x.segment<3>(3 * k);
    b += wc_[k] * x.segment<3>(3 * k);
  }
}

void BilinearConstraint::phi(const LocalState& s, VecX& out) const {
  // phiT<double> without its returned vector: the residual evaluates every constraint at
  // every Newton iteration, and that allocation was ~3% of the satellite's run.
  Eigen::Vector3d a, b;
  factors(s.x, a, b);
  out.resize(1);
  out[0] = a.dot(b) - c0_;
}

void BilinearConstraint::jacobian(const LocalState& s, MatX& J) const {
  // d/dx [(N x + a0) . (W x + b0)] = (W x + b0)^T N + (N x + a0)^T W
  Eigen::Vector3d a, b;
  factors(s.x, a, b);
  J.resize(1, N_.cols());
  if (nc_.size() == 0) {
    // Coefficient-wise (lazy) products: 3 x ~15 is far below where Eigen's gemv kernel pays.
    J.noalias() = b.transpose().lazyProduct(N_) + a.transpose().lazyProduct(W_);
    return;
  }
  for (Eigen::Index k = 0; k < nc_.size(); ++k) J.block<1, 3>(0, 3 * k) = nc_[k] * b.transpose() + wc_[k] * a.transpose();
}

std::unique_ptr<BilinearConstraint> BilinearConstraint::perpendicular(std::string name, std::vector<int> nodes,
                                                                      double c0) {
  MatX N = MatX::Zero(3, 12), W = MatX::Zero(3, 12);
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  N.block<3, 3>(0, 0) = -I;
  N.block<3, 3>(0, 3) = I;
  W.block<3, 3>(0, 6) = -I;
  W.block<3, 3>(0, 9) = I;
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  return std::make_unique<BilinearConstraint>(std::move(name), "perpendicular", std::move(nodes), N, zero, W,
                                              zero, c0);
}

std::unique_ptr<BilinearConstraint> BilinearConstraint::pointOnBodyPlane(
    std::string name, const std::vector<int>& basic, const Eigen::Matrix<double, 3, 4>& X0, int point,
    const Eigen::Vector3d& origin, const Eigen::Vector3d& normal) {
  Eigen::Matrix3d E;
  for (int j = 0; j < 3; ++j) E.col(j) = X0.col(j + 1) - X0.col(0);
  const Eigen::PartialPivLU<Eigen::Matrix3d> lu(E);
  const Eigen::Vector3d cn = lu.solve(normal.normalized());  // n = E cn
  const Eigen::Vector3d co = lu.solve(origin - X0.col(0));   // o = x_A + E co
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  MatX N = MatX::Zero(3, 15), W = MatX::Zero(3, 15);
  for (int j = 0; j < 3; ++j) {
    N.block<3, 3>(0, 0) -= cn[j] * I;
    N.block<3, 3>(0, 3 * (j + 1)) += cn[j] * I;
    W.block<3, 3>(0, 0) += co[j] * I;  // - o = -x_A - sum co_j (x_Bj - x_A)
    W.block<3, 3>(0, 3 * (j + 1)) -= co[j] * I;
  }
  W.block<3, 3>(0, 0) -= I;
  W.block<3, 3>(0, 12) += I;
  std::vector<int> nodes = basic;
  nodes.push_back(point);
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  return std::make_unique<BilinearConstraint>(std::move(name), "point_on_plane", nodes, N, zero, W, zero, 0.0);
}

std::unique_ptr<BilinearConstraint> BilinearConstraint::pointOnFixedPlane(std::string name, int point,
                                                                          const Eigen::Vector3d& origin,
                                                                          const Eigen::Vector3d& normal) {
  // Linear: the normal is the constant first factor, (x_P - origin) the second.
  return std::make_unique<BilinearConstraint>(std::move(name), "point_on_plane", std::vector<int>{point},
                                              MatX::Zero(3, 3), normal.normalized(), MatX::Identity(3, 3),
                                              Eigen::Vector3d(-origin), 0.0);
}

template class KernelConstraint<BilinearConstraint>;

}  // namespace flexsens
