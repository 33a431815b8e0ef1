#include "output/GradientVtu.hpp"

#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <map>

#include "output/VtuFrame.hpp"

namespace flexsens {

bool hasPerElementParameters(const Model& m) {
  for (const auto& par : m.parameters)
    if (par.element >= 0) return true;
  return false;
}

namespace {

/// The model's grid with one cell array per (field, family), named nameOf(field, family).
template <class NameOf>
void writeCellFields(const std::string& path, const std::string& shown, const Model& m,
                     const std::vector<std::pair<std::string, VecX>>& gradients, NameOf nameOf) {
  StateWithSens s;  // the scene's positions, at rest
  s.x.q = m.initialPositions();
  s.x.v = VecX::Zero(m.n);
  const vtkSmartPointer<vtkUnstructuredGrid> grid = frameGrid(m, s);
  auto* ids = vtkIntArray::SafeDownCast(grid->GetCellData()->GetArray("element_id"));
  // family -> (element -> parameter)
  std::map<std::string, std::map<int, int>> families;
  for (size_t k = 0; k < m.parameters.size(); ++k)
    if (m.parameters[k].element >= 0) families[m.parameters[k].family][m.parameters[k].element] = int(k);
  for (const auto& [objective, g] : gradients)
    for (const auto& [family, byElement] : families) {
      vtkNew<vtkDoubleArray> a;
      a->SetName(nameOf(objective, family).c_str());
      a->SetNumberOfValues(grid->GetNumberOfCells());
      for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
        const auto it = ids ? byElement.find(ids->GetValue(c)) : byElement.end();
        a->SetValue(c, it == byElement.end() ? NAN : g[it->second]);
      }
      grid->GetCellData()->AddArray(a);
    }
  const VtuWriteStatus st = writeVtuFile(grid, path);
  if (!st.ok)
    throw OutputError("cannot write " + shown + ": " + (st.err ? std::strerror(st.err) : "VTK error code " + std::to_string(st.code)));
}

}  // namespace

void writeGradientVtu(const std::string& path, const std::string& shown, const Model& m,
                      const std::vector<std::pair<std::string, VecX>>& gradients) {
  writeCellFields(path, shown, m, gradients,
                  [](const std::string& objective, const std::string& family) { return "d" + objective + "/d" + family; });
}

void writeParameterVtu(const std::string& path, const std::string& shown, const Model& m, const VecX& p) {
  writeCellFields(path, shown, m, {{"", p}}, [](const std::string&, const std::string& family) { return family; });
}

}  // namespace flexsens
