// Shared check of static sensitivities against central differences of whole static solutions.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>

#include "core/Assembler.hpp"
#include "integrators/Static.hpp"

namespace flexsens::test {

/// dq/dp (qp, one column per parameter) at the equilibrium q of parameters p against central
/// differences of static solutions at p_k +- h, h = 1e-4 p_k (truncation ~1e-8 relative), each
/// solved in one load step from q to 1e-14: the largest error relative to |FD|_inf below bound.
inline void expectStaticSensitivitiesMatchCentralDifferences(const Assembler& as, const Model& m, const VecX& p,
                                                             const VecX& q, const MatX& qp, double bound) {
  StaticSettings one;
  one.steps = 1;
  one.tol = 1e-14;
  for (int k = 0; k < static_cast<int>(p.size()); ++k) {
    const double h = 1e-4 * p[k];
    VecX pp = p, pm = p;
    pp[k] += h;
    pm[k] -= h;
    const VecX fd = (solveStatic(as, pp, q, one) - solveStatic(as, pm, q, one)) / (2 * h);
    const double err = (qp.col(k) - fd).lpNorm<Eigen::Infinity>() / fd.lpNorm<Eigen::Infinity>();
    std::printf("  d q / d %s: |FD| %.3e, rel. error %.2e\n", m.parameters[k].name.c_str(), fd.lpNorm<Eigen::Infinity>(), err);
    EXPECT_LT(err, bound) << m.parameters[k].name;
  }
}

}  // namespace flexsens::test
