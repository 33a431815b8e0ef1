// Slopes of ANCF nodes in a run's inputs and outputs: initial slope rates derived from the
// nodes' velocities (elements/AncfCableReader.cpp, deriveSlopeRates), and slopes written to
// series.csv (component x', ...) and to the VTK frames (point data "slope", "slope_rate",
// "dslope/d<p>").
#include <gtest/gtest.h>

#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "TestModels.hpp"
#include "core/Assembler.hpp"
#include "core/SparseAccumulator.hpp"
#include "scene/Scene.hpp"

using namespace flexsens;
namespace fs = std::filesystem;

namespace {

/// Free planar chain on a quarter circle of radius 1 (centre at the origin), each node moving
/// with the rigid velocity v0 + w J r, or with the uniform stretch e r when stretch is set.
std::string arcScene(double w, bool stretch) {
  const double e = 0.4;
  std::ostringstream os;
  os.precision(17);
  os << "dimension: 2\nnodes:\n";
  for (int i = 0; i <= 3; ++i) {
    const double a = M_PI / 2 * i / 3, x = std::cos(a), y = std::sin(a);
    const double vx = stretch ? e * x : 0.3 - w * y, vy = stretch ? e * y : -0.1 + w * x;
    os << "  - {name: n" << i << ", position: [" << x << ", " << y << "], velocity: [" << vx << ", " << vy << "]}\n";
  }
  os << "elements:\n  - {name: arc, type: ancf_cable, nodes: [n0, n1, n2, n3], E: 2.0e9, density: 7850,"
        " section: {side: 0.01}}\nintegrator: {type: trapezoidal, t_end: 0.1, dt: 0.01}\n";
  return os.str();
}

/// Stiffness K = -dQ/dq of the model at its initial positions.
MatX stiffness(const Model& m) {
  Assembler as(m);
  SparseAccumulator acc;
  acc.begin(m.n, m.n);
  const VecX q = m.initialPositions(), v = m.initialVelocities(), p = m.nominalParameters();
  as.addForceJacobian(acc, q, v, p, 1.0, 0.0, 0, 0, 0);
  return MatX(acc.finish());
}

}  // namespace

// A rigid motion of a curved planar chain: every slope turns with the body, r_s' = w J r_s
// (J the quarter turn), and the strain rate K v vanishes with these slope rates (it does not
// with zero slope rates, which bend the chain).
TEST(AncfSlopeRates, RigidMotionOfACurvedPlanarChain) {
  const double w = 2.0;
  const Scene sc = readSceneText(arcScene(w, false), "arc.yaml");
  const Model& m = *sc.model;
  for (const Node& nd : m.nodes) {
    ASSERT_EQ(nd.slopeRate.size(), 2) << nd.name;
    const Eigen::Vector2d expected(-w * nd.slope[1], w * nd.slope[0]);
    EXPECT_LT((nd.slopeRate - VecX(expected)).norm(), 1e-14) << nd.name;
  }
  const MatX K = stiffness(m);
  VecX v = m.initialVelocities();
  const double scale = K.lpNorm<Eigen::Infinity>() * v.lpNorm<Eigen::Infinity>();
  EXPECT_LT((K * v).lpNorm<Eigen::Infinity>(), 1e-9 * scale);
  for (const Node& nd : m.nodes) v.segment(nd.slopeDof, 2).setZero();
  EXPECT_GT((K * v).lpNorm<Eigen::Infinity>(), 1e-3 * scale);
}

// A uniform stretch v = e r lengthens every slope at the same rate: r_s' = e r_s.
TEST(AncfSlopeRates, UniformStretch) {
  const Scene sc = readSceneText(arcScene(0.0, true), "arc.yaml");
  for (const Node& nd : sc.model->nodes) EXPECT_LT((nd.slopeRate - 0.4 * nd.slope).norm(), 1e-14) << nd.name;
}

// A straight spatial chain pinned at the origin and turning about the vertical z at w:
// v = (0, w x, 0), so every slope (1, 0, 0) turns at (0, w, 0), also the pinned node's; a
// clamped slope gets none.
TEST(AncfSlopeRates, SpatialTurnAboutAPin) {
  const double w = 1.5;
  auto text = [&](bool clamped) {
    std::ostringstream os;
    os.precision(17);
    os << "dimension: 3\nnodes:\n  - {name: A, position: [0, 0, 0], ground: true"
       << (clamped ? ", clamped: true" : "") << "}\n";
    for (int i = 1; i <= 3; ++i)
      os << "  - {name: n" << i << ", position: [" << i / 3.0 << ", 0, 0], velocity: [0, " << w * i / 3.0 << ", 0]}\n";
    os << "elements:\n  - {name: rod, type: ancf_cable, nodes: [A, n1, n2, n3], E: 2.0e9, density: 7850,"
          " section: {side: 0.01}}\nintegrator: {type: trapezoidal, t_end: 0.1, dt: 0.01}\n";
    return os.str();
  };
  const Scene pinned = readSceneText(text(false), "rod.yaml");
  for (const Node& nd : pinned.model->nodes)
    EXPECT_LT((nd.slopeRate - Eigen::Vector3d(0, w, 0)).norm(), 1e-14) << nd.name;
  const MatX K = stiffness(*pinned.model);
  const VecX v = pinned.model->initialVelocities();
  EXPECT_LT((K * v).lpNorm<Eigen::Infinity>(), 1e-9 * K.lpNorm<Eigen::Infinity>() * v.lpNorm<Eigen::Infinity>());
  const Scene clamped = readSceneText(text(true), "rod.yaml");
  EXPECT_EQ(clamped.model->nodes[0].slopeRate.size(), 0);
}

// The CLI writes slopes: a CSV output with component y' and the VTK point data agree with
// each other at every frame (the same q), including their E-sensitivities, and the clamped
// root keeps its slope (1, 0) with zero rate and zero sensitivity.
TEST(AncfOutputs, SlopesInCsvAndVtk) {
  const fs::path dir = fs::temp_directory_path() / ("flexsens_ancf_out_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path scene = dir / "cantilever.yaml";
  std::ofstream(scene) << "dimension: 2\ngravity: [0, -9.81]\nnodes:\n"
                          "  - {name: A, position: [0, 0], ground: true, clamped: true}\n"
                          "  - {name: n1, position: [0.5, 0]}\n  - {name: tip, position: [1, 0]}\n"
                          "elements:\n  - {name: rod, type: ancf_cable, nodes: [A, n1, tip], E: 2.0e9,"
                          " density: 7850, section: {side: 0.02}}\n"
                          "parameters:\n  - {name: E, of: rod, property: E}\n"
                          "integrator: {type: trapezoidal, t_end: 0.05, dt: 0.01, frame_interval: 0.01}\n"
                          "outputs:\n  - {name: s_tip, node: tip, component: \"y'\"}\n";
  const fs::path out = dir / "out";
  const std::string cmd = std::string(FLEXSENS_EXE) + " run " + scene.string() + " --out " + out.string() + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::ifstream csv(out / "series.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("t,s_tip,ds_tip/dE", 0), 0u) << header;
  int frame = 0;
  while (std::getline(csv, line)) {
    std::stringstream ss(line);
    std::string cell;
    std::vector<double> row;
    while (std::getline(ss, cell, ',')) row.push_back(std::stod(cell));
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05d.vtu", frame);
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName((out / name).c_str());
    reader->Update();
    vtkUnstructuredGrid* g = reader->GetOutput();
    vtkDataArray *s = g->GetPointData()->GetArray("slope"), *r = g->GetPointData()->GetArray("slope_rate"),
                 *ds = g->GetPointData()->GetArray("dslope/dE");
    ASSERT_TRUE(s && r && ds) << name;
    EXPECT_NEAR(s->GetTuple3(2)[1], row[1], 1e-13) << name;  // the tip's y' (CSV: 15 digits)
    EXPECT_NEAR(ds->GetTuple3(2)[1], row[2], 1e-12 * (1.0 + std::abs(row[2]))) << name;
    EXPECT_EQ(s->GetTuple3(0)[0], 1.0);               // clamped root
    EXPECT_EQ(r->GetTuple3(0)[1], 0.0);
    EXPECT_EQ(ds->GetTuple3(0)[1], 0.0);
    if (frame == 5) EXPECT_LT(row[1], -1e-4);        // the tip bends down under its weight
    ++frame;
  }
  EXPECT_EQ(frame, 6);
  fs::remove_all(dir);
}
