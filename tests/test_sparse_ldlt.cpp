// The LDL^T path of core/SparseLU (MUMPS, core/MumpsFactor) for the Newton matrices of
// constrained continua [K, B^T; B, 0]: against the KLU path on the same matrices (a different
// factorization: LU in the saddle-point ordering), solves of several right-hand sides, the
// transposed solve, the matrices that stay on KLU, refinement near dependent constraint rows,
// and whole runs of a solid held by support rows whose motion, sensitivities and adjoint
// gradients equal the KLU path's.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "GradientChecks.hpp"
#include "core/SparseLU.hpp"
#include "scene/Scene.hpp"
#include "TestModels.hpp"

using namespace flexsens;

namespace {

/// FLEXSENS_LINEAR_SOLVER for the SparseLU objects made while it lives (read at construction).
struct SolverChoice {
  explicit SolverChoice(const char* choice) { setenv("FLEXSENS_LINEAR_SOLVER", choice, 1); }
  ~SolverChoice() { unsetenv("FLEXSENS_LINEAR_SOLVER"); }
};

/// [K, B^T; B, 0]: K a 3D elastic-like block on a g^3 grid (7-point stencil of stiffness k, a
/// mass diagonal), symmetric positive definite; B one row fixing each node of the face x = 0
/// (one entry: a support row) and `coupled` rows tying a node to the mean of four others (an
/// attach row). `shift` lowers K's diagonal (indefinite K when large).
SpMat constrainedGrid(int g, int coupled, double shift, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(0.5, 1.5);
  const int n = g * g * g;
  std::vector<Eigen::Triplet<double, int64_t>> t;
  auto node = [g](int i, int j, int k) { return (i * g + j) * g + k; };
  for (int i = 0; i < g; ++i)
    for (int j = 0; j < g; ++j)
      for (int k = 0; k < g; ++k) {
        const int a = node(i, j, k);
        t.emplace_back(a, a, 1e3 * u(gen) - shift);  // M/(beta h^2)
        for (int b : {i + 1 < g ? node(i + 1, j, k) : -1, j + 1 < g ? node(i, j + 1, k) : -1, k + 1 < g ? node(i, j, k + 1) : -1}) {
          if (b < 0) continue;
          const double s = 1e2 * u(gen);
          t.emplace_back(a, a, s), t.emplace_back(b, b, s), t.emplace_back(a, b, -s), t.emplace_back(b, a, -s);
        }
      }
  int row = n;
  auto put = [&](int c, double v) { t.emplace_back(row, c, v), t.emplace_back(c, row, v); };
  for (int j = 0; j < g; ++j)
    for (int k = 0; k < g; ++k, ++row) put(node(0, j, k), 1.0);
  for (int r = 0; r < coupled; ++r, ++row) {
    put(node(g - 1, r % g, (3 * r) % g), 1.0);
    for (int q = 0; q < 4; ++q) put(node(g / 2, (r + q) % g, (r + 2 * q) % g), -0.25 * u(gen));
  }
  SpMat A(row, row);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

/// Componentwise backward error max_i |b - A x|_i / (|A| |x| + |b|)_i, over all columns.
double backwardError(const SpMat& A, const MatX& X, const MatX& B) {
  double omega = 0.0;
  for (Eigen::Index c = 0; c < B.cols(); ++c) {
    const VecX r = (B.col(c) - A * X.col(c)).cwiseAbs();
    const VecX s = SpMat(A.cwiseAbs()) * X.col(c).cwiseAbs() + B.col(c).cwiseAbs();
    for (Eigen::Index i = 0; i < r.size(); ++i)
      if (r[i] != 0.0) omega = std::max(omega, r[i] / s[i]);
  }
  return omega;
}

MatX randomColumns(Eigen::Index rows, int cols, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  MatX B(rows, cols);
  for (Eigen::Index i = 0; i < B.size(); ++i) B.data()[i] = u(gen);
  return B;
}

}  // namespace

// A constrained continuum (n = 4096 coordinates, 256 support rows and 40 coupled rows) goes
// to LDL^T; its solutions of three right-hand sides at once equal KLU's to round-off with a
// componentwise backward error <= 1e-14, equal single solves, and the transposed solve is the
// same solve (A symmetric). Also with K indefinite (a symmetric-indefinite factorization).
TEST(SparseLDLT, ConstrainedContinuumSolvesLikeKlu) {
  for (const double shift : {0.0, 2.5e3}) {
    const SpMat A = constrainedGrid(16, 40, shift, 3);
    const MatX B = randomColumns(A.rows(), 3, 9);
    SparseLU ldlt;
    ldlt.factor(A, "test matrix");
    ASSERT_EQ(ldlt.ldltFactorizations(), 1) << shift;
    EXPECT_EQ(ldlt.choleskyFactorizations(), 0);
    MatX X = B;
    ldlt.solve(X);
    MatX Xklu = B;
    {
      SolverChoice klu("klu");
      SparseLU lu;
      lu.factor(A, "test matrix");
      EXPECT_EQ(lu.ldltFactorizations(), 0);
      lu.solve(Xklu);
    }
    const double omega = backwardError(A, X, B);
    std::printf("  shift %g: backward error LDL^T %.2e, KLU %.2e; fill %.2f, rcond %.2e\n", shift, omega,
                backwardError(A, Xklu, B), ldlt.fill(), ldlt.rcond());
    EXPECT_LE(omega, 1e-14);
    EXPECT_LT((X - Xklu).cwiseAbs().maxCoeff(), 1e-10 * Xklu.cwiseAbs().maxCoeff());
    for (int c = 0; c < 3; ++c) {
      const VecX x = ldlt.solve(VecX(B.col(c)));
      EXPECT_LT((x - X.col(c)).cwiseAbs().maxCoeff(), 1e-14 * X.cwiseAbs().maxCoeff());
      const VecX xt = ldlt.solveTransposed(VecX(B.col(c)));  // plain: no refinement
      EXPECT_LT((xt - X.col(c)).cwiseAbs().maxCoeff(), 1e-9 * X.cwiseAbs().maxCoeff());
    }
    EXPECT_GT(ldlt.fill(), 1.0);
    EXPECT_GT(ldlt.factorFlops(), 1e7);
    EXPECT_GT(ldlt.solveFlops(), 2.0 * double(A.nonZeros()));
    EXPECT_GT(ldlt.rcond(), 0.0);
    EXPECT_LT(ldlt.rcond(), 1.0);
  }
}

// FLEXSENS_LINEAR_SOLVER other than auto, cholesky or klu is refused with what it accepts.
TEST(SparseLDLT, UnknownSolverChoiceIsAnInputError) {
  SolverChoice choice("mumps");
  try {
    SparseLU lu;
    FAIL() << "FLEXSENS_LINEAR_SOLVER=mumps was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("expected auto, cholesky or klu"), std::string::npos) << e.what();
  }
}

// What stays on KLU: a small constrained matrix (a few MFLOP: KLU is faster there), an
// unsymmetric one (a follower load's dQ/dq), and a singular one (a repeated constraint row),
// which KLU reports as singular with the matrix's name.
TEST(SparseLDLT, SmallUnsymmetricAndSingularMatricesStayOnKlu) {
  auto expectKluSolves = [](const SpMat& A, const char* name, int columns, int seed) {
    SparseLU lu;
    lu.factor(A, name);
    EXPECT_EQ(lu.ldltFactorizations(), 0) << name;
    const MatX B = randomColumns(A.rows(), columns, seed);
    MatX X = B;
    lu.solve(X);
    EXPECT_LE(backwardError(A, X, B), 1e-14) << name;
  };
  expectKluSolves(constrainedGrid(6, 4, 0.0, 3), "small matrix", 1, 2);
  SpMat skew = constrainedGrid(16, 40, 0.0, 3);
  skew.coeffRef(1, 0) += 5.0;  // A(1, 0) != A(0, 1): an unsymmetric tangent entry
  expectKluSolves(skew, "unsymmetric matrix", 2, 4);
  {
    SpMat singular = constrainedGrid(16, 2, 0.0, 3);
    const Eigen::Index last = singular.rows() - 1, before = last - 1;  // the last row := the one before
    for (Eigen::Index j = 0; j < singular.cols(); ++j) {
      const double v = singular.coeff(before, j);
      if (v != 0.0 || singular.coeff(last, j) != 0.0) singular.coeffRef(last, j) = v, singular.coeffRef(j, last) = v;
    }
    singular.makeCompressed();
    SparseLU lu;
    try {
      lu.factor(singular, "repeated-row matrix");
      FAIL() << "a singular matrix was factored";
    } catch (const NumericalError& e) {
      EXPECT_NE(std::string(e.what()).find("repeated-row matrix is singular"), std::string::npos) << e.what();
    }
    EXPECT_EQ(lu.ldltFactorizations(), 0);
  }
}

// Two constraint rows that become parallel as eps -> 0 (a multiplier's pivot O(eps^2)): the
// LDL^T path's refined solves keep the componentwise backward error at round-off.
TEST(SparseLDLT, RefinementKeepsTheBackwardErrorNearDependentRows) {
  for (const double eps : {1e-2, 1e-3, 1e-4}) {  // condition ~1e10 / eps^2; at 1e-6, 1e20: singular
    SpMat A = constrainedGrid(16, 2, 0.0, 5);
    const Eigen::Index last = A.rows() - 1, before = last - 1;
    bool perturbed = false;  // row `last` := row `before`, its first entry times 1 + eps
    for (Eigen::Index j = 0; j < A.rows() - 2; ++j) {
      const double v = A.coeff(before, j);
      if (v == 0.0 && A.coeff(last, j) == 0.0) continue;
      const double w = v * (v != 0.0 && !perturbed ? 1.0 + eps : 1.0);
      perturbed |= v != 0.0;
      A.coeffRef(last, j) = w, A.coeffRef(j, last) = w;
    }
    A.makeCompressed();
    SparseLU lu;
    lu.factor(A, "near-dependent rows");
    EXPECT_EQ(lu.ldltFactorizations(), 1) << eps;
    const MatX B = randomColumns(A.rows(), 2, 6);
    MatX X = B;
    lu.solve(X);
    const double omega = backwardError(A, X, B);
    std::printf("  eps %g: componentwise backward error %.2e\n", eps, omega);
    EXPECT_LE(omega, 1e-14);
  }
}

namespace {
/// The 3D solid pendulum (examples/solid/pendulum3d.yaml) held by support rows on its hinge
/// edge instead of grounded nodes, 10 steps, sensitivities to E and density, two objectives.
const char* kHeldPendulum = R"(dimension: 3
gravity: [0, -9.81, 0]
elements:
  - {name: bar, type: solid, mesh: pendulum3d.geo, group: bar, size: 0.04, order: 2, material: neo_hookean,
     E: 2.0e6, nu: 0.3, density: 1000, support: [{group: hinge, fix: [x, y, z]}]}
parameters:
  - {name: E, of: bar, property: E}
  - {name: density, of: bar, property: density}
integrator: {type: trapezoidal, t_end: 0.05, dt: 0.005, frame_interval: 0.005}
outputs:
  - {name: tip_y, node: tip, component: y}
objectives:
  - {name: end, terminal: {output: tip_y}}
  - {name: area, integral: {output: tip_y}}
output: {vtk: false}
)";

using Series = std::vector<std::vector<double>>;

/// Runs `scene` (its mesh `geo` beside it, from examples/) with FLEXSENS_LINEAR_SOLVER=`choice`
/// and `options`: series.csv's rows (of `seriesDir` under the output) and summary.json.
std::pair<Series, std::string> runWith(const std::string& name, const std::string& scene, const std::string& geo,
                                       const std::string& choice, const std::string& options = "",
                                       const std::string& seriesDir = "") {
  const std::string dir = ::testing::TempDir() + "/" + name + "_" + choice;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(test::sourceDir() + "/examples/" + geo, dir + "/" + std::filesystem::path(geo).filename().string());
  std::ofstream(dir + "/scene.yaml") << scene;
  const std::string cmd = "FLEXSENS_LINEAR_SOLVER=" + choice + " " + FLEXSENS_EXE + " run " + dir +
                          "/scene.yaml --out " + dir + "/out " + options + " > /dev/null 2>&1";
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(rc), 0) << cmd;
  const std::string out = dir + "/out/" + seriesDir;
  Series rows;
  std::ifstream csv(out + "/series.csv");
  std::string line;
  std::getline(csv, line);  // header
  while (std::getline(csv, line)) {
    std::vector<double> row;
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) row.push_back(std::atof(cell.c_str()));
    rows.push_back(row);
  }
  std::stringstream summary;
  summary << std::ifstream(out + "/summary.json").rdbuf();
  return {rows, summary.str()};
}

std::pair<Series, std::string> heldPendulumRun(const std::string& choice) {
  return runWith("held_pendulum", kHeldPendulum, "solid/pendulum3d.geo", choice);
}

double summaryNumber(const std::string& summary, const std::string& key) {
  const size_t at = summary.find("\"" + key + "\": ");
  return at == std::string::npos ? -1.0 : std::atof(summary.c_str() + at + key.size() + 4);
}

long counter(const std::string& summary, const std::string& key) {
  const size_t at = summary.find("\"" + key + "\": ");
  return at == std::string::npos ? -1 : std::atol(summary.c_str() + at + key.size() + 4);
}
}  // namespace

// A whole run of the held pendulum (n = 1701 coordinates, 9 support rows): through LDL^T its
// tip motion and dd sensitivities equal the KLU path's to the Newton tolerance's scale (both
// solve each step to rtol 1e-8: 1e-9 relative to the series' largest value), and the adjoint
// gradients (transposed solves) equal the KLU path's adjoint and the forward gradients.
TEST(SparseLDLT, HeldSolidRunMatchesTheKluPath) {
  const auto [ldlt, ldltSummary] = heldPendulumRun("auto");
  const auto [klu, kluSummary] = heldPendulumRun("klu");
  EXPECT_GT(counter(ldltSummary, "ldlt_factorizations"), 0) << ldltSummary;
  EXPECT_EQ(counter(kluSummary, "ldlt_factorizations"), 0);
  ASSERT_EQ(ldlt.size(), klu.size());
  ASSERT_GT(ldlt.size(), 5u);
  // Every column (tip_y and its derivatives by E and density, kinetic, potential and total
  // energy) on the scale of its largest value; the total energy (kinetic + potential, which
  // cancel to 1e-5 of each) on the kinetic energy's, its derivatives (the same cancellation)
  // to 1e-4 of their own.
  auto largest = [&](size_t c) {
    double s = 0.0;
    for (const auto& row : klu) s = std::max(s, std::abs(row[c]));
    return s;
  };
  const size_t kinetic = 4, total = 6;  // t, tip_y, dtip_y/dE, dtip_y/ddensity, kinetic_J, potential_J, energy_J, ...
  for (size_t c = 1; c < ldlt[0].size(); ++c) {
    const double bound = c == total ? 1e-9 * largest(kinetic) : c > total ? 1e-4 * largest(c) : 1e-9 * largest(c);
    double diff = 0.0;
    for (size_t r = 0; r < ldlt.size(); ++r) diff = std::max(diff, std::abs(ldlt[r][c] - klu[r][c]));
    std::printf("  column %zu: largest %.3e, |LDL^T - KLU| %.2e\n", c, largest(c), diff);
    EXPECT_LE(diff, bound) << "column " << c;
  }
  const Scene sc = readSceneText(kHeldPendulum, test::sourceDir() + "/examples/solid/held.yaml");
  const GradientResult adjoint = test::gradients(sc, "adjoint"), forward = test::gradients(sc, "forward");
  EXPECT_GT(adjoint.stats.ldltFactorizations, 0);
  GradientResult adjointKlu;
  {
    SolverChoice choice("klu");
    adjointKlu = test::gradients(sc, "adjoint");
  }
  EXPECT_EQ(adjointKlu.stats.ldltFactorizations, 0);
  const double floor = 1e-6 * adjointKlu.objectives[0].gradient.cwiseAbs().maxCoeff();
  EXPECT_LT(test::worstRelative(adjoint, adjointKlu, floor), 1e-7);
  EXPECT_LT(test::worstRelative(adjoint, forward, floor), 1e-7);
}

// The five-bar with its meshed link modelled rigid (examples/fivebar/meshed_link.yaml, case F1R:
// n = 2990 with 1494 constraint rows, the link's nodes tied to its rigid body): MUMPS' analysis
// predicts little work, but KLU's LU fills 42x nnz(A); the pattern goes to LDL^T after that
// first factorization (fill ~4). The motion and its sensitivity equal the KLU path's.
TEST(SparseLDLT, RigidTwinKluFillsGoesToLdlt) {
  std::stringstream scene;
  scene << std::ifstream(test::sourceDir() + "/examples/fivebar/meshed_link.yaml").rdbuf();
  const std::string options = "--case F1R --t-end 0.03";
  const auto [ldlt, ldltSummary] = runWith("rigid_twin", scene.str(), "fivebar/meshed_link.geo", "auto", options, "F1R");
  const auto [klu, kluSummary] = runWith("rigid_twin", scene.str(), "fivebar/meshed_link.geo", "klu", options, "F1R");
  EXPECT_EQ(counter(ldltSummary, "ldlt_factorizations"), counter(ldltSummary, "factorizations")) << ldltSummary;
  EXPECT_LT(summaryNumber(ldltSummary, "lu_fill"), 10.0);
  EXPECT_GT(summaryNumber(kluSummary, "lu_fill"), 20.0);
  ASSERT_EQ(ldlt.size(), klu.size());
  ASSERT_GT(ldlt.size(), 2u);
  for (size_t c = 1; c <= 2; ++c) {  // z2 and dz2/dL_A1
    double scale = 0.0, diff = 0.0;
    for (size_t r = 0; r < ldlt.size(); ++r) {
      scale = std::max(scale, std::abs(klu[r][c]));
      diff = std::max(diff, std::abs(ldlt[r][c] - klu[r][c]));
    }
    std::printf("  column %zu: largest %.3e, |LDL^T - KLU| %.2e\n", c, scale, diff);
    EXPECT_LE(diff, 1e-8 * scale) << "column " << c;
  }
}
