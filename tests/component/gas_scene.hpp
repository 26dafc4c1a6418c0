// The gas of a component test as its options describe it: the domain, the grids and the gas on the fluid grid, set up
// (fields, boundary faces, pressure operator), created and destroyed together.
#pragma once

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

} // namespace fluidbed::component
