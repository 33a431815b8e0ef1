// End-to-end run through the command line: series.csv columns, VTK files read back by VTK's
// own reader (points, arrays, cells), the .pvd index, and summary.json's status and case data.
#include <gtest/gtest.h>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "TestModels.hpp"

using namespace flexsens::test;
namespace fs = std::filesystem;

namespace {
std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
}  // namespace

TEST(Outputs, RunWritesCsvVtkPvdAndSummary) {
  const fs::path out = fs::temp_directory_path() / ("flexsens_out_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string cmd = std::string(FLEXSENS_EXE) + " run " + sourceDir() +
                          "/examples/fivebar/rigid.yaml --case R1 --t-end 0.1 --out " + out.string() +
                          " > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const fs::path dir = out / "R1";
  // CSV: header and one row per frame (dt 1e-3, frames every 0.01 s: t = 0 ... 0.1).
  std::ifstream csv(dir / "series.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header, "t,z2,x1,z1,dz2/dL_A1,dx1/dL_A1,dz1/dL_A1,kinetic_J,potential_J,energy_J,denergy_J/dL_A1");
  int rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, 11);
  // VTK: every frame readable, 5 points (ground nodes included), 4 line cells.
  const std::string pvd = slurp(dir / "frames.pvd");
  EXPECT_NE(pvd.find("timestep=\"0.1\""), std::string::npos);
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName((dir / "frame_00010.vtu").c_str());
  reader->Update();
  vtkUnstructuredGrid* g = reader->GetOutput();
  ASSERT_NE(g, nullptr);
  EXPECT_EQ(g->GetNumberOfPoints(), 5);
  EXPECT_EQ(g->GetNumberOfCells(), 4);
  for (const char* name : {"position", "displacement", "velocity", "dq/dL_A1", "dv/dL_A1"}) {
    vtkDataArray* a = g->GetPointData()->GetArray(name);
    ASSERT_NE(a, nullptr) << name;
    EXPECT_EQ(a->GetNumberOfComponents(), 3) << name;
  }
  EXPECT_NE(g->GetCellData()->GetArray("element_kind"), nullptr);
  // The five-bar lives in the XZ plane: y stays 0; node n2 (index 3) has moved down.
  double x[3];
  g->GetPoint(3, x);
  EXPECT_EQ(x[1], 0.0);
  EXPECT_LT(x[2], -2.0);
  // Summary: complete, with the case block.
  const std::string js = slurp(dir / "summary.json");
  EXPECT_NE(js.find("\"status\": \"complete\""), std::string::npos);
  EXPECT_NE(js.find("\"m_r\": 0, \"d_s\": 2"), std::string::npos);
  EXPECT_NE(js.find("\"coordinates\": [\"x(n1)\", \"z(n1)\""), std::string::npos);
  fs::remove_all(out);
}

TEST(Outputs, NumericalFailureIsReportedAndMarkedFailed) {
  // A huge step with one Newton iteration cannot converge: exit 2, summary says failed.
  const fs::path out = fs::temp_directory_path() / ("flexsens_fail_" + std::to_string(::getpid()));
  fs::remove_all(out);
  std::ifstream in(sourceDir() + "/examples/fivebar/rigid.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string scene = ss.str();
  scene.replace(scene.find("  dt: 1.0e-3"), 12, "  dt: 0.5\n  max_newton_iterations: 1");
  const fs::path file = out.string() + ".yaml";
  std::ofstream(file) << scene;
  const std::string err = out.string() + ".err";
  const std::string cmd = std::string(FLEXSENS_EXE) + " run " + file.string() + " --case R1 --out " +
                          out.string() + " > /dev/null 2> " + err;
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(rc), 2);
  const std::string msg = slurp(err);
  EXPECT_NE(msg.find("Newton did not converge"), std::string::npos) << msg;
  EXPECT_NE(msg.find("t = 0.5 s"), std::string::npos) << msg;
  EXPECT_NE(msg.find("try a smaller --dt"), std::string::npos) << msg;
  EXPECT_NE(slurp(out / "R1" / "summary.json").find("\"status\": \"failed\""), std::string::npos);
  fs::remove_all(out);
  fs::remove(file);
  fs::remove(err);
}
