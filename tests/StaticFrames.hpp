// `flexsens static` from a test: run the scene through the command line and read the .vtu of
// its last frame (the last load step), as a user's ParaView would.
#pragma once

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "core/Assembler.hpp"
#include "integrators/Static.hpp"

namespace flexsens::test {

/// Runs `flexsens static yaml --out out`; null when it fails or writes no frame.
inline vtkSmartPointer<vtkUnstructuredGrid> staticLastFrame(const std::filesystem::path& yaml,
                                                           const std::filesystem::path& out) {
  // Scenes written to temporary folders name meshes of the source tree: allowed.
  const std::string cmd = std::string(FLEXSENS_EXE) + " static " + yaml.string() + " --allow-path " +
                          std::string(FLEXSENS_SOURCE_DIR) + " --out " + out.string() +
                          " > /dev/null 2>&1";
  if (std::system(cmd.c_str()) != 0) return nullptr;
  std::filesystem::path vtu;  // frame_NNNNN.vtu: the largest name is the last frame
  for (const auto& e : std::filesystem::directory_iterator(out))
    if (e.path().extension() == ".vtu" && (vtu.empty() || e.path() > vtu)) vtu = e.path();
  if (vtu.empty()) return nullptr;
  auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  reader->SetFileName(vtu.c_str());
  reader->Update();
  return reader->GetOutput();
}

/// Static equilibrium of m at its nominal parameters in one load step of the full load (the
/// solver of `flexsens static`), Newton to `tol` (StaticSettings::tol), from the initial positions.
inline VecX staticEquilibrium(const Model& m, double tol = StaticSettings().tol) {
  Assembler as(m);
  StaticSettings set;
  set.steps = 1;
  set.stepLoadFactor = true;
  set.tol = tol;
  return solveStatic(as, m.nominalParameters(), m.initialPositions(), set);
}

/// A cell derivative array against five-point central differences of whole runs.
struct CellDerivativeCheck {
  double worst = -1.0;  ///< max |d<base>/d<param> - central difference| over cells and components; -1: arrays missing
  double scale = 0.0;   ///< the largest |central difference| or |<base>| / p
};

/// Compares g0's cell array "d<base>/d<param>" with (8 (f(1) - f(-1)) - (f(2) - f(-2))) / (12 h p)
/// of the array <base> in the frames `at` computed at p (1 + j h), j = -2, -1, 1, 2.
inline CellDerivativeCheck checkCellDerivative(vtkUnstructuredGrid* g0,
                                               const std::vector<vtkSmartPointer<vtkUnstructuredGrid>>& at,
                                               const std::string& base, const std::string& param, double p, double h) {
  CellDerivativeCheck r;
  vtkDataArray* d = g0->GetCellData()->GetArray(("d" + base + "/d" + param).c_str());
  vtkDataArray* f0 = g0->GetCellData()->GetArray(base.c_str());
  if (!d || !f0 || at.size() != 4) return r;
  std::vector<vtkDataArray*> f;
  for (const auto& g : at) {
    f.push_back(g->GetCellData()->GetArray(base.c_str()));
    if (!f.back() || f.back()->GetNumberOfTuples() != d->GetNumberOfTuples()) return r;
  }
  r.worst = 0.0;
  for (vtkIdType c = 0; c < d->GetNumberOfTuples(); ++c)
    for (int j = 0; j < d->GetNumberOfComponents(); ++j) {
      const double fd = (8.0 * (f[2]->GetComponent(c, j) - f[1]->GetComponent(c, j)) -
                         (f[3]->GetComponent(c, j) - f[0]->GetComponent(c, j))) / (12.0 * h * p);
      r.worst = std::max(r.worst, std::abs(d->GetComponent(c, j) - fd));
      r.scale = std::max({r.scale, std::abs(fd), std::abs(f0->GetComponent(c, j)) / p});
    }
  return r;
}

}  // namespace flexsens::test
