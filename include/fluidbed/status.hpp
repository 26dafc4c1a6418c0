// How a run ends: the process exit status per failure class, so that scripts and studies can classify a run
// without parsing its text (summary.json carries the same as "status" and "exit_code"; docs/reliability.md).
#pragma once

namespace fluidbed {

enum ExitStatus {
  EXIT_OK       = 0,
  EXIT_INTERNAL = 1, // an error of the code or a library (a traceback is printed)
  EXIT_INPUT    = 2, // bad options or input files: one line naming the option, the value and what is allowed
  EXIT_OUTPUT   = 3, // a write failed (full disk, unwritable path): what was complete before stays intact
  // A signal (SIGTERM, SIGINT, or SIGUSR1, which mpiexec passes on to the ranks) ended the run early, at the next
  // step all ranks agree on: the state reached was written as a checkpoint (with -checkpoint_interval set) and as the
  // final files, so the run continues from there with -restart.
  EXIT_INTERRUPTED = 4,
  // Run-time guards (src/guards): the state went wrong and the run stopped.
  EXIT_GUARD_NAN           = 10, // NaN or inf in a particle or gas field
  EXIT_GUARD_ESCAPE        = 11, // a particle left through a wall, or was lost in migration
  EXIT_GUARD_PRESSURE      = 12, // the pressure KSP did not converge
  EXIT_GUARD_OVERLAP       = 13, // the largest overlap exceeded -guard_overlap
  EXIT_GUARD_DISPLACEMENT  = 14, // a particle moved more than -guard_displacement diameters in one step
  EXIT_GUARD_ENERGY        = 15, // the mechanical energy grew in a scene without energy input
  EXIT_GUARD_VOID_FRACTION = 16, // void fraction outside (0, 1] or held at the floor in too many cells
  EXIT_GUARD_COURANT       = 17, // the gas Courant number stayed above its limit
};

} // namespace fluidbed
