#include "scene/KindTable.hpp"

namespace flexsens {

std::string KindTable::names() const {
  std::string out;
  size_t i = 0;
  for (const auto& [name, fn] : readers) {
    out += (i == 0 ? "" : (i + 1 == readers.size() ? " or " : ", ")) + name;
    ++i;
  }
  return out;
}

// An explicit table rather than self-registering statics: the core is a static library, and
// the linker drops object files nothing references, registrations included.
const KindTable& elementKinds() {
  static const KindTable t{{
      {"ancf_beam", readAncfBeam},
      {"ancf_cable", readAncfCable},
      {"beam", readBeam},
      {"planar_rigid_body", readPlanarRigidBody},
      {"point_force", readPointForce},
      {"point_torque", readPointTorque},
      {"rigid_bar", readRigidBar},
      {"rigid_body", readRigidBody},
      {"rotational_spring_damper", readRotationalSpring},
      {"shell", readShell},
      {"solid", readSolid},
      {"spring_damper", readSpringDamper},
  }};
  return t;
}

const KindTable& constraintKinds() {
  static const KindTable t{{
      {"distance", readDistance},
      {"fixed", readFixed},
      {"motor", readMotor},
      {"perpendicular", readPerpendicular},
      {"point_on_plane", readPointOnPlane},
      {"prescribed_coordinate", readPrescribedCoordinate},
      {"prescribed_distance", readPrescribedDistance},
      {"spherical", readSpherical},
      {"hinge", readHinge},
      {"weld", readWeld},
  }};
  return t;
}

}  // namespace flexsens
