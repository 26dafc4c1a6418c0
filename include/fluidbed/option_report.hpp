// Options that have no effect in the run: misspelled ones (never read), 3D options in a 2D run, and those the scene's
// model found without effect at start-up (-average_start at or after -t_final, -average_* with averaging off:
// scene_model.hpp). They are listed as warnings at the end of a run (the start-up ones were printed then already) and
// in summary.json ("unused_options").
#pragma once

#include <petscsys.h>

#include <string>
#include <vector>

namespace fluidbed {

struct Simulation;

struct UnusedOption {
  std::string name;            // with the dash: "-dem_kn_typo"
  std::string value;           // as given ("" for an option without a value)
  std::string reason;          // why it has no effect
  bool        printed = false; // warned of at start-up (a model warning, scene_model.hpp): not printed again at the end
};
using UnusedOptions = std::vector<UnusedOption>;

// Collects the options without effect. Call at the end of a run, after every component has read its options and
// before summary.json is written (an option read later would be listed falsely).
PetscErrorCode UnusedOptionsCollect(Simulation *sim, UnusedOptions *list);
// One line per option not printed yet, on rank 0: "WARNING: option -dem_kn_typo 5 was not used (misspelled, or no effect in
// this scene)".
PetscErrorCode UnusedOptionsPrint(MPI_Comm comm, const UnusedOptions &list);

} // namespace fluidbed
