// Meshed bodies from Gmsh as scene elements (type: solid, elements/SolidReader.cpp), and the
// cantilever convergence against an independent reference: the Timoshenko beam's tip
// deflection P L^3 / (3 E I) + P L / (kappa G A) at small load (nu = 0, so the clamped root
// does not restrain a Poisson contraction). The geometries are tests/scenes/solid/*.geo.
#include <gtest/gtest.h>

#include <unistd.h>
#include <vtkCell.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "StaticFrames.hpp"
#include "core/Assembler.hpp"
#include "elements/Solid.hpp"
#include "integrators/Static.hpp"
#include "scene/Scene.hpp"

using namespace flexsens;

namespace {

std::string dirOf() { return std::string(FLEXSENS_SOURCE_DIR) + "/tests/scenes/solid/"; }

constexpr double kE = 2.1e11, kRho = 7800.0, kT = 0.01;  // [Pa], [kg/m^3], plate thickness [m]
constexpr double kL = 1.0, kHp = 0.05, kHb = 0.1;         // plate height, bar side [m]

std::string plateScene(double size, int order, double P, const std::string& extra = "") {
  std::ostringstream s;
  s.precision(17);
  s << "dimension: 2\nelements:\n  - {name: plate, type: solid, mesh: plate.geo, group: plate, size: " << size
    << ", order: " << order << ", E: " << kE << ", nu: 0, density: " << kRho << ", thickness: " << kT
    << ", ground: [root], traction: [{group: tip, force: [0, " << -P << "]}]" << extra << "}\n"
    << "static: {load_steps: 1}\n";
  return s.str();
}

std::string barScene(double size, int order, double P) {
  std::ostringstream s;
  s.precision(17);
  s << "dimension: 3\nelements:\n  - {name: bar, type: solid, mesh: bar3d.geo, group: bar, size: " << size
    << ", order: " << order << ", E: " << kE << ", nu: 0, density: " << kRho
    << ", ground: [root], traction: [{group: tip, force: [0, " << -P << ", 0]}]}\n"
    << "static: {load_steps: 1}\n";
  return s.str();
}

/// Static equilibrium (the solver of `flexsens static`); returns the mean y displacement of
/// the nodes whose rest x is L (the tip face or edge).
double tipDeflection(const std::string& text, int* dofs = nullptr) {
  const Scene sc = readSceneText(text, dirOf() + "scene.yaml");
  const Model& m = *sc.model;
  const VecX q = test::staticEquilibrium(m);
  double sum = 0.0;
  int count = 0;
  for (size_t i = 0; i < m.nodes.size(); ++i)
    if (!m.nodes[i].ground && std::abs(m.nodes[i].position[0] - kL) < 1e-9) {
      sum += q[m.dof(static_cast<int>(i), 1)] - m.nodes[i].position[1];
      ++count;
    }
  if (dofs) *dofs = m.n;
  return sum / count;
}

/// Timoshenko tip deflection [m] for a rectangular section b x h, nu = 0 (G = E / 2).
double timoshenko(double P, double b, double h) {
  const double I = b * h * h * h / 12.0, A = b * h, G = kE / 2.0, kappa = 5.0 / 6.0;
  return P * kL * kL * kL / (3.0 * kE * I) + P * kL / (kappa * G * A);
}

}  // namespace

TEST(SolidScene, MeshNamesGroupsMassAndFirstMoments) {
  const Scene sc = readSceneText(plateScene(0.05, 2, 1.0), dirOf() + "scene.yaml");
  const Model& m = *sc.model;
  EXPECT_GE(m.nodeIndex("tipmid"), 0);  // a Physical Point names its node
  int cells = 0, ground = 0;
  for (const auto& e : m.elements)
    if (auto* s = dynamic_cast<const Solid*>(e.get())) {
      ++cells;
      EXPECT_EQ(s->shape(), Simplex::Tri6);
    }
  for (const Node& nd : m.nodes) ground += nd.ground;
  EXPECT_GT(cells, 0);
  EXPECT_GE(ground, 3);  // the root edge: at least its two corners and one midside node
  for (const Node& nd : m.nodes)
    if (nd.ground) EXPECT_NEAR(nd.position[0], 0.0, 1e-12);
  // Mass and first moments of the assembled (free and ground) mass: the rectangle's.
  Assembler as(m);
  const VecX p = m.nominalParameters();
  double mass = 0.0, mx = 0.0, my = 0.0;
  for (const auto& e : m.elements) {
    MatX M;
    const LocalState s = as.localState(*e, m.initialPositions(), VecX::Zero(m.n), p);
    if (!e->mass(s, M)) continue;
    const int n = static_cast<int>(e->nodes().size());
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        mass += M(2 * i, 2 * j);
        mx += M(2 * i, 2 * j) * m.nodes[e->nodes()[j]].position[0];
        my += M(2 * i, 2 * j) * m.nodes[e->nodes()[j]].position[1];
      }
  }
  const double exact = kRho * kT * kL * kHp;
  EXPECT_NEAR(mass, exact, 1e-12 * exact);
  EXPECT_NEAR(mx, exact * kL / 2, 1e-12 * exact);
  EXPECT_NEAR(my, exact * kHp / 2, 1e-12 * exact);
}

TEST(SolidScene, PlaneStressCantileverMatchesTimoshenko) {
  // P gives a tip deflection ~1.5e-5 L: geometric nonlinearity ~ (w/L)^2, negligible.
  const double P = 10.0, ref = timoshenko(P, kT, kHp);
  // Quadratic triangles, element size H/2 and H/4: within 1e-3 (measured 3e-5 and 4e-7);
  // linear triangles at H/4 lock (9% too stiff).
  const double w2 = -tipDeflection(plateScene(kHp / 2, 2, P));
  const double w4 = -tipDeflection(plateScene(kHp / 4, 2, P));
  const double l4 = -tipDeflection(plateScene(kHp / 4, 1, P));
  const double e2 = std::abs(w2 / ref - 1), e4 = std::abs(w4 / ref - 1), el = std::abs(l4 / ref - 1);
  std::printf("plate: Timoshenko %.6e m; tri6 h=H/2 %.6e (%.2e), h=H/4 %.6e (%.2e); tri3 h=H/4 %.6e (%.2e)\n", ref,
              w2, e2, w4, e4, l4, el);
  EXPECT_LT(e4, 1e-3);
  EXPECT_LT(e2, 1e-3);
  EXPECT_LT(e4, e2);
  EXPECT_GT(el, 5 * e4);
}

TEST(SolidScene, TetrahedralCantileverMatchesTimoshenko) {
  const double P = 100.0, ref = timoshenko(P, kHb, kHb);
  const double w = -tipDeflection(barScene(kHb / 2, 2, P));
  const double e = std::abs(w / ref - 1);
  std::printf("bar: Timoshenko %.6e m; tet10 h=H/2 %.6e (%.2e)\n", ref, w, e);
  EXPECT_LT(e, 2e-3);  // measured 2.6e-4
}

TEST(SolidScene, StaticRunWritesRealCellTypesAndStress) {
  // A plate pulled along its axis by F at the tip edge (nu = 0): away from the ends the
  // Cauchy stress is F / (H t) along x and zero otherwise (bar theory), to within the
  // strain ~1e-6. `flexsens static` writes each load step as a frame.
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("flexsens_solid_vtu_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const double F = 1000.0;
  std::string text = plateScene(0.025, 2, 0.0);
  text.replace(text.find("force: [0, -0]"), 14, "force: [" + std::to_string(F) + ", 0]");
  text.replace(text.find("mesh: plate.geo"), 15, "mesh: " + dirOf() + "plate.geo");
  { std::ofstream(dir / "plate.yaml") << text; }
  const auto g = test::staticLastFrame(dir / "plate.yaml", dir / "out");
  ASSERT_NE(g, nullptr) << text;
  const Scene sc = readSceneText(text, (dir / "plate.yaml").string());
  int solids = 0;
  for (const auto& e : sc.model->elements) solids += dynamic_cast<const Solid*>(e.get()) != nullptr;
  ASSERT_EQ(g->GetNumberOfCells(), solids);
  vtkDataArray* sig = g->GetCellData()->GetArray("stress_cauchy");
  vtkDataArray* vm = g->GetCellData()->GetArray("von_mises");
  ASSERT_NE(sig, nullptr);
  ASSERT_NE(vm, nullptr);
  ASSERT_NE(g->GetCellData()->GetArray("green_lagrange_strain"), nullptr);
  ASSERT_NE(g->GetCellData()->GetArray("stress_pk2"), nullptr);
  const double s0 = F / (kHp * kT);
  int checked = 0;
  for (vtkIdType c = 0; c < g->GetNumberOfCells(); ++c) {
    EXPECT_EQ(g->GetCellType(c), VTK_QUADRATIC_TRIANGLE);
    double b[6];
    g->GetCell(c)->GetBounds(b);
    if (b[0] < 0.3 || b[1] > 0.7) continue;
    double t[9];
    sig->GetTuple(c, t);
    EXPECT_NEAR(t[0], s0, 1e-4 * s0);
    EXPECT_NEAR(t[4], 0.0, 1e-4 * s0);
    EXPECT_NEAR(t[1], 0.0, 1e-4 * s0);
    EXPECT_NEAR(vm->GetTuple1(c), s0, 1e-4 * s0);
    ++checked;
  }
  EXPECT_GT(checked, 10);
  fs::remove_all(dir);
}

// d(stress)/dp cell data (Solid::centroidStressDerivative through the run's dq/dp) against
// central differences of whole `flexsens static` runs (five points, step 1e-3 p): a cantilever plate
// (quadratic triangles, nu = 0.3) bent by a tip load to a deflection of ~5% of its length (so
// the stresses depend on E through the geometry too), parameters E, nu and thickness; every
// cell's Cauchy stress and von Mises stress, relative to the largest of each over the cells.
TEST(SolidScene, StressSensitivitiesMatchCentralDifferencesOfRuns) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("flexsens_solid_dstress_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string names[] = {"E", "nu", "thickness"};
  const double nominal[] = {kE, 0.3, kT};
  auto run = [&](int which, double factor, const std::string& tag) {
    double v[3] = {nominal[0], nominal[1], nominal[2]};
    if (which >= 0) v[which] *= factor;
    std::ostringstream t;
    t.precision(17);
    t << "dimension: 2\nelements:\n  - {name: plate, type: solid, mesh: " << dirOf() << "plate.geo, group: plate, "
      << "size: 0.025, order: 2, E: " << v[0] << ", nu: " << v[1] << ", density: " << kRho << ", thickness: " << v[2]
      << ", ground: [root], traction: [{group: tip, force: [0, -3000]}]}\n"
      << "parameters:\n  - {name: E, of: plate, property: E}\n  - {name: nu, of: plate, property: nu}\n"
      << "  - {name: thickness, of: plate, property: thickness}\nstatic: {load_steps: 1}\n";
    { std::ofstream(dir / (tag + ".yaml")) << t.str(); }
    const auto g = test::staticLastFrame(dir / (tag + ".yaml"), dir / tag);
    EXPECT_NE(g, nullptr) << t.str();
    return g;
  };
  const auto g0 = run(-1, 1.0, "nominal");
  ASSERT_NE(g0, nullptr);
  // Five-point central differences, relative step 1e-3: truncation O(h^4) ~ 1e-12, and the static
  // solve's Newton tolerance (~1e-10 of q) enters divided by 12 h only.
  const double h = 1e-3;
  for (int k = 0; k < 3; ++k) {
    std::vector<vtkSmartPointer<vtkUnstructuredGrid>> at;  // p (1 + j h), j = -2, -1, 1, 2
    for (int j : {-2, -1, 1, 2}) {
      at.push_back(run(k, 1.0 + j * h, names[k] + std::to_string(j)));
      ASSERT_NE(at.back(), nullptr);
    }
    // The scale: the largest derivative, or the stress over the parameter (dstress/dE is ~0.1 of that).
    for (const std::string base : {"stress_cauchy", "von_mises"}) {
      const auto c = test::checkCellDerivative(g0, at, base, names[k], nominal[k], h);
      std::printf("  d%s/d%s: max |analytic - central difference| = %.2e, scale %.3e\n", base.c_str(), names[k].c_str(),
                  c.worst, c.scale);
      ASSERT_GE(c.worst, 0.0) << "arrays missing: " << base << " " << names[k];
      EXPECT_LT(c.worst, 1e-6 * c.scale) << base << " " << names[k];
    }
  }
  fs::remove_all(dir);
}

// attach: a group welded to a rigid body. A body whose basic points are all ground nodes is
// fixed, so a root attached to it is the root grounded: the cantilever's tip deflection must be
// the grounded one (itself within 1e-3 of Timoshenko, PlaneStressCantileverMatchesTimoshenko),
// for the plane-stress plate on a planar_rigid_body and the tetrahedral bar on a rigid_body;
// and the rigidly attached nodes start where the mesh puts them (the coefficients are right:
// the constraints hold at the mesh positions to round-off).
TEST(SolidScene, GroupAttachedToAGroundedRigidBodyIsClamped) {
  const double P = 1000.0;
  const std::string plateAttached =
      "dimension: 2\nnodes:\n  - {name: A, position: [-0.1, 0], ground: true}\n"
      "  - {name: B, position: [-0.1, 0.05], ground: true}\nelements:\n"
      "  - {name: hub, type: planar_rigid_body, nodes: [A, B], mass: 1, center_of_mass: [-0.1, 0.025], inertia: 0.01}\n"
      "  - {name: plate, type: solid, mesh: plate.geo, group: plate, size: 0.025, order: 2, E: 2.1e11, nu: 0,"
      " density: 7800, thickness: 0.01, attach: [{group: root, body: hub}], traction: [{group: tip, force: [0, -1000]}]}\n"
      "static: {load_steps: 1}\n";
  const std::string barAttached =
      "dimension: 3\nnodes:\n  - {name: A, position: [-0.2, 0, 0], ground: true}\n"
      "  - {name: B, position: [-0.1, 0, 0], ground: true}\n  - {name: C, position: [-0.2, 0.1, 0], ground: true}\n"
      "  - {name: D, position: [-0.2, 0, 0.1], ground: true}\nelements:\n"
      "  - {name: hub, type: rigid_body, nodes: [A, B, C, D], mass: 1, center_of_mass: [-0.15, 0.02, 0.02],"
      " inertia: [0.01, 0.01, 0.01]}\n"
      "  - {name: bar, type: solid, mesh: bar3d.geo, group: bar, size: 0.1, order: 2, E: 2.1e11, nu: 0,"
      " density: 7800, attach: [{group: root, body: hub}], traction: [{group: tip, force: [0, -1000, 0]}]}\n"
      "static: {load_steps: 1}\n";
  for (const auto& [attached, grounded] :
       {std::pair<std::string, std::string>{plateAttached, plateScene(0.025, 2, P)},
        std::pair<std::string, std::string>{barAttached, barScene(0.1, 2, P)}}) {
    const Scene sc = readSceneText(attached, dirOf() + "scene.yaml");
    const Model& m = *sc.model;
    int attachRows = 0;
    for (const auto& c : m.constraints) attachRows += c->name().find(".attach(") != std::string::npos;
    EXPECT_GT(attachRows, 2);
    Assembler as(m);
    const VecX p = m.nominalParameters();
    EXPECT_LT(as.phi(m.initialPositions(), p).lpNorm<Eigen::Infinity>(), 1e-14);
    const double wa = tipDeflection(attached), wg = tipDeflection(grounded);
    std::printf("dimension %d: tip deflection attached %.9e m, grounded %.9e m (%d attached nodes)\n", m.dim, wa, wg,
                attachRows);
    EXPECT_LT(std::abs(wa - wg), 1e-9 * std::abs(wg));
  }
}
