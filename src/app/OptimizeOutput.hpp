// The files of `flexsens optimize` (app/Optimize.hpp) and the optimized scene's text.
#pragma once

#include <string>

#include "app/Optimize.hpp"
#include "app/PlotScript.hpp"
#include "output/RunDirectory.hpp"
#include "scene/Scene.hpp"

namespace flexsens {

/// More variables than this: history.csv holds none, history_variables.csv holds them all.
constexpr size_t kHistoryVariableColumns = 20;

/// history.csv (history_variables.csv), optimize.json, optimum.csv and, when an evaluation
/// completed, optimized.yaml into the staging folder of `dir` (result.sceneNote: what
/// optimized.yaml does not hold).
void writeOptimizeOutputs(RunDirectory& dir, const Scene& scene, OptimizeResult& result);

/// The scene's text with the values of the named whole-body parameters (name -> value) in
/// place of the scene's: each parameter's property scalar (an element's or constraint's key,
/// found by the parameter's `of` and `property`, or a gravity component) is replaced in the
/// text, so comments and layout stay. `missed` lists the parameters whose value is not
/// written out in the text (a default the scene does not state).
std::string optimizedSceneText(const std::string& text, const Scene& scene,
                               const std::vector<std::pair<int, double>>& values, std::vector<std::string>& missed);

}  // namespace flexsens
