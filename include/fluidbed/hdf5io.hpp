// HDF5 snapshots (ParaView via XDMF) and checkpoints, written in parallel through PETSc's HDF5 viewer.
//
// Particle fields are viewed as Vecs wrapped around the DMSwarm field arrays (one dataset per field, rows in rank
// order, shape (N, components)); DMDA fields are written in natural ordering, shape (Nz, Ny, Nx[, dof]). The
// XDMF files are written by hand: a temporal collection of Polyvertex grids for particles and of structured
// grids for the gas (XdmfCellGrid), each pointing at datasets in the per-snapshot HDF5 files.
#pragma once

#include <petscviewerhdf5.h>

#include <functional>
#include <string>
#include <vector>

#include "fluidbed/dem.hpp"
#include "fluidbed/grids.hpp"
#include "fluidbed/io.hpp"

namespace fluidbed {

struct Fluid;

// Particle datasets under /particles: position, velocity, omega, diameter and id; with `full` (checkpoints) also
// force, torque and the contact history, everything needed to continue bit for bit.
PetscErrorCode ParticlesWriteHDF5(DM swarm, PetscViewer viewer, PetscBool full);
// The bytes of data ParticlesWriteHDF5 writes (collective): the size of a file to make room for.
PetscErrorCode ParticlesHDF5Bytes(DM swarm, PetscBool full, PetscInt64 *bytes);

// A per-particle dataset /particles/<name>: 1 for the particles whose id is in ids, 0 for the others (the
// diagnostic snapshot's marks), in the rows ParticlesWriteHDF5 writes.
PetscErrorCode ParticlesWriteFlagHDF5(DM swarm, PetscViewer viewer, const char *name, const std::vector<PetscInt64> &ids);

// Reads the /particles datasets of a checkpoint written by ParticlesWriteHDF5 (any number of ranks) and gives
// every particle to the rank that owns its particle cell. The swarm's previous particles are replaced.
PetscErrorCode ParticlesReadHDF5(DM swarm, PetscViewer viewer, const Domain &domain, const ParticleGrid &pgrid);

// The particle and gas data of a snapshot or (full) a checkpoint (ParticlesWriteHDF5, FluidWriteHDF5; either may
// be NULL, off), the bulk of the file (collective).
PetscErrorCode StateHDF5Bytes(DM swarm, Fluid *fluid, PetscBool full, PetscInt64 *bytes);

// One entry of a snapshot series.
struct SnapshotRecord {
  PetscReal   time;
  std::string file; // HDF5 file name relative to the XDMF file
  PetscInt64  particles;
};

// One Polyvertex <Grid> of a snapshot's particles: position, velocity, omega, diameter, id and the extra scalars.
std::string XdmfParticleGrid(const SnapshotRecord &s, PetscInt dim, const std::vector<std::string> &extra_scalars);
// Rewrites <dir>/particles.xmf for the whole series (collective; rank 0 writes).
PetscErrorCode XdmfWriteParticles(MPI_Comm comm, const std::string &dir, PetscInt dim, const std::vector<SnapshotRecord> &series);

// Rewrites <dir>/fluid.xmf: XdmfCellGrid grids with the cell-centred velocity, pressure and void fraction
// (collective; rank 0 writes). In 2D their geometry is read from XdmfWriteFluidNodes' file.
PetscErrorCode XdmfWriteFluid(MPI_Comm comm, const std::string &dir, const Domain &domain, const FluidGrid &grid,
                              const std::vector<SnapshotRecord> &series);

// The snapshot series as an output of the run (src/io/snapshots.cpp): snapshot_NNNNN.h5 with the particles and the gas
// every `interval` of simulated time from the initial state (0: none), each listed in particles.xmf and fluid.xmf
// once complete; a checkpoint holds the series, and a restart removes the snapshots written after it. Present
// with no interval too, so that a restart keeps the series of the run it continues.
PetscErrorCode SnapshotSeriesCreate(PetscReal interval, std::unique_ptr<Output> *out);

// The file of XdmfWriteFluidNodes, in the output directory.
inline constexpr const char *kFluidNodesFile = run_files::fluid_nodes;

// Writes <dir>/fluid_grid.h5 for a 2D gas grid: /nodes, the (Nx + 1)(Ny + 1) x 2 coordinates x, y of its nodes, x
// fastest, shared by every grid of fluid.xmf (nothing in 3D). Collective; once per run, before the first fluid.xmf.
PetscErrorCode XdmfWriteFluidNodes(MPI_Comm comm, const std::string &dir, const Domain &domain, const FluidGrid &grid);

// XDMF building blocks for cell fields on a uniform grid, as ParaView 5.11 (XDMF and Xdmf3 readers) reads them
// with the particles: a 3DCoRectMesh in 3D; in 2D a 2DSMesh in the x-y plane at z = 0, its node coordinates from
// `nodes` (an HDF5 item "file:/dataset" as XdmfWriteFluidNodes writes) or, when `nodes` is empty, inline.
struct XdmfCellField {
  std::string name;       // attribute name in ParaView
  std::string dataset;    // absolute HDF5 path, e.g. "/fluid/pressure", shape (Nz,) Ny, Nx[, components]
  int         components; // 1 (scalar), 2 or 3 (vector of the grid's dimension)
};
// The gas fields of a snapshot (FluidWriteHDF5): pressure, void fraction, velocity.
std::vector<XdmfCellField> XdmfFluidFields(PetscInt dim);
// One <Grid> element of n[0] x n[1] (x n[2]) cells of size h from lo, its attributes read from `file`; with a time
// when `time` is given (an entry of a temporal collection).
std::string XdmfCellGrid(const char *name, PetscInt dim, const PetscInt n[3], const PetscReal lo[3], const PetscReal h[3],
                         const std::string &file, const std::vector<XdmfCellField> &fields, const PetscReal *time,
                         const std::string &nodes = "");
// The XDMF document around grid elements: inside a temporal collection of that name, or bare when collection is NULL.
std::string XdmfDocument(const std::string &grids, const char *collection);
// Writes text to path (collective; rank 0 writes path.tmp and renames it: OutputWriteText).
PetscErrorCode XdmfWriteFile(MPI_Comm comm, const std::string &path, const std::string &text);

// Writes an HDF5 file through PETSc's viewer (collective): write() fills it. The file is written to path.tmp and
// renamed when complete. Any failure on any rank (full disk, file-size limit, unwritable path: PETSc raises
// PETSC_ERR_LIB from the failed HDF5 call) is caught instead of printed, the file is closed on every rank, and every
// rank raises PETSC_ERR_FILE_WRITE naming path and the reason; the previous file of that name stays intact.
// bytes: the data it will hold, as far as known (0: unknown); the space for it is made sure of first (-output_reserve).
PetscErrorCode WriteHDF5File(MPI_Comm comm, const std::string &path, PetscInt64 bytes,
                             const std::function<PetscErrorCode(PetscViewer)> &write);
// -output_reserve: whether WriteHDF5File reserves a file's space before HDF5 writes it (on by default).
void OutputSetReserve(PetscBool reserve);

} // namespace fluidbed
