// A scene: the model built from a YAML file plus what to run and what to write.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/Model.hpp"
#include "integrators/Settings.hpp"
#include "integrators/State.hpp"
#include "pim/Pim.hpp"
#include "scene/Objective.hpp"
#include "scene/OptimizeSpec.hpp"

namespace flexsens {

/// A named scalar output: one coordinate component of one node [m] (a slope component [-]), or
/// (angle) the signed angle of elements/JointAngle.hpp on six nodes [rad]; with `rate`
/// (`quantity: velocity`) its time derivative [m/s, 1/s, rad/s]; with `displacement`
/// (`quantity: displacement`, an axis component of a node) the position minus the node's rest
/// position, its position as the scene or mesh gives it [m].
struct OutputSpec {
  std::string name;
  int node = -1;
  int component = 0;
  std::vector<int> angle;  ///< axis from/to, from-vector from/to, to-vector from/to (empty: coordinate)
  bool rate = false;
  bool displacement = false;
  /// Value at state x (positions q, velocities v), and its derivative along dx (a
  /// sensitivity d x/dp: the column d<name>/dp of series.csv).
  double value(const Model& m, const State& x) const;
  double derivative(const Model& m, const State& x, const State& dx) const;
  /// The gradient of the value with respect to q and v at x, times `weight`, added into gq and
  /// gv (derivative(m, x, dx) = gq . dx.q + gv . dx.v): the adjoint's source terms.
  void addGradient(const Model& m, const State& x, double weight, Eigen::Ref<VecX> gq, Eigen::Ref<VecX> gv) const;
};

/// How sensitivities are computed (the speed-versus-accuracy choice).
struct SensitivitySettings {
  std::string method = "dd";       ///< dd | ad | dq | nd
  std::string ndScheme = "central";
  double ndStep = 1e-6;            ///< relative step of nd
};

struct OutputSettings {
  std::string directory;  ///< default: results/<scene file stem>
  bool vtk = true;
  bool plots = true;
};

/// `static:` settings of `flexsens static` (load-stepped equilibrium).
struct StaticSceneSettings {
  bool given = false;  ///< the scene has a `static` key (then `integrator` may be left out)
  int loadSteps = 10;  ///< equal increments of the load factor
  /// `linear: true`: small displacements, K u = f with the stiffness at the rest state and the
  /// constraints linearized there (integrators/Static.hpp, solveLinearStatic).
  bool linear = false;
};

struct Scene {
  std::string file;  ///< path as given
  std::unique_ptr<Model> model;
  IntegratorSettings integrator;
  bool hasIntegrator = true;  ///< false: a static-only scene (`run` refuses it)
  StaticSceneSettings statics;
  SensitivitySettings sensitivity;
  std::vector<OutputSpec> outputs;
  std::vector<ObjectiveSpec> objectives;  ///< `objectives:` (scene/Objective.hpp)
  OptimizeSpec optimize;                  ///< `optimize:` (scene/OptimizeSpec.hpp)
  OutputSettings output;
  std::vector<std::string> caseNames;  ///< all PIM cases the scene defines, in order
  /// Meshed body -> its Physical Points and node groups (name, node count), for `check`.
  std::map<std::string, std::vector<std::pair<std::string, int>>> meshGroups;
  std::unique_ptr<PimCase> pimCase;    ///< the case this model was built for, if any
  /// An input error that only integration needs to raise (a massless direction nothing
  /// restrains, with file:line and key); run, check and modes throw it. Empty: none.
  std::string dynamicsError;
  void requireDynamics() const {
    if (!dynamicsError.empty()) throw InputError(dynamicsError);
  }
};

/// Values for scene parameters by name (a sweep's sample): each quantity bound to the
/// parameter takes the value in place of the scene's, for every case.
using ParameterValues = std::map<std::string, double>;

/// Reads and validates a scene file; throws InputError naming file:line, key and expectation.
/// With caseName, the model is built for that PIM case (its rigid models, its parameters).
/// With values, the named parameters' properties take them (InputError for a name the
/// scene's parameters list does not hold).
Scene readScene(const std::string& path, const std::string& caseName = "", const ParameterValues& values = {});
/// Same, from text (tests); `name` is used in messages as the file name.
Scene readSceneText(const std::string& text, const std::string& name, const std::string& caseName = "",
                    const ParameterValues& values = {});

}  // namespace flexsens
