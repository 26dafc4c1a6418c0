// The two aligned grids of the two-grid method (seed chapter 5).
//
// The fine fluid grid and the coarse particle grid are cell-centred DMDAs with the same process grid; each coarse
// cell holds a whole block of r_x x r_y x r_z fine cells, owned by the same rank (ownership ranges of the fine
// grid are r times those of the coarse grid). The DMSwarm needs a vertex DMDA as its cell DM (n + 1 nodes make n
// cells, and each rank owns the cell to the left of its first node), so a third DMDA with matching vertex
// ownership is kept for the swarm. Ratio 1 is the conventional single grid.
#pragma once

#include <petscdmda.h>

#include <functional>
#include <vector>

#include "fluidbed/domain.hpp"
#include "fluidbed/kernels/cell_grid.hpp"

namespace fluidbed {

struct FluidGrid {
  DM                    da = nullptr; // cell-centred, dof 1, star stencil of width 1: the layout of every fluid field
  PetscInt              n[3]{1, 1, 1};
  PetscReal             h[3]{1, 1, 1};
  std::vector<PetscInt> own[3]; // cells owned by each process along each direction
};

// How the process grid is chosen when -pgrid_processors is not given (-pgrid_layout).
enum GridLayout { GRID_LAYOUT_HORIZONTAL, GRID_LAYOUT_PETSC, GRID_LAYOUT_PARTICLES };

struct ParticleGrid {
  DM                    da_cell   = nullptr; // cell-centred coarse DMDA for per-particle-cell fields
  DM                    da_vertex = nullptr; // vertex DMDA used as the swarm's cell DM
  PetscInt              n[3]{1, 1, 1};
  PetscReal             h[3]{1, 1, 1};
  PetscInt              ratio[3]{1, 1, 1};
  PetscInt              procs[3]{1, 1, 1}; // process grid
  PetscInt              proc[3]{0, 0, 0};  // this rank's place in it
  GridLayout            layout = GRID_LAYOUT_HORIZONTAL;
  std::vector<PetscInt> start[3]; // first cell of each process along each direction; start[a][procs[a]] = n[a]
  PetscInt              cell_lo[3]{0, 0, 0}, cell_hi[3]{1, 1, 1}; // cells owned by this rank, [lo, hi)
  PetscReal             sub_lo[3]{0, 0, 0}, sub_hi[3]{0, 0, 0};   // the rank's subdomain in space

  // MPI rank of the process at process-grid coordinates p (DMDA ordering: x fastest).
  PetscMPIInt RankAt(const PetscInt p[3]) const { return (PetscMPIInt)(p[0] + procs[0] * (p[1] + procs[1] * p[2])); }
};

struct Grids {
  FluidGrid    fluid;
  ParticleGrid particle;
};

// Reads -grid_nx/ny/nz, -pgrid_ratio, -pgrid_cell_diameters, -pgrid_processors, -pgrid_layout and creates the DMDAs.
// d_max is the largest particle diameter (m). points, for -pgrid_layout particles: gives the initial particles'
// centres (x, y, z each, the same on every rank) and whether they are known before insertion; called only for that
// layout. gas: whether the gas is on (the work of a fluid cell, -pgrid_cell_weight, is 0 without it).
typedef std::function<PetscErrorCode(std::vector<PetscReal> *xyz, PetscBool *known)> InitialPoints;
PetscErrorCode GridsCreate(MPI_Comm comm, const Domain &domain, PetscReal d_max, Grids *grids, const InitialPoints &points = nullptr,
                           PetscBool gas = PETSC_TRUE);
PetscErrorCode GridsDestroy(Grids *grids);
// The box of n[0] x n[1] (x n[2]) cells over the domain (a grid's cell counts), as the kernels measure it.
kernels::CellGrid GridsCellGrid(const Domain &domain, const PetscInt n[3]);
// The -pgrid_layout name of a layout ("horizontal", "petsc", "particles").
const char *GridsLayoutName(GridLayout layout);
// This rank's fluid cells and the halo cells its star stencil receives from neighbouring ranks.
PetscErrorCode GridsLocalCells(const Grids &grids, PetscInt64 *owned, PetscInt64 *halo);
PetscErrorCode GridsView(const Grids &grids, const Domain &domain, PetscViewer viewer);

} // namespace fluidbed
