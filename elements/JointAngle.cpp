#include "elements/JointAngle.hpp"

#include "elements/BodyTriad.hpp"

namespace flexsens {

using triad::skew;

MatX jointAngleHessian(const VecX& x) {
  using V3 = Eigen::Vector3d;
  using M3 = Eigen::Matrix3d;
  using V9 = Eigen::Matrix<double, 9, 1>;
  using M9 = Eigen::Matrix<double, 9, 9>;
  const V3 n = x.segment<3>(3) - x.segment<3>(0);
  const V3 w1 = x.segment<3>(9) - x.segment<3>(6);
  const V3 w2 = x.segment<3>(15) - x.segment<3>(12);
  const M3 I = M3::Identity();
  const double nn = n.dot(n), L = std::sqrt(nn);
  // Work in y = (n, w1, w2); blocks (0, 1, 2).
  auto put = [](M9& H, int i, int j, const M3& B) { H.block<3, 3>(3 * i, 3 * j) += B; };
  auto vec = [](const V3& a, const V3& b, const V3& c) {
    V9 r;
    r << a, b, c;
    return r;
  };
  // Triple product T = det[n, w1, w2]: trilinear.
  const double Tr = n.dot(w1.cross(w2));
  const V9 dT = vec(w1.cross(w2), w2.cross(n), n.cross(w1));
  M9 hT = M9::Zero();
  put(hT, 0, 1, -skew(w2));
  put(hT, 1, 0, skew(w2));
  put(hT, 0, 2, skew(w1));
  put(hT, 2, 0, -skew(w1));
  put(hT, 1, 2, -skew(n));
  put(hT, 2, 1, skew(n));
  // 1/L and its derivatives (n only).
  const V9 dInvL = vec(-n / (L * nn), V3::Zero(), V3::Zero());
  M9 hInvL = M9::Zero();
  put(hInvL, 0, 0, -I / (L * nn) + 3.0 * n * n.transpose() / (L * nn * nn));
  // s = T / L
  const double s = Tr / L;
  const V9 ds = dT / L + Tr * dInvL;
  const M9 hs = hT / L + dT * dInvL.transpose() + dInvL * dT.transpose() + Tr * hInvL;
  // c = w1.w2 - a b kappa, a = n.w1, b = n.w2, kappa = 1/nn
  const double a = n.dot(w1), b = n.dot(w2), kappa = 1.0 / nn;
  const V9 da = vec(w1, n, V3::Zero()), db = vec(w2, V3::Zero(), n);
  const V9 dd = vec(V3::Zero(), w2, w1), dk = vec(-2.0 * kappa * kappa * n, V3::Zero(), V3::Zero());
  M9 ha = M9::Zero(), hb = M9::Zero(), hd = M9::Zero(), hk = M9::Zero();
  put(ha, 0, 1, I);
  put(ha, 1, 0, I);
  put(hb, 0, 2, I);
  put(hb, 2, 0, I);
  put(hd, 1, 2, I);
  put(hd, 2, 1, I);
  put(hk, 0, 0, -2.0 * kappa * kappa * I + 8.0 * kappa * kappa * kappa * n * n.transpose());
  const double c = w1.dot(w2) - a * b * kappa;
  const V9 dc = dd - (b * kappa * da + a * kappa * db + a * b * dk);
  const M9 hc = hd - (kappa * (da * db.transpose() + db * da.transpose()) + b * kappa * ha + a * kappa * hb +
                      b * (da * dk.transpose() + dk * da.transpose()) +
                      a * (db * dk.transpose() + dk * db.transpose()) + a * b * hk);
  // theta = atan2(s, c)
  const double r2 = s * s + c * c;
  const V9 g = (c * ds - s * dc) / r2;
  const M9 hy = (c * hs - s * hc + ds * dc.transpose() - dc * ds.transpose()) / r2 -
                2.0 * g * (s * ds + c * dc).transpose() / r2;
  // Back to the six points: y = B x with n = x1 - x0, w1 = x3 - x2, w2 = x5 - x4.
  Eigen::Matrix<double, 9, 18> B = Eigen::Matrix<double, 9, 18>::Zero();
  for (int k = 0; k < 3; ++k) {
    B.block<3, 3>(3 * k, 6 * k) = -I;
    B.block<3, 3>(3 * k, 6 * k + 3) = I;
  }
  return B.transpose() * hy * B;
}

}  // namespace flexsens
