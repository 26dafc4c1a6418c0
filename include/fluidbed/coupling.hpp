// Gas-particle coupling (seed chapter 2 eq. 2.1, 2.18-2.21, and chapter 5's two-grid mapping eq. 5.1-5.5).
//
// Two grids (-couple_grid two, the default): the solid volume and the drag reaction are summed on the coarse
// particle grid, the void fraction eps = 1 - solid volume / cell volume of each particle cell is copied to all
// of its fluid cells (eq. 5.2-5.5), the gas velocity each particle sees is the average of the cell velocities of
// its particle cell's fluid cells (seed step 2), and the particle cell's summed drag reaction is spread over its
// fluid cells by volume (eq. 5.1). With -pgrid_ratio 1 this is the conventional single grid; -couple_grid single
// runs the conventional method directly on the fluid grid (an independent path, tested against ratio 1).
//
// Model B (eq. 2.1, 2.20): particles feel their weight reduced by buoyancy, (rho_p - rho_g) V_p g, plus drag;
// the gas gets minus the summed drag and rho_g g. The drag law is chosen by name (-drag_model).
//
// The drag is linearised once per gas step (every -couple_substeps DEM steps): at the last DEM step before it
// each particle gets a = V_p K (K from eq. 2.11-2.17 at its cell's eps and its current slip) and b = a v_p, and
// each coupling cell sums B = sum a, M = sum b and its solid volume. The gas then advances with the drag
// M - B u implicit in u (FluidGetDragCoefficient), which stays stable when the gas-particle relaxation time
// eps rho_g / beta is far shorter than the gas step, as in a packed bed. After the gas step the cell velocity u is
// averaged over each coupling cell and every particle feels F = a u - b until the next gas step: summed over a
// cell the particles get B u - M, exactly minus what the gas got.
// Halos of these fields go through DMDA local vectors (a particle may sit up to half a Verlet skin outside its
// rank's cells between neighbour-list rebuilds).
#pragma once

#include <petscdmda.h>

#include <vector>

#include "fluidbed/fluid.hpp"
#include "fluidbed/grids.hpp"
#include "fluidbed/particle_motion.hpp"

namespace fluidbed {

struct Coupling;

// Totals for monitor.csv: drag on the particles and its reaction on the gas (they cancel to round-off), and the
// void fraction range.
struct CouplingStats {
  PetscReal  drag_particles[3]{0, 0, 0}; // sum of the drag forces on the particles in the last DEM step, N
  PetscReal  drag_gas[3]{0, 0, 0};       // the drag the gas received in the last DEM step (mean over its gas steps), N
  PetscReal  eps_min = 1, eps_max = 1;   // over coupling cells, last DEM step
  PetscInt64 clamped     = 0;            // cells whose eps hit -couple_eps_min in the last DEM step
  PetscReal  eps_raw_min = 1;            // the least 1 - solid volume / cell volume before the floor (< 0: overfilled)
  PetscInt64 cells       = 0;            // coupling cells in all
};

// Reads -couple_substeps, -couple_gas_substeps, -couple_grid, -couple_eps_min and -drag_model; installs the particles' external-force hook
// and sets the buoyancy factor.
PetscErrorCode CouplingCreate(MPI_Comm comm, const Domain &domain, const Grids &grids, ParticleSystem *particles, Fluid *fluid,
                              PhaseLog *log, Coupling **coupling);
// The void fraction of the initial particles for the first gas step, and the gas velocity per coupling cell.
PetscErrorCode CouplingSetUp(Coupling *coupling);
PetscErrorCode CouplingBeforeFluidStep(Coupling *coupling);
// After gas step k of the n of one DEM step (n = -couple_gas_substeps, else 1): the gas velocity per coupling cell,
// averaged over the n steps once the last is taken.
PetscErrorCode       CouplingAfterFluidStep(Coupling *coupling, PetscInt k, PetscInt n);
const CouplingStats &CouplingGetStats(const Coupling *coupling);
PetscErrorCode       CouplingView(const Coupling *coupling, PetscViewer viewer);
// For the void-fraction guard: this rank's fluid cells (natural indices) that lie in coupling cells held at the floor,
// and (collective) the first such coupling cell in natural ordering (-1 if none) and its size in particle diameters.
PetscErrorCode CouplingFloorCells(Coupling *coupling, std::vector<PetscInt64> *fluid_cells, PetscInt first[3]);
// The coupling cells' size (m) and the fluid cells each holds per direction (1 for the single grid).
PetscErrorCode CouplingCellSize(const Coupling *coupling, PetscReal h[3], PetscInt ratio[3]);
// The drag law's name (-drag_model) and whether the coupling runs on the particle grid (-couple_grid two).
const char *CouplingDragName(const Coupling *coupling);
PetscBool   CouplingOnParticleGrid(const Coupling *coupling);
// Whether the next step is a gas step: the coupling counts the DEM steps of each gas step (-couple_substeps).
PetscBool CouplingGasStepDue(const Coupling *coupling);
// -couple_substeps: DEM steps per gas step.
PetscInt CouplingSubsteps(const Coupling *coupling);
// -couple_gas_substeps: gas steps per DEM step (1 unless -couple_substeps is 1). Between two DEM steps the gas then
// takes that many steps with the particles' void fraction and drag coefficients of the last DEM step (held, as the
// particles hold the gas velocity between gas steps with -couple_substeps).
PetscInt CouplingGasSubsteps(const Coupling *coupling);
// The coupled gas step (DEM step x -couple_substeps / -couple_gas_substeps; -fluid_dt is an input error with particles)
// and the gas's own explicit limit for its current state, s.
PetscErrorCode CouplingGasStep(Coupling *coupling, PetscReal *dt_gas, PetscReal *dt_max);

// The coupling state a checkpoint needs to continue bit for bit (/coupling: per-cell sums, void fraction, the
// DEM steps left before the next gas step); natural ordering, any number of ranks. Reading a checkpoint whose run had
// other -couple_substeps (the root attribute couple_substeps) keeps the DEM steps already taken of the gas step.
PetscErrorCode CouplingWriteHDF5(Coupling *coupling, PetscViewer viewer);
PetscErrorCode CouplingReadHDF5(Coupling *coupling, PetscViewer viewer);
PetscErrorCode CouplingDestroy(Coupling **coupling);

} // namespace fluidbed
