#include "output/ResultWriter.hpp"

#include <vtkErrorCode.h>
#include <vtkNew.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <malloc.h>
#include <sys/stat.h>

#include "constraints/Driver.hpp"
#include "output/VtuFrame.hpp"

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
}  // namespace

void keepFreedMemory() {
  mallopt(M_TRIM_THRESHOLD, 512 * 1024 * 1024);
  mallopt(M_MMAP_THRESHOLD, 64 * 1024 * 1024);
}

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
  writes_ = !dir_.empty();
  if (writes_) {
    const std::string csvPath = dir_ + "/" + stem_ + "series.csv";
    errno = 0;
    csv_.open(csvPath);
    if (!csv_) fail(stem_ + "series.csv", errno);
    files_.push_back(csvPath);
  }
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
  if (!writes_) return;
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
  if (writes_) {
    errno = 0;
    for (size_t i = 0; i < lastRow_.size(); ++i) csv_ << (i ? "," : "") << lastRow_[i];
    csv_ << "\n";
    if (!csv_) fail(stem_ + "series.csv", errno);  // the buffer went to a full disk, ...
  }
  times_.push_back(s.x.t);
  tReached_ = s.x.t;
  if (writes_ && scene_.output.vtk) {
    std::ostringstream name;
    name << stem_ << "frame_" << std::setw(5) << std::setfill('0') << times_.size() - 1 << ".vtu";
    writeVtu(s, name.str());
    vtuFiles_.push_back(name.str());
  }
}

VecX ResultWriter::gatherNodes(const std::vector<int>& nodes, const VecX& q, bool derivative) const {
  return gatherNodeCoordinates(*scene_.model, nodes, q, derivative);
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
  const vtkSmartPointer<vtkUnstructuredGrid> grid = frameGrid(*scene_.model, s);
  const VtuWriteStatus st = writeVtuFile(grid, dir_ + "/" + name);
  if (st.ok) return;
  if (st.code == vtkErrorCode::OutOfDiskSpaceError) fail(name, ENOSPC);
  if (st.err == 0 && st.code != vtkErrorCode::NoError)
    throw OutputError("cannot write " + shownDir_ + "/" + name + ": VTK error code " + std::to_string(st.code) +
                      " (vtkErrorCode.h)");
  fail(name, st.err);
}

void ResultWriter::progress(double t) {
  tReached_ = t;
  if (!showProgress_) return;
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
  if (!scene_.output.vtk || !writes_) return;
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
