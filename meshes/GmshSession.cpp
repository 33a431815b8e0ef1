// Gmsh session guard; see GmshSession.hpp.
#include "meshes/GmshSession.hpp"

#include <gmsh.h>

#include <cmath>
#include <limits>

namespace flexsens {

/// An API call on an uninitialized Gmsh returns without touching its outputs (never
/// initialized in this process) or throws std::string("Gmsh has not been initialized")
/// (after a finalize), printing nothing either way; so an option read into a NaN probes it.
bool gmshInitialized() {
  double v = std::numeric_limits<double>::quiet_NaN();
  try {
    gmsh::option::getNumber("General.Terminal", v);
  } catch (...) {
    return false;
  }
  return !std::isnan(v);
}

GmshSession::GmshSession() {
  if (gmshInitialized()) gmsh::finalize();  // the child's copy of a parent's session
  gmsh::initialize(0, nullptr, /*readConfigFiles=*/false);
  gmsh::option::setNumber("General.Terminal", 0);
}

GmshSession::~GmshSession() {
  try {
    gmsh::finalize();
  } catch (...) {
  }
}

}  // namespace flexsens
