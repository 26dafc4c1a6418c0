// What a scene models, and why: one table printed at start-up (particles, gas, dimension, rotation, contact law,
// drag law, grids, gas step, pressure solver, guards, averaging, output, and what is off: heat, periodicity, the
// outlet), each row with the option that set it or "default", and warnings where the scene asks for more than it can
// use or less than it needs (a deep gas grid on a one-particle-deep bed, small single-grid cells, few particles per
// coupling cell, a DEM step far below what the contacts need, a gas grid finer than its slits need, averaging that
// never starts). The table goes to summary.json as "model", the warnings as "model_warnings", so that studies can
// group runs by what was active. The rows are asked of the modules through their public headers; docs/stability.md
// ("What a scene models") lists the rows, the warnings and their thresholds.
#pragma once

#include <petscviewer.h>

#include <string>
#include <vector>

#include "fluidbed/io.hpp"
#include "fluidbed/option_report.hpp"

namespace fluidbed {

struct Simulation;

struct SceneModelRow {
  std::string feature; // "particles", "gas", ...
  std::string state;   // what is active, or "off" and why not
  std::string why;     // the options that set it as given, or "default"
};

struct SceneModel {
  std::vector<SceneModelRow> rows;           // the printed table, in order
  JsonWriter                 json;           // summary.json "model": the same rows as typed values
  std::vector<std::string>   warnings;       // summary.json "model_warnings", each printed once as "WARNING: ..."
  UnusedOptions              without_effect; // options a warning found without effect, for summary.json "unused_options"
};

// Builds the table and the warnings from the set-up scene (collective: the particle count is reduced). Call at the end
// of the set-up, when every module exists and has read its options; it reads the options database only as given
// (PetscOptionsGetAll), so that it marks no option as used.
PetscErrorCode SceneModelBuild(Simulation *sim, SceneModel *model);
// Prints the table, then one "WARNING: ..." line per warning (rank 0 of the viewer).
PetscErrorCode SceneModelView(const SceneModel &model, PetscViewer viewer);
// summary.json: "model" and "model_warnings".
void SceneModelAddSummary(const SceneModel &model, JsonWriter *json);

} // namespace fluidbed
