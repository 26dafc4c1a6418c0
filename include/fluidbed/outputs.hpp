// The outputs of a run as a list. Every output of a run is one object that holds its own columns, values, files,
// summary entries and part of the checkpoint; the run registers each once (src/app/outputs.cpp, SimulationAddOutputs)
// and calls only the list (OutputList*), which calls them in that order. The list objects: the guards' report (the
// "status" entries that lead summary.json, and the diagnostic guard_failure.h5/.xmf of a run a guard stopped), the
// run's own summary entries, the monitor.csv columns of the particles, the gas and the coupling, the tracked particles
// (track.csv), the final tables (particles.csv, fluid_cells.csv), the gas probes, the time averages, the snapshot
// series, the checkpoints (the schedule, the file with the run's state and every output's part, the restart), the
// scene's entries (scene model, unused options) and summary.json (every output's entries). monitor.csv itself, the row
// of every output's columns, is written by the run on its -monitor_dt schedule (fluidbed/io.hpp). An output sees the
// run through a RunView, the narrow part of it that outputs read, so that the io and analysis modules that implement
// outputs do not depend on the application (fluidbed/simulation.hpp); the application's own outputs (src/app) may
// hold the Simulation. A new analysis is one file (a class derived from Output and its creation function, of the form
// OutputCreateFn, declared in its module's header) and one OutputListCreate line in SimulationAddOutputs.
#pragma once

#include <petscviewer.h>

#include <memory>
#include <string>
#include <vector>

#include "fluidbed/domain.hpp"
#include "fluidbed/files.hpp"
#include "fluidbed/grids.hpp"
#include "fluidbed/particles.hpp"

namespace fluidbed {

struct Fluid;

// What an output may read of the run: built by the application before each call (the clock moves between calls),
// never kept by an output.
struct RunView {
  MPI_Comm             comm;
  const Domain        &domain;
  const Grids         &grids;
  const ParticleProps &props;      // the particles' properties (the defaults when the particles are off)
  DM                   swarm;      // the particles, NULL when they are off
  Fluid               *fluid;      // the gas, NULL when it is off
  const char          *output_dir; // -output_dir
  const char          *restart;    // -restart: the checkpoint this run continues from, "" for a fresh run
  PetscInt64           step;
  PetscReal            time;               // s
  PetscReal            dt;                 // the step that reached time: the DEM step with particles, else the last gas step (s)
  PetscBool            last = PETSC_FALSE; // at Step: the run's last step (a checkpoint is due there whatever its schedule)
};

// One column of monitor.csv: its name in the header and the printf format of its values.
struct MonitorColumn {
  std::string name;
  const char *format = "%.12e"; // of a double; NULL: a count, printed as a whole number
};

// One output of a run. Every method does nothing unless the output overrides it, so that an output implements only
// what it has. Options are read when the output is created (a creation function of its module, which gives no
// output when it is off).
class Output {
public:
  virtual ~Output() = default;
  // Its name in messages.
  virtual const char *Name() const = 0;
  // Its columns of monitor.csv, after step and time; fixed once it exists (the header is written from them).
  virtual void Columns(std::vector<MonitorColumn> *columns) const;
  // Appends the values of those columns, in their order, for the row written at run.time.
  virtual PetscErrorCode Values(const RunView &run, std::vector<PetscReal> *values);
  // Once the run's state is set (read from the checkpoint on a restart) and the output directory cleared, before
  // the first Step: opens its files (a restart continues them after the checkpoint's step, run.step).
  virtual PetscErrorCode Start(const RunView &run);
  // At every output step (a fresh run's initial state, then after every step that passed the guards): what is due at
  // run.time (a sample, a row, a file). In registration order, so that the checkpoint, registered after every output
  // with a Step, holds what they wrote.
  virtual PetscErrorCode Step(const RunView &run);
  // At the end of a run that no guard stopped: its final files.
  virtual PetscErrorCode Finalize(const RunView &run);
  // At the end of a run a guard stopped, instead of Finalize: what it writes of the state that failed (the
  // diagnostic snapshot).
  virtual PetscErrorCode Stopped(const RunView &run);
  // At the end of every run, stopped or not, after Finalize or Stopped and once the run's clocks are read: the files
  // made of every output's entries (summary.json).
  virtual PetscErrorCode End(const RunView &run);
  // Its entries of summary.json (at the end of every run, stopped or not).
  virtual PetscErrorCode AddSummary(const RunView &run, JsonWriter *json);
  // Its part of a checkpoint, and reading it back on a restart (the run's own state is read first).
  virtual PetscErrorCode CheckpointWrite(const RunView &run, PetscViewer viewer);
  virtual PetscErrorCode CheckpointRead(const RunView &run, PetscViewer viewer);
  // On a restart (run.restart), once every output exists and before the run writes: the output that writes the
  // checkpoints reads run.restart, the run's own state and then every output's CheckpointRead; the others have
  // nothing to do here.
  virtual PetscErrorCode Restart(const RunView &run);
  // On a restart, once the checkpoint is read and before the run writes: removes the files the continued run wrote
  // after its checkpoint.
  virtual PetscErrorCode RemoveStale(const RunView &run);
  // Releases its PETSc objects (checked, which a destructor cannot be); the list then deletes it.
  virtual PetscErrorCode Destroy();
};

// The outputs of a run in registration order: the order of their monitor.csv columns, summary.json entries and
// calls.
struct OutputList {
  std::vector<std::unique_ptr<Output>> outputs;
};

// Appends an output; NULL (an output that is off) adds nothing.
PetscErrorCode OutputListAdd(OutputList *list, std::unique_ptr<Output> output);
// The creation function of an output that reads its options and sees the run: *output NULL when it is off.
typedef PetscErrorCode (*OutputCreateFn)(const RunView &run, std::unique_ptr<Output> *output);
// Creates an output with create and appends it (nothing when it is off); made, when given: the output (NULL when
// off), for a caller that asks it about itself.
PetscErrorCode OutputListCreate(OutputList *list, const RunView &run, OutputCreateFn create, const Output **made = nullptr);
// The columns of every output, in order.
void OutputListColumns(const OutputList &list, std::vector<MonitorColumn> *columns);
// The values of a monitor.csv row (collective); an output that gives other than one value a column is an error.
PetscErrorCode OutputListValues(const OutputList &list, const RunView &run, std::vector<PetscReal> *values);
// Output::Start, Step, Finalize, Stopped, End, AddSummary, CheckpointWrite, CheckpointRead, Restart and RemoveStale
// of every output, in order.
PetscErrorCode OutputListStart(const OutputList &list, const RunView &run);
PetscErrorCode OutputListStep(const OutputList &list, const RunView &run);
PetscErrorCode OutputListFinalize(const OutputList &list, const RunView &run);
PetscErrorCode OutputListStopped(const OutputList &list, const RunView &run);
PetscErrorCode OutputListEnd(const OutputList &list, const RunView &run);
PetscErrorCode OutputListAddSummary(const OutputList &list, const RunView &run, JsonWriter *json);
PetscErrorCode OutputListCheckpointWrite(const OutputList &list, const RunView &run, PetscViewer viewer);
PetscErrorCode OutputListCheckpointRead(const OutputList &list, const RunView &run, PetscViewer viewer);
PetscErrorCode OutputListRestart(const OutputList &list, const RunView &run);
PetscErrorCode OutputListRemoveStale(const OutputList &list, const RunView &run);
// Destroys every output and empties the list.
PetscErrorCode OutputListDestroy(OutputList *list);

} // namespace fluidbed
