// The scene's kinds: a table from an element's or constraint's `type` to the function that
// reads it. Each reader lives beside its element (elements/*Reader.cpp) or constraint
// (constraints/*Reader.cpp); a new kind adds its reader file and one line to KindTable.cpp.
#pragma once

#include <map>
#include <string>

#include "scene/SceneContext.hpp"

namespace flexsens {

/// Reads one list item of type `type` at key path `path` (e.g. "elements[3]"), named `name`,
/// and adds what it builds to ctx.m (elements, constraints) and to ctx's name tables.
using KindReader = void (*)(SceneContext& ctx, const YAML::Node& item, const std::string& path,
                            const std::string& name);

struct KindTable {
  std::map<std::string, KindReader> readers;
  /// "a, b or c": the types, for "unknown type" messages.
  std::string names() const;
};

const KindTable& elementKinds();     ///< `elements:` item types
const KindTable& constraintKinds();  ///< `constraints:` item types

// The readers (one per kind; defined beside their element or constraint).
void readRigidBar(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
void readSpringDamper(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
void readPointForce(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
void readPointTorque(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
void readPlanarRigidBody(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
void readAncfCable(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
void readAncfBeam(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
/// After the elements: the initial slope rates of free ANCF slopes from the nodes' velocities
/// (elements/AncfCableReader.cpp).
void deriveSlopeRates(SceneContext& ctx);
void readBeam(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
void readRigidBody(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
void readSolid(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
void readShell(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
void readRotationalSpring(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
void readDistance(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
void readFixed(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
void readSpherical(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
void readPerpendicular(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
void readPrescribedCoordinate(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
void readPrescribedDistance(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
void readMotor(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
void readPointOnPlane(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
void readWeld(SceneContext&, const YAML::Node&, const std::string&, const std::string&);
void readHinge(SceneContext&, const YAML::Node&, const std::string&, const std::string&);

}  // namespace flexsens
