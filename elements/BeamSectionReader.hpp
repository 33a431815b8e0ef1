// Scene reading of a beam's material and cross-section, shared by the beam kinds
// (beam, ancf_cable): keys E, density and section {side} or {area, inertia}.
#pragma once

#include <memory>
#include <string>

#include "elements/Beam.hpp"
#include "scene/YamlReader.hpp"

namespace flexsens {

/// `el.E`, `el.density`, `el.section`: {side} (square) or {area, inertia}; every entry
/// bindable as a parameter.
std::shared_ptr<BeamSection> readBeamSection(const YamlReader& r, const YAML::Node& el, const std::string& path);

/// `el.rest_shape`: initial (default) or straight; true for straight. `meaning` says in the
/// error what the two choices mean for this kind.
bool readStraightRest(const YamlReader& r, const YAML::Node& el, const std::string& path, const std::string& meaning);

}  // namespace flexsens
