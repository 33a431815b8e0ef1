// PIM of meshed bodies (type: solid): the one rigidization generator (pim/Rigidization) with
// the mesh's nodes as the cloud leaves the rigid motions of the body (d - m_r = 3 planar,
// 6 spatial: pimCounts), and the F-R twin's mass properties (pim/MassProperties) equal the
// exact integrals of the rectangle and the box the meshes represent exactly (straight edges):
// m = rho V, centre at the middle, inertia m (a^2 + b^2) / 12 about the centre.
#include <gtest/gtest.h>

#include <sstream>

#include "core/Assembler.hpp"
#include "pim/MassProperties.hpp"
#include "pim/Pim.hpp"
#include "scene/Scene.hpp"

using namespace flexsens;

namespace {

std::string dirOf() { return std::string(FLEXSENS_SOURCE_DIR) + "/tests/scenes/solid/"; }

std::string freeBody(int dim, double size, int order) {
  std::ostringstream s;
  s << "dimension: " << dim << "\nelements:\n  - {name: body, type: solid, mesh: "
    << (dim == 2 ? "plate.geo, group: plate, thickness: 0.01" : "bar3d.geo, group: bar") << ", size: " << size
    << ", order: " << order << ", E: 2.1e11, nu: 0.3, density: 7800}\n"
    << "parameters:\n  - {name: E, of: body, property: E}\n"
    << "cases:\n  - {name: F1, parameters: [E], rigidize: [body]}\n"
    << "integrator: {type: trapezoidal, t_end: 0.001, dt: 0.001}\n";
  return s.str();
}

}  // namespace

TEST(SolidPim, RigidizedMeshLeavesItsRigidMotions) {
  for (int dim : {2, 3})
    for (int order : {1, 2}) {
      SCOPED_TRACE("dimension " + std::to_string(dim) + " order " + std::to_string(order));
      const Scene sc = readSceneText(freeBody(dim, dim == 2 ? 0.05 : 0.1, order), dirOf() + "scene.yaml", "F1");
      const Model& m = *sc.model;
      Assembler as(m);
      const PimReport r = pimCounts(as, *sc.pimCase, m.initialPositions(), m.nominalParameters());
      EXPECT_EQ(r.m, 0);
      EXPECT_EQ(r.d, m.n);
      EXPECT_EQ(r.lambdaGenerated, m.n - (dim == 2 ? 3 : 6));  // the cloud rules: dim N - 3 or - 6
      EXPECT_EQ(r.lambdaDropped, 0);
      EXPECT_EQ(r.ds, dim == 2 ? 3 : 6);
    }
}

TEST(SolidPim, TwinMassPropertiesAreTheMeshIntegrals) {
  const double rho = 7800;
  {  // plate 1 x 0.05, thickness 0.01, quadratic triangles
    const Scene sc = readSceneText(freeBody(2, 0.02, 2), dirOf() + "scene.yaml");
    const Model& m = *sc.model;
    std::vector<int> all(m.nodes.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
    const MassProperties mp = rigidMassProperties(m, all, m.nominalParameters());
    const double a = 1.0, b = 0.05, mass = rho * 0.01 * a * b;
    EXPECT_NEAR(mp.mass, mass, 1e-12 * mass);
    EXPECT_NEAR(mp.centre[0], a / 2, 1e-12 * a);
    EXPECT_NEAR(mp.centre[1], b / 2, 1e-12 * a);
    const double J = mass * (a * a + b * b) / 12;
    EXPECT_NEAR(mp.inertia(0, 0), J, 1e-12 * J);
  }
  {  // bar 1 x 0.1 x 0.1 centred on the x axis, quadratic tetrahedra
    const Scene sc = readSceneText(freeBody(3, 0.1, 2), dirOf() + "scene.yaml");
    const Model& m = *sc.model;
    std::vector<int> all(m.nodes.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
    const MassProperties mp = rigidMassProperties(m, all, m.nominalParameters());
    const double a = 1.0, b = 0.1, mass = rho * a * b * b;
    EXPECT_NEAR(mp.mass, mass, 1e-12 * mass);
    EXPECT_NEAR(mp.centre[0], a / 2, 1e-12 * a);
    EXPECT_NEAR(mp.centre[1], 0.0, 1e-12 * a);
    EXPECT_NEAR(mp.centre[2], 0.0, 1e-12 * a);
    Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
    I(0, 0) = mass * (b * b + b * b) / 12;
    I(1, 1) = I(2, 2) = mass * (a * a + b * b) / 12;
    EXPECT_LT((mp.inertia - MatX(I)).norm(), 1e-12 * I.norm());
  }
}
