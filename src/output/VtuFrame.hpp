// One output frame as a VTK unstructured grid (ResultWriter writes it as frame_NNNNN.vtu):
//   point data  position, displacement, velocity and their d/dp; on ANCF models the slope
//               r' = dr/ds, its rate and d/dp;
//   cells       one line per two-node element, a rigid body's frame lines, shell triangles,
//               meshed-body cells of their own type; cell data element_kind and element_id;
//   stresses    on shell triangles and meshed bodies: Green-Lagrange strain, PK2 and Cauchy
//               stress, von Mises, and their d/dp (NaN on the other cells).
#pragma once

#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include <string>
#include <vector>

#include "core/Model.hpp"
#include "integrators/State.hpp"

namespace flexsens {

/// The grid of state s of model m (arrays in the order ParaView's readers list them).
vtkSmartPointer<vtkUnstructuredGrid> frameGrid(const Model& m, const StateWithSens& s);

/// Positions (derivative = false: ground nodes at their fixed position) or their parameter
/// derivatives (derivative = true: ground nodes 0) of a node list, dim values per node.
VecX gatherNodeCoordinates(const Model& m, const std::vector<int>& nodes, const VecX& q, bool derivative);

/// How writing a .vtu went: ok, else the errno seen (0: none) and VTK's error code.
struct VtuWriteStatus {
  bool ok = false;
  int err = 0;
  unsigned long code = 0;
};
/// Writes grid to path (appended raw data). VTK reports a failed write in its return value, or
/// only in its error code (a full disk can leave a truncated file and success): both are
/// checked, and the file itself (it must exist and not be empty).
VtuWriteStatus writeVtuFile(vtkUnstructuredGrid* grid, const std::string& path);

}  // namespace flexsens
