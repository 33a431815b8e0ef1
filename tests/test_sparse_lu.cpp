// The sparse LU of saddle-point matrices (core/SparseLU, core/SaddlePointOrdering): solutions
// against a dense LU, the ordering's promise (no pivot off the diagonal, fill near nnz(A)),
// the refinement near a singular constraint Jacobian, and the fill of the satellite's real
// Newton matrices (a counter no machine changes: KLU's own ordering filled 7.8x at refine 2).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "app/Run.hpp"
#include "core/SaddlePointOrdering.hpp"
#include "core/SparseLU.hpp"
#include "TestModels.hpp"

using namespace flexsens;

namespace {

/// [A B^T; B 0]: A a chain of n light nodes (mass/h^2 on the diagonal, springs of stiffness k
/// between neighbours), B one row per node (each node on a plane through a heavy body whose
/// `heavy` coordinates every row touches: the satellite's springs on the cube's faces).
SpMat chainOnABody(int n, int heavy, double mass, double k, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(0.5, 1.5);
  const int N = n + heavy, m = n;
  std::vector<Eigen::Triplet<double, int64_t>> t;
  for (int i = 0; i < N; ++i) t.emplace_back(i, i, (i < n ? mass : 100.0) * u(gen));
  for (int i = 0; i + 1 < n; ++i) {
    t.emplace_back(i, i, k);
    t.emplace_back(i + 1, i + 1, k);
    t.emplace_back(i, i + 1, -k);
    t.emplace_back(i + 1, i, -k);
  }
  for (int r = 0; r < m; ++r) {
    auto put = [&](int c, double v) {
      t.emplace_back(N + r, c, v);
      t.emplace_back(c, N + r, v);
    };
    put(r, u(gen));
    for (int h = 0; h < heavy; ++h) put(n + h, u(gen) - 1.0);
  }
  SpMat A(N + m, N + m);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

}  // namespace

TEST(SparseLU, SolvesSaddlePointSystemsLikeADenseLUWithDiagonalPivotsAndLittleFill) {
  for (const double mass : {1e3, 1.0, 1e-3}) {  // light nodes beside stiff springs: small pivots
    const SpMat A = chainOnABody(400, 12, mass, 1e4, 7);
    SparseLU lu;
    lu.factor(A, "test matrix");
    const VecX b = VecX::LinSpaced(A.rows(), -1.0, 2.0);
    const VecX x = lu.solve(b);
    const VecX xd = MatX(A).fullPivLu().solve(b);
    const double err = (x - xd).lpNorm<Eigen::Infinity>() / xd.lpNorm<Eigen::Infinity>();
    std::printf("  node mass %g: fill %.3f, off-diagonal pivots %ld, |x - x_dense| / |x| = %.2e\n", mass,
                lu.fill(), lu.offDiagonalPivots(), err);
    EXPECT_LT(err, 1e-10);
    EXPECT_EQ(lu.offDiagonalPivots(), 0);
    // Each multiplier after its light node, the 12 dense coordinates last: L + U hold A's
    // entries plus a 12-wide border (each eliminated multiplier couples the next node to the
    // body): about 1.9 nnz(A), the same at four times the size (linear fill).
    SparseLU big;
    big.factor(chainOnABody(1600, 12, mass, 1e4, 7), "test matrix");
    std::printf("  fill at n = 1612: %.3f\n", big.fill());
    EXPECT_LT(lu.fill(), 2.5);
    EXPECT_NEAR(big.fill(), lu.fill(), 0.02 * lu.fill());
  }
}

TEST(SaddlePointOrdering, EachMultiplierFollowsItsLightCoordinate) {
  // 400 light nodes: the 12 heavy coordinates have degree 411 in the coordinates' graph, above
  // AMD's dense limit 10 sqrt(412) = 203, so they do not hold the multipliers back.
  const SpMat A = chainOnABody(400, 12, 1.0, 1.0, 3);
  const std::vector<int64_t> perm = saddlePointOrdering(A);
  ASSERT_EQ(static_cast<Eigen::Index>(perm.size()), A.rows());
  std::vector<int64_t> pos(perm.size());
  for (size_t k = 0; k < perm.size(); ++k) pos[perm[k]] = static_cast<int64_t>(k);
  std::vector<int64_t> sorted = perm;
  std::sort(sorted.begin(), sorted.end());
  for (size_t k = 0; k < sorted.size(); ++k) ASSERT_EQ(sorted[k], static_cast<int64_t>(k));  // a permutation
  const int N = 412;
  for (int r = 0; r < 400; ++r) EXPECT_EQ(pos[N + r], pos[r] + 1) << "multiplier " << r;
}

TEST(SparseLU, RefinementKeepsTheBackwardErrorAtRoundOffNearASingularJacobian) {
  // Two constraint rows that become parallel as eps -> 0: the second multiplier's Schur pivot
  // is O(eps^2). The componentwise backward error of every solve stays at round-off.
  for (const double eps : {1e-3, 1e-5, 1e-7}) {
    SpMat A = chainOnABody(60, 3, 1e-2, 1e3, 11);
    A.coeffRef(63 + 1, 0) = A.coeff(63, 0) * (1.0 + eps);  // row 2 ~ row 1 on node 0 as well
    A.coeffRef(0, 63 + 1) = A.coeff(63 + 1, 0);
    A.makeCompressed();
    SparseLU lu;
    lu.factor(A, "near-singular test matrix");
    const VecX b = VecX::Ones(A.rows());
    const VecX x = lu.solve(b);
    const VecX r = b - A * x;
    const VecX scale = SpMat(A.cwiseAbs()) * x.cwiseAbs() + b.cwiseAbs();
    const double omega = (r.cwiseAbs().array() / scale.array()).maxCoeff();
    std::printf("  eps %g: componentwise backward error %.2e\n", eps, omega);
    EXPECT_LT(omega, 1e-14);
  }
}

TEST(SparseLU, SatelliteNewtonMatricesFillLittleAtEveryRefinement) {
  // The satellite without its PIM cases, segments x1 and x3, BDF-1 for 5 steps: summary.json's
  // lu_fill, the largest nnz(L+U)/nnz(A) of its Newton matrices (KLU's AMD: 4.8x and 7.8x at
  // x1 and x2; bench/linear).
  std::ifstream in(test::sourceDir() + "/examples/satellite/satellite.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string original = ss.str();
  for (int refine : {1, 3}) {
    std::string text = original.substr(0, original.find("\ncases:")) +
                       original.substr(original.find("\nintegrator:"));
    for (size_t at = text.find("segments: "); at != std::string::npos; at = text.find("segments: ", at + 1)) {
      const size_t end = text.find_first_of(",}", at);
      const int s = std::atoi(text.substr(at + 10, end - at - 10).c_str());
      if (s > 1) text.replace(at + 10, end - at - 10, std::to_string(s * refine));
    }
    text.replace(text.find("gmsh: "), 6, "gmsh: " + test::sourceDir() + "/examples/satellite/");
    const std::string dir = ::testing::TempDir() + "/sat_fill_" + std::to_string(refine);
    const std::string scene = dir + ".yaml";
    std::filesystem::remove_all(dir);  // output of an earlier build of this test: not necessarily a flexsens run of this layout
    std::ofstream(scene) << text;
    const std::string cmd = std::string(FLEXSENS_EXE) + " run " + scene + " --allow-path " + test::sourceDir() + " --integrator bdf1 --t-end 0.1 --out " +
                            dir + " > /dev/null 2>&1";
    const int rc = std::system(cmd.c_str());
    ASSERT_TRUE(WEXITSTATUS(rc) == 0 || WEXITSTATUS(rc) == 5) << cmd;
    std::ifstream js(dir + "/summary.json");
    std::stringstream all;
    all << js.rdbuf();
    const std::string s = all.str();
    const size_t at = s.find("\"lu_fill\": ");
    ASSERT_NE(at, std::string::npos);
    const double fill = std::atof(s.c_str() + at + 11);
    std::printf("  refine %d: lu_fill %.3f\n", refine, fill);
    // nnz(L + U) / nnz(A): 1.26 / 1.28 while A held the constant Hessians' zero entries, 1.81 /
    // 1.84 without them for the same L + U (KLU's own ordering: 4.8x and 7.8x of the A with them).
    EXPECT_GT(fill, 1.0);
    EXPECT_LT(fill, 2.0);
  }
}

namespace {
/// A 2D Laplacian-like stiffness on a g x g grid plus a mass diagonal: symmetric positive
/// definite, the pattern of a meshed body's Newton matrix. `skew` adds an unsymmetric part
/// (a follower load's dQ/dq), `shift` subtracts from the diagonal (indefinite when large).
SpMat gridMatrix(int g, double skew, double shift) {
  const int n = g * g;
  std::vector<Eigen::Triplet<double, int64_t>> t;
  for (int i = 0; i < g; ++i)
    for (int j = 0; j < g; ++j) {
      const int k = i * g + j;
      t.emplace_back(k, k, 4.5 - shift);
      if (j + 1 < g) t.emplace_back(k, k + 1, -1.0 + skew), t.emplace_back(k + 1, k, -1.0 - skew);
      if (i + 1 < g) t.emplace_back(k, k + g, -1.0), t.emplace_back(k + g, k, -1.0);
    }
  SpMat A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}
}  // namespace

// Symmetric positive definite matrices go to CHOLMOD's Cholesky, unsymmetric and indefinite
// ones to KLU; all three solutions equal a dense LU's to 1e-12, three right-hand sides at once
// equal three single solves, and the backward error is round-off.
TEST(SparseLU, CholeskyForSymmetricPositiveDefiniteKluForTheRest) {
  struct Case { double skew, shift; bool cholesky; };
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  // shift 2: positive diagonal, indefinite (CHOLMOD tries and stops); shift 5: negative diagonal
  for (const Case c : {Case{0.0, 0.0, true}, Case{0.3, 0.0, false}, Case{0.0, 2.0, false}, Case{0.0, 5.0, false}}) {
    const SpMat A = gridMatrix(30, c.skew, c.shift);
    SparseLU lu;
    lu.factor(A, "test matrix");
    EXPECT_EQ(lu.choleskyFactorizations(), c.cholesky ? 1 : 0) << c.skew << " " << c.shift;
    MatX B(A.rows(), 3);
    for (Eigen::Index i = 0; i < B.size(); ++i) B.data()[i] = u(rng);
    MatX X = B;
    lu.solve(X);
    const MatX dense = Eigen::MatrixXd(A).partialPivLu().solve(B);
    EXPECT_LT((X - dense).cwiseAbs().maxCoeff(), 1e-12 * dense.cwiseAbs().maxCoeff());
    for (int col = 0; col < 3; ++col) {
      const VecX x = lu.solve(VecX(B.col(col)));
      EXPECT_LT((x - X.col(col)).cwiseAbs().maxCoeff(), 1e-14 * X.cwiseAbs().maxCoeff());
      const VecX r = A * x - B.col(col);
      const VecX scale = A.cwiseAbs() * x.cwiseAbs() + VecX(B.col(col).cwiseAbs());
      EXPECT_LT(r.cwiseQuotient(scale).cwiseAbs().maxCoeff(), 1e-14);
    }
    // The transposed solve with the same factors (KLU's tsolve; Cholesky: A is symmetric),
    // against the dense LU of A^T (the skewed matrix is not symmetric: A^T x != A x).
    const VecX b = B.col(0);
    const VecX xt = lu.solveTransposed(b);
    const VecX denseT = Eigen::MatrixXd(A).transpose().partialPivLu().solve(b);
    EXPECT_LT((xt - denseT).cwiseAbs().maxCoeff(), 1e-11 * denseT.cwiseAbs().maxCoeff()) << c.skew << " " << c.shift;
  }
}
