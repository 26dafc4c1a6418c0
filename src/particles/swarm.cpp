#include "fluidbed/particles.hpp"
#include "fluidbed/options.hpp"

namespace fluidbed {

PetscErrorCode ParticlePropsSetFromOptions(MPI_Comm comm, const Domain &dom, ParticleProps *p)
{
  PetscReal d       = p->d_min;
  PetscBool set_min = PETSC_FALSE, set_max = PETSC_FALSE;
  PetscReal lmin = PetscMin(dom.len[0], dom.len[1]);
  if (dom.dim == 3) lmin = PetscMin(lmin, dom.len[2]);

  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, "particle_", "Particles", "Particles");
  PetscCall(OptionsReal(PetscOptionsObject, "-diameter", "Particle diameter (monodisperse)", "m", Positive(0.1), &d, NULL));
  p->d_min = p->d_max = d;
  PetscCall(OptionsReal(PetscOptionsObject, "-diameter_min", "Smallest diameter of a uniform-by-number size distribution", "m",
                        Positive(0.1), &p->d_min, &set_min));
  PetscCall(OptionsReal(PetscOptionsObject, "-diameter_max", "Largest diameter of a uniform-by-number size distribution", "m",
                        Positive(0.1), &p->d_max, &set_max));
  PetscCall(OptionsReal(PetscOptionsObject, "-density", "Particle material density", "kg/m^3", Positive(1.0e5), &p->density, NULL));
  PetscOptionsEnd();
  PetscCheck(p->d_max >= p->d_min, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "-particle_diameter_max %.6g m must be at least -particle_diameter_min %.6g m", (double)p->d_max, (double)p->d_min);
  PetscCheck(p->d_max < lmin, comm, PETSC_ERR_ARG_OUTOFRANGE, "particle diameter %.6g m does not fit in the domain (smallest side %.6g m)",
             (double)p->d_max, (double)lmin);
  PetscFunctionReturn(0);
}

PetscErrorCode ParticlesCreate(MPI_Comm comm, const Domain &dom, const ParticleGrid &pg, PetscInt K, PetscInt hs, DM *swarm)
{
  DM sw;

  PetscFunctionBeginUser;
  PetscCall(DMCreate(comm, &sw));
  PetscCall(PetscObjectSetName((PetscObject)sw, "particles"));
  PetscCall(DMSetType(sw, DMSWARM));
  PetscCall(DMSetDimension(sw, dom.dim)); // before the type: PIC registers coordinates with this block size
  PetscCall(DMSwarmSetType(sw, DMSWARM_PIC));
  PetscCall(DMSwarmSetCellDM(sw, pg.da_vertex)); // no reference taken: the grids outlive the swarm
  PetscCall(DMSwarmRegisterPetscDatatypeField(sw, field::velocity, 3, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(sw, field::omega, 3, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(sw, field::force, 3, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(sw, field::torque, 3, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(sw, field::diameter, 1, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(sw, field::id, 1, PETSC_INT64));
  PetscCall(DMSwarmRegisterPetscDatatypeField(sw, field::contact_key, K, PETSC_INT64));
  PetscCall(DMSwarmRegisterPetscDatatypeField(sw, field::contact_hist, hs * K, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(sw, field::drag_coef, 1, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(sw, field::drag_ref, 3, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(sw, field::drag_cell, 1, PETSC_INT64));
  PetscCall(DMSwarmFinalizeFieldRegister(sw));
  PetscCall(DMSwarmSetLocalSizes(sw, 0, 1024));
  *swarm = sw;
  PetscFunctionReturn(0);
}

PetscErrorCode ParticleArraysGet(DM sw, ParticleArrays *a)
{
  PetscInt bs, hbs;

  PetscFunctionBeginUser;
  PetscCall(DMSwarmGetLocalSize(sw, &a->n));
  PetscCall(DMGetDimension(sw, &a->dim));
  PetscCall(DMSwarmGetField(sw, DMSwarmPICField_coor, NULL, NULL, (void **)&a->x));
  PetscCall(DMSwarmGetField(sw, field::velocity, NULL, NULL, (void **)&a->v));
  PetscCall(DMSwarmGetField(sw, field::omega, NULL, NULL, (void **)&a->w));
  PetscCall(DMSwarmGetField(sw, field::force, NULL, NULL, (void **)&a->f));
  PetscCall(DMSwarmGetField(sw, field::torque, NULL, NULL, (void **)&a->t));
  PetscCall(DMSwarmGetField(sw, field::diameter, NULL, NULL, (void **)&a->d));
  PetscCall(DMSwarmGetField(sw, field::id, NULL, NULL, (void **)&a->id));
  PetscCall(DMSwarmGetField(sw, field::contact_key, &bs, NULL, (void **)&a->ckey));
  PetscCall(DMSwarmGetField(sw, field::contact_hist, &hbs, NULL, (void **)&a->chist));
  PetscCall(DMSwarmGetField(sw, field::drag_coef, NULL, NULL, (void **)&a->dcoef));
  PetscCall(DMSwarmGetField(sw, field::drag_ref, NULL, NULL, (void **)&a->dref));
  PetscCall(DMSwarmGetField(sw, field::drag_cell, NULL, NULL, (void **)&a->dcell));
  a->K  = bs;
  a->hs = hbs / bs;
  PetscFunctionReturn(0);
}

PetscErrorCode ParticleArraysRestore(DM sw, ParticleArrays *a)
{
  PetscFunctionBeginUser;
  PetscCall(DMSwarmRestoreField(sw, DMSwarmPICField_coor, NULL, NULL, (void **)&a->x));
  PetscCall(DMSwarmRestoreField(sw, field::velocity, NULL, NULL, (void **)&a->v));
  PetscCall(DMSwarmRestoreField(sw, field::omega, NULL, NULL, (void **)&a->w));
  PetscCall(DMSwarmRestoreField(sw, field::force, NULL, NULL, (void **)&a->f));
  PetscCall(DMSwarmRestoreField(sw, field::torque, NULL, NULL, (void **)&a->t));
  PetscCall(DMSwarmRestoreField(sw, field::diameter, NULL, NULL, (void **)&a->d));
  PetscCall(DMSwarmRestoreField(sw, field::id, NULL, NULL, (void **)&a->id));
  PetscCall(DMSwarmRestoreField(sw, field::contact_key, NULL, NULL, (void **)&a->ckey));
  PetscCall(DMSwarmRestoreField(sw, field::contact_hist, NULL, NULL, (void **)&a->chist));
  PetscCall(DMSwarmRestoreField(sw, field::drag_coef, NULL, NULL, (void **)&a->dcoef));
  PetscCall(DMSwarmRestoreField(sw, field::drag_ref, NULL, NULL, (void **)&a->dref));
  PetscCall(DMSwarmRestoreField(sw, field::drag_cell, NULL, NULL, (void **)&a->dcell));
  PetscFunctionReturn(0);
}

PetscErrorCode ParticlesGlobalCount(DM sw, PetscInt64 *n)
{
  PetscInt   nloc;
  PetscInt64 l;

  PetscFunctionBeginUser;
  PetscCall(DMSwarmGetLocalSize(sw, &nloc));
  l = nloc;
  PetscCallMPI(MPI_Allreduce(&l, n, 1, MPIU_INT64, MPI_SUM, PetscObjectComm((PetscObject)sw)));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
