// Micro-benchmark of the continuum and shell element kernels (not a test; bench/kernels,
// README.md there): for each kernel, one force() + forceJacobian() call of the library's
// element against the plain fixed-size reference of Reference.hpp at the same state, with
//   ratio   the element's time over the reference's (best of several batches each, alternated),
//   GFLOP/s the nominal flop count of one force + tangent over the element's time,
//   allocs  heap allocations per element call (malloc counted, MallocCounter.cpp),
//   diff    max |element - reference| / max |reference| of the tangent (and of the force).
//
//   flexsens_bench_kernels [--seconds S]   (S: target time per batch, default 0.05 s)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "MallocCounter.hpp"
#include "Reference.hpp"
#include "elements/ShellClampHinge.hpp"
#include "elements/ShellHinge.hpp"
#include "elements/ShellTriangle.hpp"
#include "elements/Solid.hpp"

using namespace flexsens;

namespace {

double batchSeconds = 0.05;

/// Best time per call [s] of f over 7 batches of `reps` calls.
double bestPerCall(const std::function<void()>& f, long reps) {
  double best = 1e300;
  for (int b = 0; b < 7; ++b) {
    const auto t0 = std::chrono::steady_clock::now();
    for (long r = 0; r < reps; ++r) f();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / reps);
  }
  return best;
}

/// Calls per batch so that one batch of f takes about batchSeconds.
long calibrate(const std::function<void()>& f) {
  long reps = 1;
  for (;;) {
    const auto t0 = std::chrono::steady_clock::now();
    for (long r = 0; r < reps; ++r) f();
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (s > 0.2 * batchSeconds) return std::max(1L, long(reps * batchSeconds / s));
    reps *= 4;
  }
}

double relDiff(const MatX& a, const MatX& b) {
  const double scale = b.lpNorm<Eigen::Infinity>();
  return scale > 0.0 ? (a - b).lpNorm<Eigen::Infinity>() / scale : (a - b).lpNorm<Eigen::Infinity>();
}

/// One kernel: the library element at state s and its reference (force into Qr, tangent into Kr).
struct Case {
  std::string name;
  std::shared_ptr<Element> element;
  LocalState s;
  std::function<void(VecX& Qr, MatX& Kr)> reference;
  double flops;  ///< nominal flops of one force + tangent
};

void run(Case& c) {
  VecX Q, Qr;
  MatX K, Kv, Kr;
  auto elementCall = [&] {
    c.element->force(c.s, Q);
    c.element->forceJacobian(c.s, K, Kv);
  };
  auto referenceCall = [&] { c.reference(Qr, Kr); };
  elementCall();
  referenceCall();
  const double dK = relDiff(K, Kr), dQ = relDiff(Q, Qr);
  const std::size_t a0 = bench::allocations();
  elementCall();
  const double allocs = double(bench::allocations() - a0);
  const long repsE = calibrate(elementCall), repsR = calibrate(referenceCall);
  double tE = 1e300, tR = 1e300;
  for (int round = 0; round < 3; ++round) {  // alternated: both see the same load
    tE = std::min(tE, bestPerCall(elementCall, repsE));
    tR = std::min(tR, bestPerCall(referenceCall, repsR));
  }
  std::printf("%-26s %10.2f %10.2f %7.2f %8.2f %7.0f %9.1e %9.1e\n", c.name.c_str(), tE * 1e6, tR * 1e6, tE / tR,
              c.flops / tE * 1e-9, allocs, dK, dQ);
}

// ------------------------------------------------------------------ continuum cases
template <int DS, int DM, int N, int NP>
double continuumFlops() {
  constexpr int ND = DS * N, NV = DM == 2 ? 3 : 6;
  const double perPoint = 2.0 * DS * DM * N + 2.0 * DM * DM * DS       // F, C
                          + 2.0 * DS * DM * DM + 2.0 * DS * DM * N      // P = F S, forces
                          + 2.0 * NV * NV * ND + 2.0 * ND * ND * NV     // B^T (D B)
                          + 2.0 * N * DM * DM + 2.0 * N * N * DM + N * N * DS;  // G S G^T (x) I
  return NP * perPoint;
}

LocalState stateOf(const VecX& x, int dim) {
  static const VecX none;  // no parameters: every property a constant
  LocalState s;
  s.dim = dim;
  s.x = x;
  s.v = VecX::Zero(x.size());
  s.p = &none;
  s.gravity = nullptr;
  return s;
}

MatX restSimplex(Simplex shape) {
  const int d = simplexDim(shape), n = simplexNodes(shape);
  MatX X(d, n);
  if (d == 2) X.leftCols(3) << 0.0, 0.04, 0.01, 0.0, 0.005, 0.035;
  else X.leftCols(4) << 0.0, 0.04, 0.01, 0.008, 0.0, 0.005, 0.035, 0.01, 0.0, 0.004, 0.006, 0.038;
  const auto edges = simplexEdges(shape);
  for (size_t k = 0; k < edges.size(); ++k) X.col(d + 1 + k) = 0.5 * (X.col(edges[k].first) + X.col(edges[k].second));
  return X;
}

template <int D, int N, int NP>
Case solidCase(const std::string& name, Simplex shape, Law law) {
  const double E = 2.0e6, nu = 0.3;
  auto props = std::make_shared<SolidProperties>();
  props->dim = D;
  props->E = {E, -1};
  props->nu = {nu, -1};
  props->density = {1000.0, -1};
  props->law = {law, D == 2 ? PlanarState::PlaneStress : PlanarState::None};
  const MatX X = restSimplex(shape);
  auto reference = std::make_shared<ref::Continuum<D, D, N, NP>>();
  reference->mat = {E / (2 * (1 + nu)), E * nu / ((1 + nu) * (1 - 2 * nu)),
                    law == Law::NeoHookean ? ref::Law::NeoHookean : ref::Law::SaintVenantKirchhoff, D == 2};
  const SimplexRule rule = stiffnessRule(shape);
  for (int g = 0; g < NP; ++g) {
    VecX Nv;
    MatX dN;
    simplexShape(shape, rule.x[g], Nv, dN);
    const MatX J = X * dN;
    reference->G[g] = dN * J.inverse();
    reference->w[g] = rule.w[g] * J.determinant();
  }
  std::srand(11);
  const VecX x = Eigen::Map<const VecX>(X.data(), X.size()) + 0.003 * VecX::Random(D * N);
  Case c{name, std::make_shared<Solid>(name, std::vector<int>(N, 0), props, shape, X), stateOf(x, D), {},
         continuumFlops<D, D, N, NP>()};
  c.reference = [reference, x](VecX& Qr, MatX& Kr) {
    typename ref::Continuum<D, D, N, NP>::Vec Q;
    typename ref::Continuum<D, D, N, NP>::Mat K;
    reference->forceAndTangent(x.data(), Q, K);
    Qr = Q;
    Kr = K;
  };
  return c;
}

// ------------------------------------------------------------------ shell cases
std::shared_ptr<ShellProperties> shellProps(Law law) {
  auto pr = std::make_shared<ShellProperties>();
  pr->E = {4.0e9, -1};
  pr->nu = {0.38, -1};
  pr->density = {1380.0, -1};
  pr->thickness = {5e-4, -1};
  pr->law.law = law;
  return pr;
}

Case shellTriangleCase(const std::string& name, Law law) {
  const auto pr = shellProps(law);
  VecX X(9);
  X << 0.0, 0.0, 0.0, 0.025, 0.002, 0.001, 0.006, 0.022, -0.002;
  const Eigen::Vector3d e1 = X.segment<3>(3) - X.segment<3>(0), e2 = X.segment<3>(6) - X.segment<3>(0);
  const Eigen::Vector3d n = e1.cross(e2), t1 = e1.normalized(), t2 = n.normalized().cross(t1);
  Eigen::Matrix2d Dm;
  Dm << e1.dot(t1), e2.dot(t1), e1.dot(t2), e2.dot(t2);
  const Eigen::Matrix2d Di = Dm.inverse();
  auto reference = std::make_shared<ref::Continuum<3, 2, 3, 1>>();
  reference->G[0] << -(Di.row(0) + Di.row(1)), Di.row(0), Di.row(1);
  reference->w[0] = 0.5 * n.norm() * pr->thickness.constant;
  const double E = pr->E.constant, nu = pr->nu.constant;
  reference->mat = {E / (2 * (1 + nu)), E * nu / ((1 + nu) * (1 - 2 * nu)),
                    law == Law::NeoHookean ? ref::Law::NeoHookean : ref::Law::SaintVenantKirchhoff, true};
  std::srand(13);
  const VecX x = X + 0.0005 * VecX::Random(9);
  Case c{name, std::make_shared<ShellTriangle>(name, std::vector<int>{0, 1, 2}, pr, X), stateOf(x, 3), {},
         continuumFlops<3, 2, 3, 1>()};
  c.reference = [reference, x](VecX& Qr, MatX& Kr) {
    ref::Continuum<3, 2, 3, 1>::Vec Q;
    ref::Continuum<3, 2, 3, 1>::Mat K;
    reference->forceAndTangent(x.data(), Q, K);
    Qr = Q;
    Kr = K;
  };
  return c;
}

/// Nominal flops of the hinge's angle, gradient, Hessian and force + tangent (counted from
/// Reference.hpp's expressions: the 9 x 9 Hessians ~1400, B^T Hu B as block sums ~400, the
/// 12 x 12 tangent ~450, the rest ~250).
constexpr double kHingeFlops = 2500.0;

double bendingStiffnessOf(const ShellProperties& pr) {
  const double E = pr.E.constant, nu = pr.nu.constant, t = pr.thickness.constant;
  return E * t * t * t / (12.0 * (1.0 - nu * nu));
}

Case hingeCase() {
  const auto pr = shellProps(Law::SaintVenantKirchhoff);
  Eigen::Matrix<double, 12, 1> X;
  X << 0.0, 0.0, 0.0, 0.025, 0.0, 0.0, 0.012, 0.021, 0.0, 0.013, -0.022, 0.001;
  auto reference = std::make_shared<ref::Hinge>();
  Eigen::Matrix<double, 12, 1> g;
  Eigen::Matrix<double, 12, 12> H;
  reference->theta0 = ref::Hinge::angle(X, g, H);
  const Eigen::Vector3d e = X.segment<3>(3) - X.segment<3>(0);
  const double A1 = 0.5 * e.cross(X.segment<3>(6) - X.segment<3>(0)).norm();
  const double A2 = 0.5 * e.cross(X.segment<3>(9) - X.segment<3>(0)).norm();
  reference->k = bendingStiffnessOf(*pr) * e.squaredNorm() / (A1 + A2);
  std::srand(17);
  const VecX x = X + 0.002 * VecX::Random(12);
  Case c{"shell hinge", std::make_shared<ShellHinge>("hinge", std::vector<int>{0, 1, 2, 3}, pr, VecX(X)),
         stateOf(x, 3), {}, kHingeFlops};
  c.reference = [reference, x](VecX& Qr, MatX& Kr) {
    ref::Hinge::Vec12 Q;
    ref::Hinge::Mat12 K;
    reference->forceAndTangent(x, Q, K);
    Qr = Q;
    Kr = K;
  };
  return c;
}

Case clampCase() {
  const auto pr = shellProps(Law::SaintVenantKirchhoff);
  Eigen::Matrix<double, 9, 1> X;
  X << 0.0, 0.0, 0.0, 0.025, 0.0, 0.0, 0.012, 0.021, 0.0;
  auto reference = std::make_shared<ref::Clamp>();
  const Eigen::Vector3d X0 = X.segment<3>(0), e = X.segment<3>(3) - X0, a = X.segment<3>(6) - X0;
  const Eigen::Vector3d along = e.dot(a) / e.squaredNorm() * e;
  reference->ghost = X0 + along - (a - along);
  ref::Hinge::Vec12 y, g;
  ref::Hinge::Mat12 H;
  y << X, reference->ghost;
  reference->hinge.theta0 = ref::Hinge::angle(y, g, H);
  reference->hinge.k = bendingStiffnessOf(*pr) * e.squaredNorm() / (0.5 * e.cross(a).norm());
  std::srand(19);
  const VecX x = X + 0.002 * VecX::Random(9);
  Case c{"shell clamp", std::make_shared<ShellClampHinge>("clamp", std::vector<int>{0, 1, 2}, pr, VecX(X)),
         stateOf(x, 3), {}, kHingeFlops};
  c.reference = [reference, x](VecX& Qr, MatX& Kr) {
    ref::Clamp::Vec9 Q;
    ref::Clamp::Mat9 K;
    reference->forceAndTangent(x, Q, K);
    Qr = Q;
    Kr = K;
  };
  return c;
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i + 1 < argc; ++i)
    if (!std::strcmp(argv[i], "--seconds")) batchSeconds = std::atof(argv[i + 1]);
  std::vector<Case> cases;
  cases.push_back(solidCase<3, 10, 4>("tet10 neo-Hookean", Simplex::Tet10, Law::NeoHookean));
  cases.push_back(solidCase<3, 10, 4>("tet10 St.Venant-Kirchhoff", Simplex::Tet10, Law::SaintVenantKirchhoff));
  cases.push_back(solidCase<3, 4, 1>("tet4 neo-Hookean", Simplex::Tet4, Law::NeoHookean));
  cases.push_back(solidCase<2, 6, 3>("tri6 neo-Hookean p.stress", Simplex::Tri6, Law::NeoHookean));
  cases.push_back(solidCase<2, 3, 1>("tri3 neo-Hookean p.stress", Simplex::Tri3, Law::NeoHookean));
  cases.push_back(shellTriangleCase("shell triangle SVK", Law::SaintVenantKirchhoff));
  cases.push_back(shellTriangleCase("shell triangle neo-Hookean", Law::NeoHookean));
  cases.push_back(hingeCase());
  cases.push_back(clampCase());
  std::printf("force + tangent per call; ratio = element / fixed-size reference (bench/kernels/Reference.hpp)\n");
  std::printf("%-26s %10s %10s %7s %8s %7s %9s %9s\n", "kernel", "elem [us]", "ref [us]", "ratio", "GFLOP/s",
              "allocs", "diff K", "diff Q");
  for (Case& c : cases) run(c);
  return 0;
}
