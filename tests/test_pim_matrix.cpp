// The PIM matrix's factorization and condition estimate (pim/PimMatrix.hpp) against the dense
// SVD, and its errors.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <random>

#include "pim/PimMatrix.hpp"

namespace flexsens {
namespace {

/// A nonsymmetric sparse n x n matrix: a spread diagonal (1 .. 1e3) plus random couplings.
SpMat testMatrix(int n, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> col(0, n - 1);
  std::vector<Eigen::Triplet<double, int64_t>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, std::pow(1e3, double(i) / (n - 1)));
    for (int k = 0; k < 3; ++k) t.emplace_back(i, col(gen), u(gen));
  }
  SpMat A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

std::vector<std::string> labels(int n) {
  std::vector<std::string> l;
  for (int i = 0; i < n; ++i) l.push_back("row " + std::to_string(i));
  return l;
}

TEST(PimMatrix, ConditionEstimateEqualsTheDenseSvdAndTheLuSolves) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const SpMat A = testMatrix(60, seed);
    const Eigen::JacobiSVD<MatX> svd{MatX(A)};
    const VecX sv = svd.singularValues();
    const FactoredPimMatrix f = factorPimMatrix(A, labels(60), "test", "");
    EXPECT_NEAR(f.condition / (sv[0] / sv[sv.size() - 1]), 1.0, 1e-4) << "seed " << seed;
    const VecX b = VecX::LinSpaced(60, -1.0, 2.0);
    EXPECT_LT((A * f.lu->solve(b) - b).norm(), 1e-12 * b.norm());
  }
}

TEST(PimMatrix, ExactlyDependentRowsAreNamed) {
  SpMat A = testMatrix(20, 4);
  MatX D(A);
  D.row(7) = 2.0 * D.row(3);  // row 7 depends on row 3
  A = D.sparseView();
  try {
    factorPimMatrix(A, labels(20), "the test matrix", "Choose other rows");
    ADD_FAILURE() << "a singular matrix was accepted";
  } catch (const NumericalError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("the test matrix is rank-deficient"), std::string::npos) << m;
    EXPECT_NE(m.find("[row 3]"), std::string::npos) << m;
    EXPECT_NE(m.find("[row 7]"), std::string::npos) << m;
    EXPECT_NE(m.find("Choose other rows"), std::string::npos) << m;
  }
}

TEST(PimMatrix, NearlyDependentRowsGiveTheConditionEstimate) {
  SpMat A = testMatrix(20, 5);
  MatX D(A);
  D.row(7) = 2.0 * D.row(3);
  D(7, 0) += 1e-9;  // nearly dependent: condition ~1e12
  A = D.sparseView();
  try {
    factorPimMatrix(A, labels(20), "the test matrix", "");
    ADD_FAILURE() << "a near-singular matrix was accepted";
  } catch (const NumericalError& e) {
    const std::string m = e.what();
    EXPECT_TRUE(m.find("near-singular (condition estimate") != std::string::npos ||
                m.find("rank-deficient") != std::string::npos) << m;
  }
}

}  // namespace
}  // namespace flexsens
