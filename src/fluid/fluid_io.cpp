// The gas fields in HDF5: cell fields for snapshots, the full state for checkpoints. DMDA vectors are written in
// natural ordering, so a checkpoint loads on any number of ranks.
#include "fluid_impl.hpp"

#include <petscviewerhdf5.h>

namespace fluidbed {

namespace {
PetscErrorCode ViewNamed(Vec v, const char *name, PetscViewer viewer)
{
  const char *old;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetName((PetscObject)v, &old));
  std::string keep = old ? old : "";
  PetscCall(PetscObjectSetName((PetscObject)v, name));
  PetscCall(VecView(v, viewer));
  PetscCall(PetscObjectSetName((PetscObject)v, keep.c_str()));
  PetscFunctionReturn(0);
}
PetscErrorCode LoadNamed(Vec v, const char *name, PetscViewer viewer)
{
  const char *old;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetName((PetscObject)v, &old));
  std::string keep = old ? old : "";
  PetscCall(PetscObjectSetName((PetscObject)v, name));
  PetscCall(VecLoad(v, viewer));
  PetscCall(PetscObjectSetName((PetscObject)v, keep.c_str()));
  PetscFunctionReturn(0);
}
// The datasets of /fluid: snapshots write the first three, checkpoints all (FluidWriteHDF5, FluidHDF5Bytes).
// "velocity" is the cell-centred velocity, f->cell_u once FluidGetCellVelocity has filled it.
struct FluidDataset {
  const char *name;
  Vec         v;
  bool        checkpoint_only;
};
std::vector<FluidDataset> FluidDatasets(const Fluid *f)
{
  return {{"velocity", f->cell_u, false},          {"pressure", f->p, false},
          {"void_fraction", f->eps, false},        {"face_velocity", f->u, true},
          {"void_fraction_old", f->eps_old, true}, {"momentum_source", f->source, true},
          {"outlet_velocity", f->u_top, true}};
}
} // namespace

PetscErrorCode FluidHDF5Bytes(Fluid *f, PetscBool full, PetscInt64 *bytes)
{
  PetscFunctionBeginUser;
  *bytes = 0;
  for (const FluidDataset &s : FluidDatasets(f)) {
    PetscInt n;
    if (s.checkpoint_only && !full) continue;
    PetscCall(VecGetSize(s.v, &n));
    *bytes += (PetscInt64)n * (PetscInt64)sizeof(PetscScalar);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FluidWriteHDF5(Fluid *f, PetscViewer viewer, PetscBool full)
{
  Vec cell;

  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5PushGroup(viewer, "/fluid"));
  PetscCall(FluidGetCellVelocity(f, &cell));
  for (const FluidDataset &s : FluidDatasets(f))
    if (full || !s.checkpoint_only) PetscCall(ViewNamed(s.v, s.name, viewer));
  if (full) {
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/fluid", "time", PETSC_REAL, &f->time));
    // the next solve rebuilds the preconditioner, in this run and in one restarted from this checkpoint alike, so a
    // restart repeats the uninterrupted run exactly
    f->since_pc = f->pc_reuse;
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/fluid", "since_pc", PETSC_INT, &f->since_pc));
    const PetscReal steps = (PetscReal)f->stats.steps;
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/fluid", "steps", PETSC_REAL, &steps));
  }
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetGasProperties(const Fluid *f, PetscReal *rho, PetscReal *mu)
{
  PetscFunctionBeginUser;
  *rho = f->rho;
  *mu  = f->mu;
  PetscFunctionReturn(0);
}

PetscBool FluidIsModelB(const Fluid *f)
{
  return f->model == FLUID_MODEL_B ? PETSC_TRUE : PETSC_FALSE;
}

PetscErrorCode FluidGetJetSlots(const Fluid *f, std::vector<std::array<PetscReal, 2>> *slots)
{
  PetscFunctionBeginUser;
  slots->clear();
  for (const kernels::JetCells &j : f->inlet.openings)
    slots->push_back({f->dom->lo[0] + j.first * f->h[0], f->dom->lo[0] + j.last * f->h[0]});
  PetscFunctionReturn(0);
}

const char *FluidBoundaryType(const Fluid *f, Face face)
{
  return f->periodic[face / 2] ? "periodic" : FluidBCTypes[f->bc[face]];
}

PetscErrorCode FluidReadHDF5(Fluid *f, PetscViewer viewer)
{
  PetscReal steps;

  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5PushGroup(viewer, "/fluid"));
  PetscCall(LoadNamed(f->u, "face_velocity", viewer));
  PetscCall(LoadNamed(f->p, "pressure", viewer));
  PetscCall(LoadNamed(f->eps, "void_fraction", viewer));
  PetscCall(LoadNamed(f->eps_old, "void_fraction_old", viewer));
  PetscCall(LoadNamed(f->source, "momentum_source", viewer));
  PetscCall(LoadNamed(f->u_top, "outlet_velocity", viewer));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/fluid", "time", PETSC_REAL, NULL, &f->time));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/fluid", "since_pc", PETSC_INT, NULL, &f->since_pc));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/fluid", "steps", PETSC_REAL, NULL, &steps));
  f->stats.steps = (PetscInt64)steps;
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  PetscCall(DMGlobalToLocal(f->da_s, f->u_top, INSERT_VALUES, f->u_top_loc));
  PetscCall(FluidScatterVelocity(f));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
