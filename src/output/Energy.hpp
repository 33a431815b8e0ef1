// Mechanical energy of a state: kinetic T = 1/2 v^T M v with the constant mass matrix, and
// potential V (gravity, elastic, dead loads: the elements' potential()) [J]. Used for the
// energy columns of series.csv and the run's energy audit.
#pragma once

#include "core/Assembler.hpp"

namespace flexsens {

struct Energy {
  double kinetic = 0.0;    ///< [J]
  double potential = 0.0;  ///< [J], zero where the elements put it (gravity: at the origin)
  double total() const { return kinetic + potential; }
};

class EnergyMeter {
 public:
  /// M(p) is assembled once: masses do not depend on q.
  EnergyMeter(const Assembler& as, const VecX& p) : as_(as), p_(p), M_(as.mass(p)) {}
  Energy at(const VecX& q, const VecX& v) const {
    return {0.5 * v.dot(M_ * v), as_.potentialEnergy(q, p_)};
  }

 private:
  const Assembler& as_;
  VecX p_;
  SpMat M_;
};

}  // namespace flexsens
