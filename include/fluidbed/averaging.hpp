// Time averages of the bed during a run (seed chapters 3-5): every -average_interval from -average_start, each
// rank bins its own particles into its block of the particle grid (sim->grids.particle.da_cell) and adds the
// snapshot to per-cell sums (kernels::CellAverageSums, a DMDA of kCellAverageSumsDof dof); with the gas on, each
// sample also records the pressure drop across the bed and the height of every inlet jet. At the end (and every
// -average_output_interval) <output_dir>/analysis.h5 and analysis.xmf hold the time-averaged fields, horizontal
// and cross-section profiles, the time series and the whole-bed measures, which also go to summary.json under
// "averages". The accumulators travel in checkpoints, so a restarted run (on any number of ranks) writes the same
// analysis.h5 as the uninterrupted one. The physics is in include/fluidbed/kernels/bed_*.hpp and jet_height.hpp;
// docs/analysis.md has the definitions, the options and the file layout.
#pragma once

#include <petscviewer.h>

namespace fluidbed {

struct Simulation;
struct JsonWriter;
struct BedAverages;

// Reads the -average_* options; *avg is NULL when averaging is off (no -average, no -average_start). Call after
// the grids, the particles and the gas exist, before a restart's checkpoint is read. Every function below accepts
// a NULL object and then does nothing.
PetscErrorCode BedAveragesCreate(Simulation *sim, BedAverages **avg);
// Takes the sample that is due at the simulation's current time (and writes analysis.h5 when
// -average_output_interval is due). Call at every output step, before a checkpoint of that step is written.
PetscErrorCode BedAveragesStep(BedAverages *avg);
// Adds the current state as one sample, due or not.
PetscErrorCode BedAveragesSample(BedAverages *avg);
// Writes <output_dir>/analysis.h5 and analysis.xmf and computes the whole-bed measures for the summary.
PetscErrorCode BedAveragesWrite(BedAverages *avg);
// When the samples start and how often they are taken (-average_start, -average_interval), s.
PetscErrorCode BedAveragesSchedule(const BedAverages *avg, PetscReal *start, PetscReal *interval);
// The "averages" object of summary.json (after BedAveragesWrite).
PetscErrorCode BedAveragesAddSummary(BedAverages *avg, JsonWriter *json);
// Checkpoint group /averages: per-cell sums (natural ordering, any rank count), sample count, weight, schedule and
// the time series so far. Reading a checkpoint without it starts the averages afresh.
PetscErrorCode BedAveragesWriteHDF5(BedAverages *avg, PetscViewer viewer);
PetscErrorCode BedAveragesReadHDF5(BedAverages *avg, PetscViewer viewer);
PetscErrorCode BedAveragesDestroy(BedAverages **avg);

} // namespace fluidbed
