#include "app/Modes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "core/MemoryBudget.hpp"

namespace flexsens {

double Mode::omega() const { return omega2 >= 0.0 ? std::sqrt(omega2) : -std::sqrt(-omega2); }

namespace {

std::string partOf(const std::string& elementName) {
  return elementName.substr(0, elementName.find('.'));
}

VecX gather(const std::vector<int>& map, const VecX& x) {
  VecX r = VecX::Zero(map.size());
  for (size_t i = 0; i < map.size(); ++i)
    if (map[i] >= 0) r[i] = x[map[i]];
  return r;
}

/// Labels of the coordinates carrying the largest entries of x (at most 4).
std::string largestCoordinates(const Model& model, const VecX& x) {
  std::vector<int> idx(x.size());
  for (int i = 0; i < x.size(); ++i) idx[i] = i;
  std::sort(idx.begin(), idx.end(), [&](int a, int b) { return std::abs(x[a]) > std::abs(x[b]); });
  std::string s;
  for (size_t k = 0; k < idx.size() && k < 4; ++k) {
    if (std::abs(x[idx[k]]) < 0.1 * std::abs(x[idx[0]])) break;
    s += (k ? ", " : "") + model.coordinateLabel(idx[k]);
  }
  return s;
}

/// Strain and kinetic energy of mode shape x (full coordinates) by part, as shares.
std::vector<EnergyShare> energyShares(const Assembler& as, const State& s, const VecX& p,
                                      const VecX& x, double omega2, const MatX& Kc) {
  const Model& model = as.model();
  std::map<std::string, EnergyShare> byPart;
  std::vector<std::string> order;
  auto entry = [&](const std::string& part) -> EnergyShare& {
    if (!byPart.count(part)) {
      order.push_back(part);
      byPart[part].part = part;
    }
    return byPart[part];
  };
  MatX Kq, Kv, Me;
  double total = 0.0;  // sum of |energies|: an unstable mode's strain is negative
  for (size_t e = 0; e < model.elements.size(); ++e) {
    const Element& el = *model.elements[e];
    const LocalState ls = as.localState(el, s.q, s.v, p);
    const VecX xe = gather(as.elementDofs(e), x);
    el.forceJacobian(ls, Kq, Kv);
    const double U = -0.5 * xe.dot(Kq * xe);  // K_e = -dQ_e/dq
    const double T = el.mass(ls, Me) ? 0.5 * std::abs(omega2) * xe.dot(Me * xe) : 0.0;
    EnergyShare& sh = entry(partOf(el.name()));
    sh.strain += U;
    sh.kinetic += T;
    total += std::abs(U) + std::abs(T);
  }
  if (as.m()) {  // geometric stiffness of the constraint forces, lambda Phi_qq
    const double U = 0.5 * x.dot(Kc * x);
    entry("constraints").strain += U;
    total += std::abs(U);
  }
  std::vector<EnergyShare> r;
  for (const auto& name : order) {
    EnergyShare sh = byPart[name];
    sh.strain /= total;
    sh.kinetic /= total;
    r.push_back(sh);
  }
  std::sort(r.begin(), r.end(), [](const EnergyShare& a, const EnergyShare& b) {
    return std::abs(a.total()) > std::abs(b.total());
  });
  return r;
}

}  // namespace

void requireModesMemory(int n) {
  // K, Kc, M, the null-space basis N, the reduced and condensed matrices and the eigenvectors:
  // about eight dense n x n matrices at their peak.
  requireMemory(doubles(8.0 * n * n), "modes: the dense eigenproblem of n = " + std::to_string(n) + " coordinates",
                "coarsen the mesh (the bodies' size key) or use fewer segments");
}

void requireIndependentConstraints(const Assembler& as, const VecX& q, const VecX& p) {
  const int m = as.m();
  if (m == 0) return;
  requireMemory(doubles(2.0 * m * as.n()), "the rank check of Phi_q (" + std::to_string(m) + " x " +
                std::to_string(as.n()) + ", dense)", "coarsen the mesh (the bodies' size key) or use fewer segments");
  const MatX J = as.phiQDense(q, p);
  Eigen::ColPivHouseholderQR<MatX> qr(J.transpose());  // pivots pick independent rows of J
  qr.setThreshold(1e-10);  // pivots below 1e-10 of the largest count as zero
  const int rank = static_cast<int>(qr.rank());
  if (rank == m) return;
  std::ostringstream os;
  os << "the constraint Jacobian Phi_q at the initial positions has rank " << rank << " < " << m
     << " rows (redundant constraints, or a constraint degenerate at this configuration); rows that "
        "depend on the others:";
  for (int k = rank; k < m; ++k) os << (k > rank ? ", " : " ") << as.rowLabel(qr.colsPermutation().indices()[k]);
  os << "; remove them or change the configuration";
  throw NumericalError(os.str());
}

MatX tangentStiffness(const Assembler& as, const State& s, const VecX& p) {
  SparseAccumulator acc;
  acc.begin(as.n(), as.n());
  as.addForceJacobian(acc, s.q, s.v, p, 1.0, 0.0, 0, 0, 0);
  if (as.m()) as.addHessian(acc, s.q, p, s.lambda, 1.0, 0, 0);
  return MatX(acc.finish());
}

ModalAnalysis analyzeModes(const Assembler& as, const State& s, const VecX& p, int count) {
  const Model& model = as.model();
  const int n = as.n(), m = as.m();
  requireModesMemory(n);
  requireIndependentConstraints(as, s.q, p);
  ModalAnalysis a;
  a.n = n;
  a.m = m;

  // K = -dQ/dq + H(lambda) [N/m]; Kc = H(lambda) alone (for the energy of the constraints).
  MatX K = tangentStiffness(as, s, p);
  MatX Kc = MatX::Zero(n, n);
  if (m) {
    SparseAccumulator acc;
    acc.begin(n, n);
    as.addHessian(acc, s.q, p, s.lambda, 1.0, 0, 0);
    Kc = MatX(acc.finish());
  }
  const double kNorm = K.norm();
  a.asymmetry = kNorm > 0 ? (K - K.transpose()).norm() / kNorm : 0.0;
  K = 0.5 * (K + K.transpose());
  Kc = 0.5 * (Kc + Kc.transpose());
  const MatX M = MatX(as.mass(p));

  // Orthonormal basis N of the null space of Phi_q: the last n - m columns of Q in Phi_q^T = QR.
  MatX N;
  if (m) {
    Eigen::HouseholderQR<MatX> qr(as.phiQDense(s.q, p).transpose());
    N = MatX(qr.householderQ()).rightCols(n - m);
  } else {
    N = MatX::Identity(n, n);
  }
  a.tangent = static_cast<int>(N.cols());
  if (a.tangent == 0) {
    a.noModes = "no dynamic direction: the " + std::to_string(m) + " constraint equations fix all " +
                std::to_string(n) + " coordinates (d = n - m = 0), so nothing can vibrate";
    return a;
  }
  const MatX Kr = N.transpose() * K * N, Mr = N.transpose() * M * N;

  // Split the tangent space into directions with mass (A) and massless ones (B).
  Eigen::SelfAdjointEigenSolver<MatX> me(Mr);
  const VecX mu = me.eigenvalues();
  const double muMax = mu.size() ? std::max(mu.maxCoeff(), 0.0) : 0.0;
  const double muTol = 1e-12 * muMax;
  std::vector<int> ia, ib;
  for (int i = 0; i < mu.size(); ++i) (mu[i] > muTol ? ia : ib).push_back(i);
  a.massless = static_cast<int>(ib.size());
  const int na = static_cast<int>(ia.size()), nb = a.massless;
  MatX A(Mr.rows(), na), B(Mr.rows(), nb);
  for (int j = 0; j < na; ++j) A.col(j) = me.eigenvectors().col(ia[j]) / std::sqrt(mu[ia[j]]);  // A^T Mr A = I
  for (int j = 0; j < nb; ++j) B.col(j) = me.eigenvectors().col(ib[j]);
  MatX Kt = A.transpose() * Kr * A;
  MatX condense;  // y_b = condense * y_a
  if (nb) {
    const MatX Kbb = B.transpose() * Kr * B, Kba = B.transpose() * Kr * A;
    Eigen::SelfAdjointEigenSolver<MatX> kb(Kbb);
    const double kTol = 1e-10 * std::max(Kr.cwiseAbs().maxCoeff(), 1e-300);
    for (int i = 0; i < nb; ++i)
      if (std::abs(kb.eigenvalues()[i]) <= kTol) {
        const VecX x = N * (B * kb.eigenvectors().col(i));
        throw NumericalError("a massless direction without stiffness (no mass, no elastic or constraint "
                             "restraint) involving " + largestCoordinates(model, x) +
                             ": give these nodes mass, stiffness or a constraint");
      }
    condense = -kb.eigenvectors() * kb.eigenvalues().cwiseInverse().asDiagonal() *
               kb.eigenvectors().transpose() * Kba;
    Kt += Kba.transpose() * condense;  // Kaa - Kab Kbb^-1 Kba
  }
  if (na == 0) {  // every massless direction is restrained (checked above): a static structure
    a.noModes = "every one of the " + std::to_string(nb) + " free directions is massless (no element with mass moves "
                "them): the model is in static equilibrium at every instant and has no vibration modes";
    return a;
  }
  Kt = 0.5 * (Kt + Kt.transpose());
  Eigen::SelfAdjointEigenSolver<MatX> es(Kt);
  if (es.info() != Eigen::Success) throw NumericalError("modes: the eigenvalue solver did not converge");
  const VecX w2 = es.eigenvalues();
  const double w2Max = w2.size() ? w2.cwiseAbs().maxCoeff() : 0.0;
  for (int j = 0; j < na; ++j) {
    Mode md;
    md.omega2 = w2[j];
    md.rigid = std::abs(w2[j]) <= 1e-12 * w2Max + 1e-300;
    a.modes.push_back(md);
  }
  // Energies of the lowest `count` elastic and the highest `count` modes.
  std::vector<int> elastic;
  for (int j = 0; j < na; ++j)
    if (!a.modes[j].rigid) elastic.push_back(j);
  const int ne = static_cast<int>(elastic.size());
  for (int k = 0; k < ne; ++k) {
    const int j = elastic[k];
    if (k >= count && k < ne - count) continue;
    const VecX ya = es.eigenvectors().col(j);
    VecX y = A * ya;
    if (nb) y += B * (condense * ya);
    a.modes[j].shape = N * y;
    a.modes[j].parts = energyShares(as, s, p, a.modes[j].shape, w2[j], Kc);
  }
  return a;
}

// ------------------------------------------------------------------------------- reports
namespace {

std::string fmt(const char* f, double x) {
  char b[64];
  std::snprintf(b, sizeof b, f, x);
  return b;
}

std::string sharesText(const Mode& md) {
  std::string s;
  for (size_t k = 0; k < md.parts.size() && k < 3; ++k)
    s += (k ? ", " : "") + md.parts[k].part + " " + fmt("%.0f%%", 100 * md.parts[k].total());
  return s;
}

}  // namespace

void listedModes(const ModalAnalysis& a, int count, std::vector<int>& low, std::vector<int>& high) {
  std::vector<int> elastic;
  for (int j = 0; j < static_cast<int>(a.modes.size()); ++j)
    if (!a.modes[j].rigid) elastic.push_back(j);
  const int ne = static_cast<int>(elastic.size());
  for (int k = 0; k < ne && k < count; ++k) low.push_back(elastic[k]);
  for (int k = std::max(count, ne - count); k < ne; ++k) high.push_back(elastic[k]);
}

namespace {

/// Parts holding most (> 50% together, largest first) of the kinetic energy of the highest modes.
std::vector<std::string> fastParts(const ModalAnalysis& a, const std::vector<int>& high) {
  std::map<std::string, double> kin;
  for (int j : high)
    for (const auto& sh : a.modes[j].parts) kin[sh.part] += sh.kinetic;
  std::vector<std::pair<double, std::string>> v;
  double total = 0.0;
  for (const auto& [k, e] : kin) {
    v.push_back({e, k});
    total += e;
  }
  std::sort(v.rbegin(), v.rend());
  std::vector<std::string> r;
  double acc = 0.0;
  for (const auto& [e, k] : v) {
    if (acc > 0.5 * total || e < 0.05 * total) break;
    r.push_back(k);
    acc += e;
  }
  return r;
}

}  // namespace

std::string modesReport(const ModalAnalysis& a, int count) {
  std::ostringstream os;
  int rigid = 0, unstable = 0;
  double wMax = 0.0;
  for (const auto& md : a.modes) {
    rigid += md.rigid;
    unstable += (!md.rigid && md.omega2 < 0);
    wMax = std::max(wMax, md.omega());
  }
  os << "linearized at the consistent initial state: K = -dQ/dq + sum_i lambda_i Phi_i,qq (initial "
        "multipliers; symmetric part, |K - K^T|/|K| = "
     << fmt("%.1e", a.asymmetry) << "), velocity terms neglected\n"
     << "  n = " << a.n << " coordinates, m = " << a.m << " constraint equations, tangent space "
     << a.tangent << ", massless directions " << a.massless << " (condensed), " << a.modes.size()
     << " modes: " << rigid << " rigid-body (zero to round-off)";
  if (unstable) os << ", " << unstable << " unstable (omega^2 < 0, printed as negative omega)";
  os << "\n";
  if (!a.noModes.empty()) {
    os << "no modes: " << a.noModes << "\n";
    return os.str();
  }
  std::vector<int> low, high;
  listedModes(a, count, low, high);
  auto table = [&](const char* title, const std::vector<int>& idx) {
    os << title << "\n     #   omega [rad/s]    f [Hz]        dt for omega dt = 0.1 [s]   energy by part (strain + kinetic)\n";
    for (int j : idx) {
      const double w = a.modes[j].omega();
      os << fmt("  %4.0f", j + 1) << fmt("   %13.6e", w) << fmt("   %11.4e", w / (2 * M_PI))
         << (w > 0 ? fmt("   %11.3e                 ", kResolveLimit / w) : std::string("   -  (unstable)               "))
         << sharesText(a.modes[j]) << "\n";
    }
  };
  table("lowest elastic modes:", low);
  table("highest modes:", high);
  if (wMax > 0) {
    os << "time steps:\n"
       << (a.massless ? "  maggi_rk4 (explicit RK4) does not run massless parts; with mass it would be stable for dt < 2.785 / omega_max = "
                      : "  maggi_rk4 (explicit RK4) is stable for dt < 2.785 / omega_max = ")
       << fmt("%.3e", kRk4StabilityLimit / wMax) << " s\n"
       << "  implicit schemes (bdf1, trapezoidal, generalized_alpha; IDAS when a mode is excited) resolve a mode when\n"
       << "  omega dt <= 0.1 (column above); a mode with omega dt >> 1 is not resolved: bdf1 and generalized_alpha\n"
       << "  (rho_inf < 1) damp it, trapezoidal keeps it undamped, IDAS cuts its step to follow it\n";
  }
  const std::vector<std::string> fast = fastParts(a, high);
  if (!fast.empty() && !high.empty()) {
    // The highest listed mode not carried (>= 50% of its energy) by the fast parts: the limit without them.
    double next = 0.0;
    for (int j = static_cast<int>(a.modes.size()) - 1; j >= 0 && next == 0.0; --j) {
      if (a.modes[j].rigid) break;
      if (a.modes[j].parts.empty()) break;  // beyond the listed modes: unknown
      double k = 0.0;
      for (const auto& sh : a.modes[j].parts)
        if (std::find(fast.begin(), fast.end(), sh.part) != fast.end()) k += sh.total();
      if (k < 0.5) next = a.modes[j].omega();
    }
    os << "suggestion: the highest modes move mostly ";
    for (size_t k = 0; k < fast.size(); ++k) os << (k ? ", " : "") << fast[k];
    os << ". If their inertia does not matter, make them massless (beam key inertia: none), or rigid if\n"
          "  their deformation does not matter; that removes these modes";
    if (next > 0) os << " (the highest listed mode not carried by them: " << fmt("%.3e", next) << " rad/s)";
    os << ".\n";
  }
  return os.str();
}

std::string modesJson(const ModalAnalysis& a, int count) {
  std::ostringstream os;
  os.precision(10);
  std::vector<int> low, high;
  listedModes(a, count, low, high);
  double wMax = 0.0;
  int rigid = 0;
  for (const auto& md : a.modes) {
    wMax = std::max(wMax, md.omega());
    rigid += md.rigid;
  }
  os << "{\n  \"n\": " << a.n << ", \"m\": " << a.m << ", \"tangent\": " << a.tangent
     << ", \"massless_directions\": " << a.massless << ", \"rigid_modes\": " << rigid
     << ", \"asymmetry\": " << a.asymmetry << ",\n";
  if (!a.noModes.empty()) os << "  \"no_modes\": \"" << a.noModes << "\",\n";
  os << "  \"omega_max\": " << wMax
     << ", \"maggi_rk4_dt_max\": " << (wMax > 0 ? kRk4StabilityLimit / wMax : 0.0) << ",\n";
  auto list = [&](const char* key, const std::vector<int>& idx, bool last) {
    os << "  \"" << key << "\": [";
    for (size_t i = 0; i < idx.size(); ++i) {
      const Mode& md = a.modes[idx[i]];
      os << (i ? ",\n    " : "\n    ") << "{\"index\": " << idx[i] + 1 << ", \"omega\": " << md.omega()
         << ", \"hz\": " << md.omega() / (2 * M_PI) << ", \"dt_resolve\": "
         << (md.omega() > 0 ? kResolveLimit / md.omega() : 0.0) << ", \"parts\": [";
      for (size_t k = 0; k < md.parts.size() && k < 3; ++k)
        os << (k ? ", " : "") << "{\"part\": \"" << md.parts[k].part << "\", \"strain\": " << md.parts[k].strain
           << ", \"kinetic\": " << md.parts[k].kinetic << "}";
      os << "]}";
    }
    os << "\n  ]" << (last ? "\n" : ",\n");
  };
  list("lowest", low, false);
  list("highest", high, true);
  os << "}\n";
  return os.str();
}

}  // namespace flexsens
