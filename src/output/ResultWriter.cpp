#include "output/ResultWriter.hpp"

#include "elements/ShellTriangle.hpp"
#include "elements/Solid.hpp"

#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <sys/stat.h>

#include "constraints/Driver.hpp"

#include <array>
#include <cerrno>
#include <cstring>
#include <chrono>
#include <cmath>
#include <map>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace flexsens {

namespace {
double wallSeconds() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}
/// Index (0..2) of planar axis c in 3D, given the scene's plane ("xz" -> x=0, z=2).
int axis3(const Model& m, int c) {
  const char a = m.axisName(c);
  return a == 'x' ? 0 : (a == 'y' ? 1 : 2);
}
}  // namespace

std::string jsonString(const std::string& s) {
  std::string r = "\"";
  for (char ch : s) {
    if (ch == '"' || ch == '\\') r += '\\', r += ch;
    else if (ch == '\n') r += "\\n";
    else if (static_cast<unsigned char>(ch) < 0x20) r += ' ';
    else r += ch;
  }
  return r + "\"";
}

std::string jsonNumber(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream os;
  os << std::setprecision(12) << v;
  return os.str();
}

ResultWriter::ResultWriter(const Scene& scene, std::string dir, std::string stem, std::string shownDir,
                           const std::string& timeColumn, const EnergyMeter* energy)
    : scene_(scene), energy_(energy), dir_(std::move(dir)), stem_(std::move(stem)), shownDir_(std::move(shownDir)),
      tEnd_(scene.integrator.tEnd), startWall_(wallSeconds()) {
  if (shownDir_.empty()) shownDir_ = dir_;
  const std::string csvPath = dir_ + "/" + stem_ + "series.csv";
  errno = 0;
  csv_.open(csvPath);
  if (!csv_) fail(stem_ + "series.csv", errno);
  files_.push_back(csvPath);
  columns_.push_back(timeColumn);
  for (const auto& o : scene_.outputs) columns_.push_back(o.name);
  for (const auto& o : scene_.outputs)
    for (const auto& p : scene_.model->parameters) columns_.push_back("d" + o.name + "/d" + p.name);
  {
    const Model& m = *scene_.model;
    int row = 0;
    for (size_t c = 0; c < m.constraints.size(); ++c) {
      if (dynamic_cast<const Driver*>(m.constraints[c].get()))
        drivers_.emplace_back(c, row);
      row += m.constraints[c]->rows();
    }
    std::vector<std::string> names;
    for (const auto& [c, r] : drivers_) {
      const auto* d = static_cast<const Driver*>(m.constraints[c].get());
      names.push_back(d->name() + ".reaction_" + (std::string(d->reactionUnit()) == "N" ? "N" : "Nm"));
    }
    for (const auto& n : names) columns_.push_back(n);
    for (const auto& n : names)
      for (const auto& p : m.parameters) columns_.push_back("d" + n + "/d" + p.name);
  }
  if (energy_) {
    for (const char* c : {"kinetic_J", "potential_J", "energy_J"}) columns_.push_back(c);
    for (const auto& p : scene_.model->parameters) columns_.push_back("denergy_J/d" + p.name);
  }
  for (size_t i = 0; i < columns_.size(); ++i) csv_ << (i ? "," : "") << columns_[i];
  csv_ << "\n";
  csv_ << std::setprecision(15);
}

void ResultWriter::frame(const StateWithSens& s) {
  const Model& m = *scene_.model;
  for (const auto* v : {&s.x.q, &s.x.v})
    if (!v->allFinite())
      throw NumericalError("non-finite state at t = " + std::to_string(s.x.t) + " s; nothing written for it");
  lastRow_.assign(1, s.x.t);
  for (const auto& o : scene_.outputs) lastRow_.push_back(o.value(m, s.x));
  for (const auto& o : scene_.outputs)
    for (size_t k = 0; k < s.dp.size(); ++k) lastRow_.push_back(o.derivative(m, s.x, s.dp[k]));
  if (!drivers_.empty()) {
    // reaction = -lambda dPhi/ds; its derivative -(lambda_p dPhi/ds + lambda (dPhi/ds)_x x_p)
    std::vector<double> sens;
    for (const auto& [c, r] : drivers_) {
      const auto* d = static_cast<const Driver*>(m.constraints[c].get());
      VecX grad;
      const double lam = s.x.lambda.size() > r ? s.x.lambda[r] : 0.0;
      const double scale = d->reactionScale(gatherNodes(d->nodes(), s.x.q, false), &grad);
      lastRow_.push_back(-lam * scale);
      for (size_t k = 0; k < s.dp.size(); ++k) {
        const double lp = s.dp[k].lambda.size() > r ? s.dp[k].lambda[r] : 0.0;
        sens.push_back(-(lp * scale + lam * grad.dot(gatherNodes(d->nodes(), s.dp[k].q, true))));
      }
    }
    lastRow_.insert(lastRow_.end(), sens.begin(), sens.end());
  }
  if (energy_) {
    const Energy e = energy_->at(s.x.q, s.x.v);
    lastRow_.insert(lastRow_.end(), {e.kinetic, e.potential, e.total()});
    for (const double d : energy_->sensitivities(s.x, s.dp)) lastRow_.push_back(d);
  }
  requireFiniteRow();
  errno = 0;
  for (size_t i = 0; i < lastRow_.size(); ++i) csv_ << (i ? "," : "") << lastRow_[i];
  csv_ << "\n";
  if (!csv_) fail(stem_ + "series.csv", errno);  // the buffer went to a full disk, ...
  times_.push_back(s.x.t);
  tReached_ = s.x.t;
  if (scene_.output.vtk) {
    std::ostringstream name;
    name << stem_ << "frame_" << std::setw(5) << std::setfill('0') << times_.size() - 1 << ".vtu";
    writeVtu(s, name.str());
    vtuFiles_.push_back(name.str());
  }
}

VecX ResultWriter::gatherNodes(const std::vector<int>& nodes, const VecX& q, bool derivative) const {
  const Model& m = *scene_.model;
  VecX x(m.dim * nodes.size());
  for (size_t a = 0; a < nodes.size(); ++a)
    for (int c = 0; c < m.dim; ++c) {
      const int d = m.dof(nodes[a], c);
      x[m.dim * a + c] = d >= 0 ? q[d] : (derivative ? 0.0 : m.nodes[nodes[a]].position[c]);
    }
  return x;
}

void ResultWriter::requireFiniteRow() const {
  for (size_t i = 0; i < lastRow_.size(); ++i) {
    if (std::isfinite(lastRow_[i])) continue;
    const std::string col = i < columns_.size() ? columns_[i] : "number " + std::to_string(i + 1);
    const bool derivative = col.rfind("d", 0) == 0 && col.find("/d") != std::string::npos;
    std::ostringstream os;
    os << "series.csv column '" << col << "' would hold " << lastRow_[i] << " at " << columns_.front() << " = "
       << lastRow_.front() << " (frame " << times_.size() << "); nothing was written for it. "
       << (derivative ? "A parameter derivative: check the parameter's nominal value (0 or near it where the "
                        "derivative is undefined), or compare with --method nd"
                      : "Try a smaller dt, another integrator (--integrator idas), or check the scene's values");
    throw NumericalError(os.str());
  }
}

void ResultWriter::fail(const std::string& name, int err) const {
  throw OutputError("cannot write " + shownDir_ + "/" + name + ": " +
                    (err ? std::strerror(err) : "the stream failed without an OS error"));
}

void ResultWriter::writeVtu(const StateWithSens& s, const std::string& name) const {
  const std::string path = dir_ + "/" + name;
  const Model& m = *scene_.model;
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  auto vectorArray = [&](const std::string& name) {
    vtkNew<vtkDoubleArray> a;
    a->SetName(name.c_str());
    a->SetNumberOfComponents(3);
    a->SetNumberOfTuples(m.nodes.size());
    return a;
  };
  auto pos = vectorArray("position"), disp = vectorArray("displacement"), vel = vectorArray("velocity");
  std::vector<vtkSmartPointer<vtkDoubleArray>> dq, dv, ds;
  for (size_t k = 0; k < s.dp.size(); ++k) {
    dq.push_back(vectorArray("dq/d" + m.parameters[k].name));
    dv.push_back(vectorArray("dv/d" + m.parameters[k].name));
  }
  // Nodes say what they carry: when some carry a slope (ANCF; an ancf_beam node: its r_x), the slope r' = dr/ds [-], its
  // rate [1/s] and its sensitivities are point-data vectors too (zero on nodes without one).
  bool slopes = false;
  for (const Node& nd : m.nodes) slopes = slopes || nd.hasSlope();
  vtkSmartPointer<vtkDoubleArray> slope, slopeRate;
  if (slopes) {
    slope = vectorArray("slope");
    slopeRate = vectorArray("slope_rate");
    for (size_t k = 0; k < s.dp.size(); ++k) ds.push_back(vectorArray("dslope/d" + m.parameters[k].name));
  }
  for (size_t i = 0; i < m.nodes.size(); ++i) {
    double x[3] = {0, 0, 0}, x0[3] = {0, 0, 0}, v[3] = {0, 0, 0};
    std::vector<std::array<double, 3>> sq(s.dp.size(), {0, 0, 0}), sv(s.dp.size(), {0, 0, 0});
    for (int c = 0; c < m.dim; ++c) {
      const int a = m.dim == 3 ? c : axis3(m, c);
      const int d = m.dof(static_cast<int>(i), c);
      x0[a] = m.nodes[i].position[c];
      x[a] = d < 0 ? x0[a] : s.x.q[d];
      v[a] = d < 0 ? 0.0 : s.x.v[d];
      for (size_t k = 0; k < s.dp.size(); ++k) {
        sq[k][a] = d < 0 ? 0.0 : s.dp[k].q[d];
        sv[k][a] = d < 0 ? 0.0 : s.dp[k].v[d];
      }
    }
    pts->InsertNextPoint(x);
    pos->SetTuple(i, x);
    const double u[3] = {x[0] - x0[0], x[1] - x0[1], x[2] - x0[2]};
    disp->SetTuple(i, u);
    vel->SetTuple(i, v);
    for (size_t k = 0; k < s.dp.size(); ++k) {
      dq[k]->SetTuple(i, sq[k].data());
      dv[k]->SetTuple(i, sv[k].data());
    }
    if (!slopes) continue;
    double r1[3] = {0, 0, 0}, w1[3] = {0, 0, 0};
    std::vector<std::array<double, 3>> sr(s.dp.size(), {0, 0, 0});
    if (m.nodes[i].hasSlope())
      for (int c = 0; c < m.dim; ++c) {
        const int a = m.dim == 3 ? c : axis3(m, c);
        const int d = m.dof(static_cast<int>(i), m.dim + c);  // -1: clamped, fixed slope
        r1[a] = m.coordinate(s.x.q, static_cast<int>(i), m.dim + c);
        w1[a] = d < 0 ? 0.0 : s.x.v[d];
        for (size_t k = 0; k < s.dp.size(); ++k) sr[k][a] = d < 0 ? 0.0 : s.dp[k].q[d];
      }
    slope->SetTuple(i, r1);
    slopeRate->SetTuple(i, w1);
    for (size_t k = 0; k < s.dp.size(); ++k) ds[k]->SetTuple(i, sr[k].data());
  }
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(pts);
  vtkNew<vtkIntArray> kind, id;
  kind->SetName("element_kind");  // 1 rigid bar, 2 spring-damper, 3 beam segment, 4 rigid body, 5 solid, 6 ANCF cable, 7 ANCF beam, 8 shell triangle
  id->SetName("element_id");
  std::map<vtkIdType, size_t> shellCells;  // cell -> element, of the shell triangles
  for (size_t e = 0; e < m.elements.size(); ++e) {
    const auto& el = *m.elements[e];
    const std::string k = el.kind();
    // Two-node elements are lines; a rigid body shows its basic frame (A-B, A-C, A-D);
    // beam hinges and rotational springs share the lines of the elements they join.
    std::vector<std::array<int, 2>> lines;
    if (el.nodes().size() == 2) lines.push_back({el.nodes()[0], el.nodes()[1]});
    if (k == "rigid_body")
      for (int j = 1; j < 4; ++j) lines.push_back({el.nodes()[0], el.nodes()[j]});
    for (const auto& l : lines) {
      vtkIdType ids[2] = {l[0], l[1]};
      grid->InsertNextCell(VTK_LINE, 2, ids);
      kind->InsertNextValue(k == "rigid_bar" ? 1 : k == "spring_damper" ? 2 : k == "beam_segment" ? 3
                                                  : k == "rigid_body" ? 4 : k == "ancf_cable" ? 6 : k == "ancf_beam" ? 7 : 0);
      id->InsertNextValue(static_cast<int>(e));
    }
    if (k == "shell_triangle") {  // the shell's surface (its hinges have no cell of their own)
      vtkIdType ids[3] = {el.nodes()[0], el.nodes()[1], el.nodes()[2]};
      shellCells[grid->GetNumberOfCells()] = e;
      grid->InsertNextCell(VTK_TRIANGLE, 3, ids);
      kind->InsertNextValue(8);
      id->InsertNextValue(static_cast<int>(e));
    }
  }
  // Meshed bodies (elements/Solid.hpp): cells of their real type, with cell data of the
  // Green-Lagrange strain, the second Piola-Kirchhoff and Cauchy stresses (3x3 tensors in the
  // scene's axes, planar ones padded with zeros) and the von Mises stress at each cell's
  // centroid, at the nominal parameters, and their sensitivities d/dp (named like
  // "dstress_cauchy/dE": the chain rule through the run's dq/dp plus the explicit dependence on
  // E and nu, Solid::centroidStressDerivative); NaN on the other cells. Only when the model has one.
  // Shell triangles (elements/ShellTriangle.hpp) carry their membrane strain and stresses and
  // their sensitivities (ShellTriangle::membraneStressDerivative).
  bool anySolid = !shellCells.empty();
  for (const auto& el : m.elements) anySolid = anySolid || dynamic_cast<const Solid*>(el.get());
  // [0 .. 3]: strain, PK2, Cauchy, von Mises; then the same four per parameter.
  std::vector<vtkSmartPointer<vtkDoubleArray>> cellArrays;
  if (anySolid) {
    const vtkIdType before = grid->GetNumberOfCells();
    std::vector<std::string> suffix = {""};
    for (size_t k = 0; k < s.dp.size(); ++k) suffix.push_back("/d" + m.parameters[k].name);
    for (const std::string& sfx : suffix)
      for (const char* base : {"green_lagrange_strain", "stress_pk2", "stress_cauchy", "von_mises"}) {
        auto a = vtkSmartPointer<vtkDoubleArray>::New();
        a->SetName(((sfx.empty() ? "" : "d") + std::string(base) + sfx).c_str());
        a->SetNumberOfComponents(std::string(base) == "von_mises" ? 1 : 9);
        cellArrays.push_back(a);
      }
    const double nan = std::nan("");
    const std::array<double, 9> nans{nan, nan, nan, nan, nan, nan, nan, nan, nan};
    const VecX pn = m.nominalParameters();
    for (vtkIdType c = 0; c < before; ++c) {
      const auto sc = shellCells.find(c);
      if (sc == shellCells.end()) {
        for (auto& a : cellArrays) a->InsertNextTuple(nans.data());
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
      cellArrays[0]->InsertNextTuple(E.data());  // symmetric: column-major = row-major
      cellArrays[1]->InsertNextTuple(S.data());
      cellArrays[2]->InsertNextTuple(sig.data());
      cellArrays[3]->InsertNextTuple(&vm);
      for (size_t k = 0; k < s.dp.size(); ++k) {
        tri.membraneStressDerivative(ls, gatherNodes(tri.nodes(), s.dp[k].q, true), static_cast<int>(k), E, S, sig, vm);
        cellArrays[4 * k + 4]->InsertNextTuple(E.data());
        cellArrays[4 * k + 5]->InsertNextTuple(S.data());
        cellArrays[4 * k + 6]->InsertNextTuple(sig.data());
        cellArrays[4 * k + 7]->InsertNextTuple(&vm);
      }
    }
    const VecX p = m.nominalParameters();
    for (size_t e = 0; e < m.elements.size(); ++e) {
      const auto* so = dynamic_cast<const Solid*>(m.elements[e].get());
      if (!so) continue;
      const auto& nodes = so->nodes();
      std::vector<vtkIdType> ids(nodes.begin(), nodes.end());
      const int type = so->shape() == Simplex::Tri3 ? VTK_TRIANGLE : so->shape() == Simplex::Tri6 ? VTK_QUADRATIC_TRIANGLE
                       : so->shape() == Simplex::Tet4 ? VTK_TETRA : VTK_QUADRATIC_TETRA;
      grid->InsertNextCell(type, static_cast<vtkIdType>(ids.size()), ids.data());
      kind->InsertNextValue(5);
      id->InsertNextValue(static_cast<int>(e));
      LocalState ls;
      ls.dim = m.dim;
      ls.p = &p;
      ls.x.resize(m.dim * nodes.size());
      for (size_t j = 0; j < nodes.size(); ++j)
        for (int c = 0; c < m.dim; ++c) ls.x[j * m.dim + c] = m.coordinate(s.x.q, nodes[j], c);
      auto put = [&](vtkDoubleArray* a, const MatX& T) {
        std::array<double, 9> t{};
        for (int r = 0; r < m.dim; ++r)
          for (int c = 0; c < m.dim; ++c) {
            const int R = m.dim == 3 ? r : axis3(m, r), C = m.dim == 3 ? c : axis3(m, c);
            t[3 * R + C] = T(r, c);
          }
        a->InsertNextTuple(t.data());
      };
      for (size_t k = 0; k <= s.dp.size(); ++k) {
        MatX E, S, sig;
        double vm = nan;
        try {
          if (k == 0)
            so->centroidStress(ls, E, S, sig, vm);
          else
            so->centroidStressDerivative(ls, gatherNodes(nodes, s.dp[k - 1].q, true), static_cast<int>(k - 1), E, S,
                                         sig, vm);
        } catch (const NumericalError&) {  // inside out: no stress to show
          E = S = sig = MatX::Constant(m.dim, m.dim, nan);
        }
        put(cellArrays[4 * k], E);
        put(cellArrays[4 * k + 1], S);
        put(cellArrays[4 * k + 2], sig);
        cellArrays[4 * k + 3]->InsertNextValue(vm);
      }
    }
  }
  grid->GetCellData()->AddArray(kind);
  grid->GetCellData()->AddArray(id);
  for (auto& a : cellArrays) grid->GetCellData()->AddArray(a);
  grid->GetPointData()->AddArray(pos);
  grid->GetPointData()->AddArray(disp);
  grid->GetPointData()->AddArray(vel);
  for (size_t k = 0; k < dq.size(); ++k) {
    grid->GetPointData()->AddArray(dq[k]);
    grid->GetPointData()->AddArray(dv[k]);
  }
  if (slopes) {
    grid->GetPointData()->AddArray(slope);
    grid->GetPointData()->AddArray(slopeRate);
    for (const auto& a : ds) grid->GetPointData()->AddArray(a);
  }
  vtkNew<vtkXMLUnstructuredGridWriter> w;
  w->SetFileName(path.c_str());
  w->SetInputData(grid);
  w->SetDataModeToAppended();
  w->EncodeAppendedDataOff();
  // VTK reports a failed write in its return value, or only in its error code (a full disk
  // can leave a truncated file and success): check both, and the file itself.
  errno = 0;
  const int ok = w->Write();
  const int err = errno;
  const unsigned long code = w->GetErrorCode();
  struct stat st;
  if (ok != 1 || code != vtkErrorCode::NoError || ::stat(path.c_str(), &st) != 0 || st.st_size == 0) {
    if (code == vtkErrorCode::OutOfDiskSpaceError) fail(name, ENOSPC);
    if (err == 0 && code != vtkErrorCode::NoError)
      throw OutputError("cannot write " + shownDir_ + "/" + name + ": VTK error code " + std::to_string(code) +
                        " (vtkErrorCode.h)");
    fail(name, err);
  }
}

void ResultWriter::progress(double t) {
  tReached_ = t;
  const double now = wallSeconds() - startWall_;
  if (now < 1.0 || now - lastPrint_ < 0.5) return;
  lastPrint_ = now;
  printed_ = true;
  std::fprintf(stderr, "\r  t = %.4f / %.4f s  (%3.0f%%)  %.1f s elapsed", t, tEnd_,
               100.0 * t / tEnd_, now);
  std::fflush(stderr);
}

void ResultWriter::close() {
  if (printed_) std::fprintf(stderr, "\n");
  printed_ = false;
  if (csv_.is_open()) {
    errno = 0;
    csv_.flush();
    if (!csv_) fail(stem_ + "series.csv", errno);
    csv_.close();
    if (!csv_) fail(stem_ + "series.csv", errno);
  }
  if (!scene_.output.vtk) return;
  const std::string path = dir_ + "/" + stem_ + "frames.pvd";
  errno = 0;
  std::ofstream pvd(path);
  if (!pvd) fail(stem_ + "frames.pvd", errno);
  pvd << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n";
  pvd << std::setprecision(12);
  for (size_t i = 0; i < vtuFiles_.size(); ++i)
    pvd << "    <DataSet timestep=\"" << times_[i] << "\" part=\"0\" file=\"" << vtuFiles_[i] << "\"/>\n";
  pvd << "  </Collection>\n</VTKFile>\n";
  pvd.close();
  if (!pvd) fail(stem_ + "frames.pvd", errno);
  files_.push_back(path);
}

}  // namespace flexsens
