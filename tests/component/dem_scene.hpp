// The DEM of a component test as its options describe it: the domain, the particle properties, the grids, the DEM
// and its empty swarm, created and destroyed together.
#pragma once

#include "../../src/contact/dem_impl.hpp"
#include "fluidbed/domain.hpp"
#include "fluidbed/grids.hpp"
#include "fluidbed/particles.hpp"
#include "fluidbed/phases.hpp"

namespace fluidbed::component {

struct DemScene {
  MPI_Comm      comm = MPI_COMM_NULL;
  Domain        dom;
  ParticleProps props;
  Grids         grids;
  PhaseLog      log;
  Dem          *dem   = nullptr;
  DM            swarm = nullptr;
};

inline PetscErrorCode DemSceneCreate(MPI_Comm comm, DemScene *s)
{
  PetscFunctionBeginUser;
  s->comm = comm;
  PetscCall(PhaseLogRegister(&s->log));
  PetscCall(DomainSetFromOptions(comm, &s->dom));
  PetscCall(ParticlePropsSetFromOptions(comm, s->dom, &s->props));
  PetscCall(GridsCreate(comm, s->dom, s->props.d_max, &s->grids));
  PetscCall(DemCreate(comm, s->dom, s->grids.particle, s->props, &s->log, &s->dem));
  PetscCall(DemCreateSwarm(s->dem, &s->swarm));
  PetscFunctionReturn(0);
}

inline PetscErrorCode DemSceneDestroy(DemScene *s)
{
  PetscFunctionBeginUser;
  PetscCall(DMDestroy(&s->swarm));
  PetscCall(DemDestroy(&s->dem));
  PetscCall(GridsDestroy(&s->grids));
  PetscFunctionReturn(0);
}

} // namespace fluidbed::component
