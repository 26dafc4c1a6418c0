// Gas boundary conditions: the options of each face and of the bottom inlet, the boundary face velocities, and the
// ghost layers beyond the walls that let the interior stencils run unchanged up to the boundary.
#include "fluid_impl.hpp"
#include "fluidbed/inlets.hpp"
#include "fluidbed/options.hpp"

#include <algorithm>
#include <string>

namespace fluidbed {

const char *const FluidBCTypes[]            = {"noslip", "freeslip", "outlet", "pressure", "FluidBC", "FLUID_BC_", NULL};
const char *const FluidFaceKeys[FACE_COUNT] = {"xlo", "xhi", "ylo", "yhi", "zlo", "zhi"};

namespace {

bool TopIsOutlet(const Fluid *f)
{
  return !f->periodic[1] && (f->bc[FACE_YHI] == FLUID_BC_OUTLET || f->bc[FACE_YHI] == FLUID_BC_PRESSURE);
}

} // namespace

PetscErrorCode FluidReadBoundaryOptions(Fluid *f)
{
  char      inlet_type[64] = "slits";
  PetscBool set_bc[FACE_COUNT]{};

  PetscFunctionBeginUser;
  PetscOptionsBegin(f->comm, "fluid_bc_", "Gas boundary conditions of each face (x/y/z lo/hi; periodic faces come from -domain_periodic_*)",
                    "Fluid");
  for (int face = 0; face < 2 * f->dim; ++face) {
    const std::string name = std::string("-") + FluidFaceKeys[face], vname = name + "_velocity";
    const std::string help = std::string("Gas condition on the ") + FaceNames[face] + " face: noslip or freeslip wall" +
                             (face == FACE_YHI ? ", outlet (uniform, mass-conserving: the seed's) or pressure (p = 0)" : "");
    PetscEnum type = (PetscEnum)f->bc[face];
    PetscInt  n    = 3;
    PetscCall(OptionsEnum(PetscOptionsObject, name.c_str(), help.c_str(), FluidBCTypes, &type, &set_bc[face]));
    f->bc[face] = (FluidBC)type;
    PetscCall(OptionsRealArray(PetscOptionsObject, vname.c_str(), "Velocity ux,uy,uz of a moving no-slip wall (tangential components only)",
                               "m/s", Closed(-1e4, 1e4), f->wall_velocity[face], &n, PETSC_TRUE, NULL));
    PetscCheck(f->wall_velocity[face][face / 2] == 0, f->comm, PETSC_ERR_ARG_OUTOFRANGE,
               "%s: the wall-normal component %.6g m/s must be 0 (walls do not move through themselves)",
               OptionName(PetscOptionsObject, vname.c_str()), (double)f->wall_velocity[face][face / 2]);
    PetscCheck(!set_bc[face] || !f->periodic[face / 2], f->comm, PETSC_ERR_USER_INPUT, "%s: the face is periodic (-domain_periodic_%c)",
               OptionName(PetscOptionsObject, name.c_str()), "xyz"[face / 2]);
    PetscCheck(face == FACE_YHI || (f->bc[face] != FLUID_BC_OUTLET && f->bc[face] != FLUID_BC_PRESSURE), f->comm, PETSC_ERR_USER_INPUT,
               "%s %s: outlets are at the top only (-fluid_bc_yhi)", OptionName(PetscOptionsObject, name.c_str()),
               FluidBCTypes[f->bc[face]]);
  }
  PetscOptionsEnd();

  PetscOptionsBegin(f->comm, "inlet_", "Gas inlet through the bottom (y = 0)", "Fluid");
  {
    PetscFunctionList types;
    PetscCall(InletList(&types));
    PetscCall(PetscOptionsFList("-type", "Inlet type (slits: a porous distributor and slits through the depth, the seed's)",
                                "InletRegister", types, inlet_type, inlet_type, sizeof(inlet_type), NULL));
  }
  PetscCall(OptionsReal(PetscOptionsObject, "-ramp_time",
                        "Time over which the distributor and slit velocities grow linearly from 0 to their values (0: at full speed "
                        "from the start; a packed bed hit by a full jet at once can be launched as a slug)",
                        "s", NonNegative(1e6), &f->inlet_ramp, NULL));
  PetscOptionsEnd();

  {
    InletFace face;
    face.comm = f->comm;
    face.dom  = f->dom;
    for (int a = 0; a < 3; ++a) {
      face.n[a] = f->n[a];
      face.h[a] = f->h[a];
    }
    PetscCall(InletSetUp(inlet_type, face, &f->inlet));
  }
  const bool inflow =
    !f->inlet.openings.empty() || std::any_of(f->inlet.velocity.begin(), f->inlet.velocity.end(), [](PetscReal v) { return v != 0; });
  PetscCheck(!inflow || !f->periodic[1], f->comm, PETSC_ERR_USER_INPUT,
             "-inlet_velocity / -inlet_jets need a bottom, but y is periodic (-domain_periodic_y)");
  PetscCheck(!inflow || TopIsOutlet(f), f->comm, PETSC_ERR_USER_INPUT,
             "gas flows in through the bottom (-inlet_velocity / -inlet_jets) but the top is closed: set -fluid_bc_yhi outlet (uniform, "
             "the seed's) or pressure");
  // The inflow: each row along z summed over x; rows that all carry the same flow (slits through the depth) count as
  // one row's times n_z.
  {
    const PetscInt         nx = f->n[0], nz = f->n[2];
    std::vector<PetscReal> rows((std::size_t)nz, 0.0);
    for (PetscInt k = 0; k < nz; ++k)
      for (PetscInt i = 0; i < nx; ++i) rows[(std::size_t)k] += f->inlet.velocity[(std::size_t)(i + nx * k)];
    if (std::all_of(rows.begin(), rows.end(), [&](PetscReal r) { return r == rows[0]; })) f->inflow_rate = rows[0] * f->area[1] * nz;
    else {
      PetscReal sum = 0;
      for (PetscReal r : rows) sum += r;
      f->inflow_rate = sum * f->area[1];
    }
  }
  f->has_dirichlet = (PetscBool)(!f->periodic[1] && f->bc[FACE_YHI] == FLUID_BC_PRESSURE);
  PetscFunctionReturn(0);
}

PetscErrorCode FluidFillGhosts(Fluid *f, Vec loc, PetscInt kind)
{
  DM        dm = kind == 1 ? f->da_u : f->da_s;
  DMDAField v, top;
  const int sw = 2;

  PetscFunctionBeginUser;
  PetscCall(DMDAFieldGet(dm, loc, PETSC_TRUE, &v));
  const bool outlet = kind == 1 && TopIsOutlet(f);
  if (outlet) {
    PetscCall(DMDAFieldGet(f->da_s, f->u_top_loc, PETSC_TRUE, &top));
    PetscCheck(SameLayout(v, top), f->comm, PETSC_ERR_PLIB, "the velocity and scalar ghosted layouts differ");
  }
  for (int b = 0; b < f->dim; ++b) {
    if (f->periodic[b]) continue;
    for (int side = 0; side < 2; ++side) {
      if (side == 0 ? f->xs[b] != 0 : f->xs[b] + f->xm[b] != f->n[b]) continue;
      const int      face   = 2 * b + side;
      const bool     noslip = f->bc[face] == FLUID_BC_NOSLIP;
      const PetscInt nb = f->n[b], sb = v.stride(b), dof = v.dof;
      PetscInt       lo[3], hi[3];
      for (int d = 0; d < 3; ++d) {
        lo[d] = v.s[d];
        hi[d] = v.s[d] + v.m[d];
      }
      for (int g = 1; g <= sw; ++g) {
        const PetscInt pos = side ? nb - 1 + g : -g, mirror = side ? nb - g : g - 1;
        lo[b] = pos;
        hi[b] = pos + 1;
        // offsets from the ghost cell to its mirror (q) and, for the normal velocity, to the faces it is reflected
        // from: side 0, faces -1, -2: odd reflection about the boundary face 0 (r = 0, s = g); side 1: the boundary
        // face n itself (g = 1, from r = n - 1: the outlet velocity kept there) and face n + 1 (r = n, s = n - 1)
        const PetscInt dq = (mirror - pos) * sb, dr = ((side == 0 ? 0 : (g == 1 ? nb - 1 : nb)) - pos) * sb;
        const PetscInt ds = ((side == 0 ? g : nb - 1) - pos) * sb;
        // a pass writes the plane pos only and reads other planes: its loops may go in any order
        if (kind == 0) {
          ForEachCellInBox(v, lo, hi, [&](PetscInt p) { v.a[p] = v.a[p + dq]; });
          continue;
        }
        for (int c = 0; c < f->dim; ++c) {
          PetscScalar *x = v.a + c; // x[p * dof]: component c of the cell at offset p
          if (c != b) {
            const PetscReal w2 = 2.0 * f->wall_velocity[face][c];
            if (noslip) ForEachCellInBox(v, lo, hi, [&](PetscInt p) { x[p * dof] = w2 - x[(p + dq) * dof]; });
            else ForEachCellInBox(v, lo, hi, [&](PetscInt p) { x[p * dof] = x[(p + dq) * dof]; });
          } else if (side == 0 || g != 1) {
            ForEachCellInBox(v, lo, hi, [&](PetscInt p) { x[p * dof] = 2.0 * x[(p + dr) * dof] - x[(p + ds) * dof]; });
          } else if (outlet && b == 1) {
            ForEachCellInBox(v, lo, hi, [&](PetscInt p) { x[p * dof] = top.a[p + dr]; });
          } else {
            ForEachCellInBox(v, lo, hi, [&](PetscInt p) { x[p * dof] = 0.0; });
          }
        }
      }
    }
  }
  if (outlet) PetscCall(DMDAFieldRestore(f->u_top_loc, &top));
  PetscCall(DMDAFieldRestore(loc, &v));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidDepsSum(Fluid *f, PetscReal dt, PetscReal *sum)
{
  DMDAField e, e0;
  PetscReal loc = 0;

  PetscFunctionBeginUser;
  *sum = 0;
  if (!f->deps_dt || !(dt > 0)) PetscFunctionReturn(0);
  PetscCall(DMDAFieldGet(f->da_p, f->eps, PETSC_FALSE, &e));
  PetscCall(DMDAFieldGet(f->da_p, f->eps_old, PETSC_FALSE, &e0));
  ForEachOwnedCell(f, [&](PetscInt i, PetscInt j, PetscInt k) { loc -= f->vol * (e(i, j, k) - e0(i, j, k)) / dt; });
  PetscCall(DMDAFieldRestore(f->eps_old, &e0));
  PetscCall(DMDAFieldRestore(f->eps, &e));
  PetscCallMPI(MPI_Allreduce(&loc, sum, 1, MPIU_REAL, MPI_SUM, f->comm));
  PetscFunctionReturn(0);
}

PetscReal FluidInletScale(const Fluid *f, PetscReal t)
{
  return f->inlet_ramp > 0 ? PetscMin(1.0, t / f->inlet_ramp) : 1.0;
}

PetscErrorCode FluidSetBoundaryFaces(Fluid *f, PetscReal dt, PetscBool extrapolate)
{
  DMDAField u, e;
  PetscReal deps_sum;

  PetscFunctionBeginUser;
  PetscCall(FluidDepsSum(f, dt, &deps_sum));
  const PetscReal scale        = FluidInletScale(f, f->time + dt); // the faces of the end of the step
  const PetscReal outflow_rate = scale * f->inflow_rate + deps_sum;
  PetscCall(DMDAFieldGet(f->da_u, f->u, PETSC_FALSE, &u));
  PetscCall(DMDAFieldGet(f->da_p, f->eps, PETSC_FALSE, &e));
  // lower faces: walls (0) and the bottom inlet (superficial velocity / eps)
  for (int a = 0; a < f->dim; ++a) {
    if (f->periodic[a] || f->xs[a] != 0) continue;
    PetscInt lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
      lo[d] = f->xs[d];
      hi[d] = f->xs[d] + f->xm[d];
    }
    hi[a] = 1;
    for (PetscInt k = lo[2]; k < hi[2]; ++k)
      for (PetscInt j = lo[1]; j < hi[1]; ++j)
        for (PetscInt i = lo[0]; i < hi[0]; ++i)
          u(i, j, k, a) = a == 1 ? scale * f->inlet.velocity[(std::size_t)(i + f->n[0] * k)] / e(i, j, k) : 0.0;
  }
  // top outlet
  if (TopIsOutlet(f) && f->xs[1] + f->xm[1] == f->n[1]) {
    DMDAField      top;
    const PetscInt j = f->n[1] - 1;
    PetscCall(DMDAFieldGet(f->da_p, f->u_top, PETSC_FALSE, &top));
    for (PetscInt k = f->xs[2]; k < f->xs[2] + f->xm[2]; ++k)
      for (PetscInt i = f->xs[0]; i < f->xs[0] + f->xm[0]; ++i) {
        if (f->bc[FACE_YHI] == FLUID_BC_OUTLET) top(i, j, k) = outflow_rate / (f->area[1] * f->n[0] * f->n[2] * e(i, j, k));
        else if (extrapolate) top(i, j, k) = u(i, j, k, 1); // the predicted velocity, zero normal gradient; corrected by p = 0
        else top(i, j, k) = f->initial_velocity[1] / e(i, j, k);
      }
    PetscCall(DMDAFieldRestore(f->u_top, &top));
  }
  PetscCall(DMDAFieldRestore(f->eps, &e));
  PetscCall(DMDAFieldRestore(f->u, &u));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidScatterVelocity(Fluid *f)
{
  PetscFunctionBeginUser;
  PetscCall(DMGlobalToLocal(f->da_u, f->u, INSERT_VALUES, f->u_loc));
  if (TopIsOutlet(f)) {
    PetscCall(DMGlobalToLocal(f->da_s, f->u_top, INSERT_VALUES, f->u_top_loc));
    PetscCall(FluidFillGhosts(f, f->u_top_loc, 0));
  }
  PetscCall(FluidFillGhosts(f, f->u_loc, 1));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidFlowRates(Fluid *f, PetscReal *in, PetscReal *out)
{
  DMDAField u, e;
  PetscReal loc[2] = {0, 0}, glob[2];

  PetscFunctionBeginUser;
  PetscCall(DMDAFieldGet(f->da_u, f->u_loc, PETSC_TRUE, &u));
  PetscCall(DMDAFieldGet(f->da_s, f->eps_loc, PETSC_TRUE, &e));
  if (!f->periodic[1]) {
    for (int side = 0; side < 2; ++side) {
      if (side == 0 ? f->xs[1] != 0 : f->xs[1] + f->xm[1] != f->n[1]) continue;
      const PetscInt j = side ? f->n[1] : 0;
      for (PetscInt k = f->xs[2]; k < f->xs[2] + f->xm[2]; ++k)
        for (PetscInt i = f->xs[0]; i < f->xs[0] + f->xm[0]; ++i) {
          const PetscInt c[3] = {i, j, k};
          loc[side] += FaceEps(e, c, 1) * u(i, j, k, 1) * f->area[1];
        }
    }
  }
  PetscCall(DMDAFieldRestore(f->eps_loc, &e));
  PetscCall(DMDAFieldRestore(f->u_loc, &u));
  PetscCallMPI(MPI_Allreduce(loc, glob, 2, MPIU_REAL, MPI_SUM, f->comm));
  *in  = glob[0];
  *out = glob[1];
  PetscFunctionReturn(0);
}

} // namespace fluidbed
