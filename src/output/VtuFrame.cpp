#include "output/VtuFrame.hpp"

#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkErrorCode.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <sys/stat.h>

#include <array>
#include <cerrno>
#include <cmath>
#include <map>
#include <string>

#include "elements/ShellTriangle.hpp"
#include "elements/Solid.hpp"

namespace flexsens {

namespace {

using DoubleArrays = std::vector<vtkSmartPointer<vtkDoubleArray>>;

/// Index (0..2) of planar axis c in 3D, given the scene's plane ("xz" -> x=0, z=2).
int axis3(const Model& m, int c) {
  const char a = m.axisName(c);
  return a == 'x' ? 0 : (a == 'y' ? 1 : 2);
}

/// Axis in 3D of the model's coordinate c (planar scenes: their plane's axes).
int axisOf(const Model& m, int c) { return m.dim == 3 ? c : axis3(m, c); }

vtkSmartPointer<vtkDoubleArray> vectorArray(const Model& m, const std::string& name) {
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name.c_str());
  a->SetNumberOfComponents(3);
  a->SetNumberOfTuples(m.nodes.size());
  return a;
}

// ------------------------------------------------------------------ point data
/// The point-data vectors, in the order they are added to the grid.
struct PointArrays {
  vtkSmartPointer<vtkDoubleArray> position, displacement, velocity;
  DoubleArrays dq, dv;  ///< per parameter
  /// Nodes say what they carry: when some carry a slope (ANCF; an ancf_beam node: its r_x), the
  /// slope r' = dr/ds [-], its rate [1/s] and its sensitivities are point-data vectors too (zero
  /// on nodes without one).
  bool slopes = false;
  vtkSmartPointer<vtkDoubleArray> slope, slopeRate;
  DoubleArrays dslope;  ///< per parameter
};

PointArrays createPointArrays(const Model& m, size_t parameters) {
  PointArrays a;
  a.position = vectorArray(m, "position");
  a.displacement = vectorArray(m, "displacement");
  a.velocity = vectorArray(m, "velocity");
  for (size_t k = 0; k < parameters; ++k) {
    a.dq.push_back(vectorArray(m, "dq/d" + m.parameters[k].name));
    a.dv.push_back(vectorArray(m, "dv/d" + m.parameters[k].name));
  }
  for (const Node& nd : m.nodes) a.slopes = a.slopes || nd.hasSlope();
  if (a.slopes) {
    a.slope = vectorArray(m, "slope");
    a.slopeRate = vectorArray(m, "slope_rate");
    for (size_t k = 0; k < parameters; ++k) a.dslope.push_back(vectorArray(m, "dslope/d" + m.parameters[k].name));
  }
  return a;
}

/// Node i's position, displacement, velocity and their sensitivities into the arrays (and pts).
void putNodeMotion(const Model& m, const StateWithSens& s, size_t i, vtkPoints* pts, PointArrays& a) {
  double x[3] = {0, 0, 0}, x0[3] = {0, 0, 0}, v[3] = {0, 0, 0};
  std::vector<std::array<double, 3>> sq(s.dp.size(), {0, 0, 0}), sv(s.dp.size(), {0, 0, 0});
  for (int c = 0; c < m.dim; ++c) {
    const int ax = axisOf(m, c);
    const int d = m.dof(static_cast<int>(i), c);
    x0[ax] = m.nodes[i].position[c];
    x[ax] = d < 0 ? x0[ax] : s.x.q[d];
    v[ax] = d < 0 ? 0.0 : s.x.v[d];
    for (size_t k = 0; k < s.dp.size(); ++k) {
      sq[k][ax] = d < 0 ? 0.0 : s.dp[k].q[d];
      sv[k][ax] = d < 0 ? 0.0 : s.dp[k].v[d];
    }
  }
  pts->InsertNextPoint(x);
  a.position->SetTuple(i, x);
  const double u[3] = {x[0] - x0[0], x[1] - x0[1], x[2] - x0[2]};
  a.displacement->SetTuple(i, u);
  a.velocity->SetTuple(i, v);
  for (size_t k = 0; k < s.dp.size(); ++k) {
    a.dq[k]->SetTuple(i, sq[k].data());
    a.dv[k]->SetTuple(i, sv[k].data());
  }
}

/// Node i's slope, its rate and their sensitivities (zero on a node without a slope).
void putNodeSlope(const Model& m, const StateWithSens& s, size_t i, PointArrays& a) {
  double r1[3] = {0, 0, 0}, w1[3] = {0, 0, 0};
  std::vector<std::array<double, 3>> sr(s.dp.size(), {0, 0, 0});
  if (m.nodes[i].hasSlope())
    for (int c = 0; c < m.dim; ++c) {
      const int ax = axisOf(m, c);
      const int d = m.dof(static_cast<int>(i), m.dim + c);  // -1: clamped, fixed slope
      r1[ax] = m.coordinate(s.x.q, static_cast<int>(i), m.dim + c);
      w1[ax] = d < 0 ? 0.0 : s.x.v[d];
      for (size_t k = 0; k < s.dp.size(); ++k) sr[k][ax] = d < 0 ? 0.0 : s.dp[k].q[d];
    }
  a.slope->SetTuple(i, r1);
  a.slopeRate->SetTuple(i, w1);
  for (size_t k = 0; k < s.dp.size(); ++k) a.dslope[k]->SetTuple(i, sr[k].data());
}

PointArrays pointData(const Model& m, const StateWithSens& s, vtkPoints* pts) {
  PointArrays a = createPointArrays(m, s.dp.size());
  for (size_t i = 0; i < m.nodes.size(); ++i) {
    putNodeMotion(m, s, i, pts, a);
    if (a.slopes) putNodeSlope(m, s, i, a);
  }
  return a;
}

void addPointData(vtkUnstructuredGrid* grid, const PointArrays& a) {
  grid->GetPointData()->AddArray(a.position);
  grid->GetPointData()->AddArray(a.displacement);
  grid->GetPointData()->AddArray(a.velocity);
  for (size_t k = 0; k < a.dq.size(); ++k) {
    grid->GetPointData()->AddArray(a.dq[k]);
    grid->GetPointData()->AddArray(a.dv[k]);
  }
  if (a.slopes) {
    grid->GetPointData()->AddArray(a.slope);
    grid->GetPointData()->AddArray(a.slopeRate);
    for (const auto& d : a.dslope) grid->GetPointData()->AddArray(d);
  }
}

// ------------------------------------------------------------------ cells per element kind
/// The cells' element_kind and element_id, and which cells are shell triangles.
struct CellTags {
  vtkNew<vtkIntArray> kind, id;
  std::map<vtkIdType, size_t> shellCells;  ///< cell -> element, of the shell triangles
};

/// element_kind of a line cell: 1 rigid bar, 2 spring-damper, 3 beam segment, 4 rigid body,
/// 6 ANCF cable, 7 ANCF beam (5 solid and 8 shell triangle are not lines), 0 other.
int lineKind(const std::string& k) {
  return k == "rigid_bar" ? 1 : k == "spring_damper" ? 2 : k == "beam_segment" ? 3
         : k == "rigid_body" ? 4 : k == "ancf_cable" ? 6 : k == "ancf_beam" ? 7 : 0;
}

/// Two-node elements are lines; a rigid body shows its basic frame (A-B, A-C, A-D); beam
/// hinges and rotational springs share the lines of the elements they join. Shell triangles
/// are the shell's surface (its hinges have no cell of their own).
void addLineAndShellCells(const Model& m, vtkUnstructuredGrid* grid, CellTags& tags) {
  for (size_t e = 0; e < m.elements.size(); ++e) {
    const auto& el = *m.elements[e];
    const std::string k = el.kind();
    std::vector<std::array<int, 2>> lines;
    if (el.nodes().size() == 2) lines.push_back({el.nodes()[0], el.nodes()[1]});
    if (k == "rigid_body")
      for (int j = 1; j < 4; ++j) lines.push_back({el.nodes()[0], el.nodes()[j]});
    for (const auto& l : lines) {
      vtkIdType ids[2] = {l[0], l[1]};
      grid->InsertNextCell(VTK_LINE, 2, ids);
      tags.kind->InsertNextValue(lineKind(k));
      tags.id->InsertNextValue(static_cast<int>(e));
    }
    if (k == "shell_triangle") {
      vtkIdType ids[3] = {el.nodes()[0], el.nodes()[1], el.nodes()[2]};
      tags.shellCells[grid->GetNumberOfCells()] = e;
      grid->InsertNextCell(VTK_TRIANGLE, 3, ids);
      tags.kind->InsertNextValue(8);
      tags.id->InsertNextValue(static_cast<int>(e));
    }
  }
}

// ------------------------------------------------------------------ stresses (cell data)
// Meshed bodies (elements/Solid.hpp): cells of their real type, with cell data of the
// Green-Lagrange strain, the second Piola-Kirchhoff and Cauchy stresses (3x3 tensors in the
// scene's axes, planar ones padded with zeros) and the von Mises stress at each cell's
// centroid, at the nominal parameters, and their sensitivities d/dp (named like
// "dstress_cauchy/dE": the chain rule through the run's dq/dp plus the explicit dependence on
// E and nu, Solid::centroidStressDerivative); NaN on the other cells. Only when the model has one.
// Shell triangles (elements/ShellTriangle.hpp) carry their membrane strain and stresses and
// their sensitivities (ShellTriangle::membraneStressDerivative).

/// [0 .. 3]: strain, PK2, Cauchy, von Mises; then the same four per parameter.
DoubleArrays createStressArrays(const Model& m, size_t parameters) {
  DoubleArrays arrays;
  std::vector<std::string> suffix = {""};
  for (size_t k = 0; k < parameters; ++k) suffix.push_back("/d" + m.parameters[k].name);
  for (const std::string& sfx : suffix)
    for (const char* base : {"green_lagrange_strain", "stress_pk2", "stress_cauchy", "von_mises"}) {
      auto a = vtkSmartPointer<vtkDoubleArray>::New();
      a->SetName(((sfx.empty() ? "" : "d") + std::string(base) + sfx).c_str());
      a->SetNumberOfComponents(std::string(base) == "von_mises" ? 1 : 9);
      arrays.push_back(a);
    }
  return arrays;
}

/// The stresses of the cells already in the grid (lines: NaN; shell triangles: membrane).
void shellStresses(const Model& m, const StateWithSens& s, vtkIdType cells,
                   const std::map<vtkIdType, size_t>& shellCells, DoubleArrays& arrays) {
  const double nan = std::nan("");
  const std::array<double, 9> nans{nan, nan, nan, nan, nan, nan, nan, nan, nan};
  const VecX pn = m.nominalParameters();
  for (vtkIdType c = 0; c < cells; ++c) {
    const auto sc = shellCells.find(c);
    if (sc == shellCells.end()) {
      for (auto& a : arrays) a->InsertNextTuple(nans.data());
      continue;
    }
    const auto& tri = static_cast<const ShellTriangle&>(*m.elements[sc->second]);
    LocalState ls;
    ls.dim = 3;
    ls.p = &pn;
    ls.x.resize(9);
    for (int j = 0; j < 3; ++j)
      for (int cc = 0; cc < 3; ++cc) ls.x[3 * j + cc] = m.coordinate(s.x.q, tri.nodes()[j], cc);
    MatX E, S, sig;
    double vm;
    tri.membraneStress(ls, E, S, sig, vm);
    arrays[0]->InsertNextTuple(E.data());  // symmetric: column-major = row-major
    arrays[1]->InsertNextTuple(S.data());
    arrays[2]->InsertNextTuple(sig.data());
    arrays[3]->InsertNextTuple(&vm);
    for (size_t k = 0; k < s.dp.size(); ++k) {
      tri.membraneStressDerivative(ls, gatherNodeCoordinates(m, tri.nodes(), s.dp[k].q, true), static_cast<int>(k), E,
                                   S, sig, vm);
      arrays[4 * k + 4]->InsertNextTuple(E.data());
      arrays[4 * k + 5]->InsertNextTuple(S.data());
      arrays[4 * k + 6]->InsertNextTuple(sig.data());
      arrays[4 * k + 7]->InsertNextTuple(&vm);
    }
  }
}

/// A dim x dim tensor as the 3 x 3 tuple in the scene's axes (planar: padded with zeros).
void putTensor(const Model& m, vtkDoubleArray* a, const MatX& T) {
  std::array<double, 9> t{};
  for (int r = 0; r < m.dim; ++r)
    for (int c = 0; c < m.dim; ++c) t[3 * axisOf(m, r) + axisOf(m, c)] = T(r, c);
  a->InsertNextTuple(t.data());
}

/// Solid element e's cell of its own type, its tags, and its centroid stresses and their d/dp.
void addSolidCell(const Model& m, const StateWithSens& s, const VecX& p, size_t e, const Solid& so,
                  vtkUnstructuredGrid* grid, CellTags& tags, DoubleArrays& arrays) {
  const double nan = std::nan("");
  const auto& nodes = so.nodes();
  std::vector<vtkIdType> ids(nodes.begin(), nodes.end());
  const int type = so.shape() == Simplex::Tri3 ? VTK_TRIANGLE : so.shape() == Simplex::Tri6 ? VTK_QUADRATIC_TRIANGLE
                   : so.shape() == Simplex::Tet4 ? VTK_TETRA : VTK_QUADRATIC_TETRA;
  grid->InsertNextCell(type, static_cast<vtkIdType>(ids.size()), ids.data());
  tags.kind->InsertNextValue(5);
  tags.id->InsertNextValue(static_cast<int>(e));
  LocalState ls;
  ls.dim = m.dim;
  ls.p = &p;
  ls.x.resize(m.dim * nodes.size());
  for (size_t j = 0; j < nodes.size(); ++j)
    for (int c = 0; c < m.dim; ++c) ls.x[j * m.dim + c] = m.coordinate(s.x.q, nodes[j], c);
  for (size_t k = 0; k <= s.dp.size(); ++k) {
    MatX E, S, sig;
    double vm = nan;
    try {
      if (k == 0)
        so.centroidStress(ls, E, S, sig, vm);
      else
        so.centroidStressDerivative(ls, gatherNodeCoordinates(m, nodes, s.dp[k - 1].q, true), static_cast<int>(k - 1),
                                    E, S, sig, vm);
    } catch (const NumericalError&) {  // inside out: no stress to show
      E = S = sig = MatX::Constant(m.dim, m.dim, nan);
    }
    putTensor(m, arrays[4 * k], E);
    putTensor(m, arrays[4 * k + 1], S);
    putTensor(m, arrays[4 * k + 2], sig);
    arrays[4 * k + 3]->InsertNextValue(vm);
  }
}

/// The stress arrays of every cell when the model has shells or meshed bodies (empty otherwise);
/// the meshed bodies' cells are added to the grid here.
DoubleArrays stressCells(const Model& m, const StateWithSens& s, vtkUnstructuredGrid* grid, CellTags& tags) {
  bool anySolid = !tags.shellCells.empty();
  for (const auto& el : m.elements) anySolid = anySolid || dynamic_cast<const Solid*>(el.get());
  if (!anySolid) return {};
  DoubleArrays arrays = createStressArrays(m, s.dp.size());
  shellStresses(m, s, grid->GetNumberOfCells(), tags.shellCells, arrays);
  const VecX p = m.nominalParameters();
  for (size_t e = 0; e < m.elements.size(); ++e)
    if (const auto* so = dynamic_cast<const Solid*>(m.elements[e].get())) addSolidCell(m, s, p, e, *so, grid, tags, arrays);
  return arrays;
}

}  // namespace

VecX gatherNodeCoordinates(const Model& m, const std::vector<int>& nodes, const VecX& q, bool derivative) {
  VecX x(m.dim * nodes.size());
  for (size_t a = 0; a < nodes.size(); ++a)
    for (int c = 0; c < m.dim; ++c) {
      const int d = m.dof(nodes[a], c);
      x[m.dim * a + c] = d >= 0 ? q[d] : (derivative ? 0.0 : m.nodes[nodes[a]].position[c]);
    }
  return x;
}

vtkSmartPointer<vtkUnstructuredGrid> frameGrid(const Model& m, const StateWithSens& s) {
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  const PointArrays points = pointData(m, s, pts);
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(pts);
  CellTags tags;
  tags.kind->SetName("element_kind");  // lineKind; 5 solid, 8 shell triangle
  tags.id->SetName("element_id");
  addLineAndShellCells(m, grid, tags);
  const DoubleArrays stresses = stressCells(m, s, grid, tags);
  grid->GetCellData()->AddArray(tags.kind);
  grid->GetCellData()->AddArray(tags.id);
  for (auto& a : stresses) grid->GetCellData()->AddArray(a);
  addPointData(grid, points);
  return grid;
}

VtuWriteStatus writeVtuFile(vtkUnstructuredGrid* grid, const std::string& path) {
  vtkNew<vtkXMLUnstructuredGridWriter> w;
  w->SetFileName(path.c_str());
  w->SetInputData(grid);
  w->SetDataModeToAppended();
  w->EncodeAppendedDataOff();
  errno = 0;
  const int written = w->Write();
  VtuWriteStatus st;
  st.err = errno;
  st.code = w->GetErrorCode();
  struct stat file;
  st.ok = written == 1 && st.code == vtkErrorCode::NoError && ::stat(path.c_str(), &file) == 0 && file.st_size > 0;
  return st;
}

}  // namespace flexsens
