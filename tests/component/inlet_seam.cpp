// Component test of the inlet seam (include/fluidbed/inlets.hpp): an inlet type registered from outside the gas
// module, here one square orifice in the bottom face (cell (i, k), velocity v), replaces the slits with -inlet_type
// orifice and no other change. Checks on any number of ranks, in 3D, after the set-up and after gas steps:
//   - the bottom face's normal velocity is v / eps at the orifice's cell and 0 at every other bottom cell (the
//     profile of cell (i, k) reaches the face of cell (i, 0, k), not one velocity per x column);
//   - the inflow rate is v times one cell's face area;
//   - the uniform outlet carries out what came in: the top faces' flux sums to the inflow within 1e-12 relative.
// Prints one line per check and exits nonzero on the first failure.
#include "component_common.hpp"
#include "gas_scene.hpp"

#include "../../src/fluid/fluid_impl.hpp"
#include "fluidbed/domain.hpp"
#include "fluidbed/grids.hpp"
#include "fluidbed/inlets.hpp"
#include "fluidbed/phases.hpp"

#include <cmath>

using namespace fluidbed;
using component::Check;

static const char help[] = "Inlet seam: an orifice inlet registered by the test (-orifice_cell i,k, -orifice_velocity v, -steps N)\n";

namespace {

PetscInt  orifice_cell[2]  = {1, 1};
PetscReal orifice_velocity = 0.5;

// The orifice inlet type: the superficial velocity v through bottom cell (i, k), nothing elsewhere.
PetscErrorCode InletCreateOrifice(const InletFace &face, Inlet *inlet)
{
  PetscFunctionBeginUser;
  inlet->velocity.assign((std::size_t)(face.n[0] * face.n[2]), 0.0);
  inlet->velocity[(std::size_t)(orifice_cell[0] + face.n[0] * orifice_cell[1])] = orifice_velocity;
  inlet->summary                                                                = "one orifice";
  PetscFunctionReturn(0);
}

PetscErrorCode CheckFaces(Fluid *f, const char *when)
{
  DMDAField u, e, top;
  long long wrong = 0;
  PetscReal out   = 0, out_all;

  PetscFunctionBeginUser;
  PetscCall(DMDAFieldGet(f->da_u, f->u, PETSC_FALSE, &u));
  PetscCall(DMDAFieldGet(f->da_p, f->eps, PETSC_FALSE, &e));
  if (f->xs[1] == 0)
    for (PetscInt k = f->xs[2]; k < f->xs[2] + f->xm[2]; ++k)
      for (PetscInt i = f->xs[0]; i < f->xs[0] + f->xm[0]; ++i) {
        const bool      hole   = i == orifice_cell[0] && k == orifice_cell[1];
        const PetscReal expect = hole ? orifice_velocity / e(i, 0, k) : 0.0;
        if (std::fabs(u(i, 0, k, 1) - expect) > 1e-14 * orifice_velocity) ++wrong;
      }
  PetscCall(DMDAFieldRestore(f->eps, &e));
  PetscCall(DMDAFieldRestore(f->u, &u));
  if (f->xs[1] + f->xm[1] == f->n[1]) {
    PetscCall(DMDAFieldGet(f->da_p, f->u_top, PETSC_FALSE, &top));
    PetscCall(DMDAFieldGet(f->da_p, f->eps, PETSC_FALSE, &e));
    const PetscInt j = f->n[1] - 1;
    for (PetscInt k = f->xs[2]; k < f->xs[2] + f->xm[2]; ++k)
      for (PetscInt i = f->xs[0]; i < f->xs[0] + f->xm[0]; ++i) out += top(i, j, k) * e(i, j, k) * f->area[1];
    PetscCall(DMDAFieldRestore(f->eps, &e));
    PetscCall(DMDAFieldRestore(f->u_top, &top));
  }
  PetscCallMPI(MPI_Allreduce(&out, &out_all, 1, MPIU_REAL, MPI_SUM, f->comm));
  PetscCall(PetscPrintf(f->comm, "%s:\n", when));
  PetscCall(Check(f->comm, wrong == 0, "the bottom faces carry v / eps at the orifice's cell and 0 elsewhere (wrong faces)", wrong));
  const PetscReal in = orifice_velocity * f->area[1];
  PetscCall(Check(f->comm, std::fabs(f->inflow_rate - in) <= 1e-14 * in, "the inflow rate is v times one face area", 0));
  PetscCall(Check(f->comm, std::fabs(out_all - in) <= 1e-12 * in, "the uniform outlet carries out the inflow (1e-12 relative)",
                  (long long)std::llround(1e15 * std::fabs(out_all - in) / in)));
  PetscFunctionReturn(0);
}

} // namespace

int main(int argc, char **argv)
{
  component::GasScene sc;
  PetscInt            n = 2, steps = 3;
  PetscReal           dt;

  PetscCall(PetscInitialize(&argc, &argv, NULL, help));
  PetscCall(PetscOptionsGetIntArray(NULL, NULL, "-orifice_cell", orifice_cell, &n, NULL));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-orifice_velocity", &orifice_velocity, NULL));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-steps", &steps, NULL));
  PetscCall(InletRegister("orifice", InletCreateOrifice)); // the seam: one function and one registration
  PetscCall(component::GasSceneCreate(PETSC_COMM_WORLD, &sc));
  Fluid *fluid = sc.fluid;
  PetscCall(CheckFaces(fluid, "after the set-up"));
  PetscCall(FluidMaxTimeStep(fluid, &dt));
  for (PetscInt s = 0; s < steps; ++s) PetscCall(FluidStep(fluid, dt));
  PetscCall(CheckFaces(fluid, "after the gas steps"));
  PetscCall(component::GasSceneDestroy(&sc));
  PetscCall(PetscFinalize());
  return 0;
}
