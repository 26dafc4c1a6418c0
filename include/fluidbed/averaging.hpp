// Time averages of the bed during a run (seed chapters 3-5): every -average_interval from -average_start, each
// rank bins its own particles into its block of the particle grid (grids.particle.da_cell) and adds the
// snapshot to per-cell sums (kernels::CellAverageSums, a DMDA of kCellAverageSumsDof dof); with the gas on, each
// sample also records the pressure drop across the bed and the height of every inlet jet. At the end (and every
// -average_output_interval) <output_dir>/analysis.h5 and analysis.xmf hold the time-averaged fields, horizontal
// and cross-section profiles, the time series and the whole-bed measures, which also go to summary.json under
// "averages". The accumulators travel in checkpoints, so a restarted run (on any number of ranks) writes the same
// analysis.h5 as the uninterrupted one. The physics is in include/fluidbed/kernels/bed_*.hpp and jet_height.hpp;
// docs/analysis.md has the definitions, the options and the file layout.
#pragma once

#include <memory>

#include "fluidbed/outputs.hpp"

namespace fluidbed {

// Reads the -average_* options and, when averaging is on (-average, or -average_start), creates the averages as an
// output of the run (*out NULL when it is off): it samples at the output steps that are due (-average_start,
// -average_interval; before a checkpoint of that step is written, which then holds the sample) and writes
// analysis.h5 every -average_output_interval, writes <output_dir>/analysis.h5 and analysis.xmf at the end, adds
// "averages" to summary.json (the whole-bed measures), and keeps checkpoint group /averages: per-cell sums
// (natural ordering, any rank count), sample count, weight, schedule and the time series so far; reading a
// checkpoint without it starts the averages afresh. Create it once the grids, the particles and the gas exist,
// before a restart's checkpoint is read.
PetscErrorCode BedAveragesCreate(const RunView &run, std::unique_ptr<Output> *out);
// When the samples of the averages output (NULL: averaging off, zeros) start and how often they are taken
// (-average_start, -average_interval), s.
PetscErrorCode BedAveragesSchedule(const Output *averages, PetscReal *start, PetscReal *interval);

} // namespace fluidbed
