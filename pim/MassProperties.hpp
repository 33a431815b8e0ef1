// Mass properties of a body's F-R twin (its rigid model): the mass, centre of mass and inertia
// the body's own constant mass matrix M gives under rigid motions of its nodes, so that the
// rigid model of a meshed body carries the mesh's integrals, not guessed values:
//   m = u_x^T M u_x (u_x: unit translation), m c = first moments from u_a^T M X,
//   inertia about c from the rigid rotation fields w_a,i = e_a x (X_i - c): I_ab = w_a^T M w_b
// (planar: the polar moment w^T M w, w_i = R90 (X_i - c)). For consistent isoparametric mass
// these are exactly int rho dV, int rho X dV and int rho (|r|^2 I - r r^T) dV of the mesh.
//
// Units: m [kg], c [m], inertia [kg m^2].
#pragma once

#include <vector>

#include "core/Model.hpp"

namespace flexsens {

struct MassProperties {
  double mass = 0.0;
  VecX centre;   ///< dim entries [m]
  MatX inertia;  ///< 3x3 about the centre (spatial) or 1x1 polar (planar) [kg m^2]
};

/// From the elements whose nodes all belong to `nodes` (the body's), at their initial
/// positions and parameters p.
MassProperties rigidMassProperties(const Model& m, const std::vector<int>& nodes, const VecX& p);

}  // namespace flexsens
