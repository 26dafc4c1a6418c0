// The gas of a component test as its options describe it: the domain, the grids and the gas on the fluid grid, set up
// (fields, boundary faces, pressure operator), created and destroyed together.
#pragma once

#include "fluidbed/dmda_field.hpp"
#include "fluidbed/domain.hpp"
#include "fluidbed/fluid.hpp"
#include "fluidbed/grids.hpp"
#include "fluidbed/phases.hpp"

namespace fluidbed::component {

struct GasScene {
  MPI_Comm comm = MPI_COMM_NULL;
  Domain   dom;
  Grids    grids;
  PhaseLog log;
  Fluid   *fluid = nullptr;
};

inline PetscErrorCode GasSceneCreate(MPI_Comm comm, GasScene *s)
{
  PetscFunctionBeginUser;
  s->comm = comm;
  PetscCall(PhaseLogRegister(&s->log));
  PetscCall(DomainSetFromOptions(comm, &s->dom));
  PetscCall(GridsCreate(comm, s->dom, 0.0, &s->grids));
  PetscCall(FluidCreate(comm, s->dom, s->grids.fluid, &s->log, &s->fluid));
  PetscCall(FluidSetUp(s->fluid));
  PetscFunctionReturn(0);
}

inline PetscErrorCode GasSceneDestroy(GasScene *s)
{
  PetscFunctionBeginUser;
  PetscCall(FluidDestroy(&s->fluid));
  PetscCall(GridsDestroy(&s->grids));
  PetscFunctionReturn(0);
}

// Writes value(natural index) into the owned cells of a scalar field of da: a field that does not depend on the
// decomposition.
template <class Fn>
PetscErrorCode SetByNaturalIndex(DM da, Vec v, const PetscInt n[3], Fn &&value)
{
  DMDAField f;

  PetscFunctionBeginUser;
  PetscCall(DMDAFieldGet(da, v, PETSC_FALSE, &f));
  for (PetscInt k = f.s[2]; k < f.s[2] + f.m[2]; ++k)
    for (PetscInt j = f.s[1]; j < f.s[1] + f.m[1]; ++j)
      for (PetscInt i = f.s[0]; i < f.s[0] + f.m[0]; ++i) f(i, j, k) = value(i + n[0] * (j + n[1] * k));
  PetscCall(DMDAFieldRestore(v, &f));
  PetscFunctionReturn(0);
}

} // namespace fluidbed::component
