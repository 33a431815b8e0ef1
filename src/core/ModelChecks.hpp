// Checks of a built model that no single element or constraint can make, and the bounds on
// the input that keep a model inside what double precision and the solvers handle.
#pragma once

#include <vector>

#include "core/Model.hpp"

namespace flexsens {

/// |position| and |velocity| components of a node [m, m/s]: mechanisms here are metres in
/// size; beyond 1e6 the round-off of q (1e-10 m at 1e6 m) swamps the Newton tolerances, and
/// 1e308 overflows the first product.
inline constexpr double kMaxCoordinate = 1e6;
inline constexpr double kMaxVelocity = 1e6;

/// Free nodes that no element and no constraint touches: no mass, no force, no constraint
/// row, so every integrator's matrix is singular there (exit 2 at the first step). Massless
/// nodes that springs or constraints carry (quasi-static, e.g. a spring end on a plane) are
/// not reported: the kernel tests use them, and issue 14 makes massless parts a feature.
std::vector<int> nodesActedOnByNothing(const Model& m);

}  // namespace flexsens

namespace flexsens {

/// A direction of the free coordinates that carries no mass and that no stiffness, damping or
/// constraint restrains at the initial state: every integrator's matrix
/// (M/(beta h^2) + C gamma/(beta h) + K, Phi_q^T; Phi_q, 0) has it as a null vector for every
/// step h, so a run can only fail on it. Empty when there is none.
struct UnrestrainedMassless {
  std::vector<int> nodes;  ///< the nodes the direction moves most, largest first
  std::string direction;   ///< the direction in words, e.g. "n2.y" or "0.71 n2.x + 0.71 n3.x"
};
/// Dense rank-revealing QR on the columns of the massless coordinates; models too large for it
/// (rows x massless columns > 4e7) are not checked (nullopt-like: empty result).
UnrestrainedMassless unrestrainedMasslessDirection(const Model& m);

}  // namespace flexsens
