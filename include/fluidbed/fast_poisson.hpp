// The PC type "fastpoisson" (-fluid_p_pc_type fastpoisson, src/fluid/fast_poisson.cpp): the exact inverse of the
// projection's operator with one constant face coefficient on the uniform pressure grid, by FFTW transforms along the
// walled and periodic axes and a tridiagonal solve along y (kernels/separable_poisson.hpp); on a grid split among the
// ranks along x only, transforms along y and z and the lines along x solved across the ranks by the partition method
// (no pencils). A preconditioner for CG on the projection, whose face coefficients vary only through the implicit drag
// (model B) or the void fraction (model A).
#pragma once

#include <petscksp.h>

namespace fluidbed {

#define PCFASTPOISSON "fastpoisson"

// Whether the PC's pencil layouts fit a grid of n[0] x n[1] (x n[2]) cells on `ranks` ranks: at least as many cells as
// ranks along x (the line-solve pencils are split along x) and along y (the transform pencils along y). The default
// pressure PC (src/fluid/pressure.cpp) asks it of every grid, also of those split along x only, which need no pencils.
inline bool FastPoissonPencilsFit(const PetscInt n[3], PetscMPIInt ranks)
{
  return n[0] >= ranks && n[1] >= ranks;
}

// Adds "fastpoisson" to PETSc's PC types (again is harmless).
PetscErrorCode FastPoissonRegister();
// Gives a fastpoisson PC its grid: da, a cell-centred DMDA of the pressure's layout (its sizes, periodic axes and
// ownership), the face weights A_a / h_a (m) and whether the top face is a pressure outlet (phi = 0 half a cell above the
// top centres). A no-op for a PC of another type.
PetscErrorCode PCFastPoissonSetGrid(PC pc, DM da, const PetscReal weight[3], PetscBool outlet_top);
// Whether pc is a fastpoisson PC and, if so, its set-ups so far, those with the Jacobi steps on, and the largest
// coefficient contrast a set-up saw (the mean face coefficient over the smallest cell's).
PetscErrorCode PCFastPoissonGetStats(PC pc, PetscBool *is_fp, PetscInt *setups, PetscInt *jacobi_setups, PetscReal *contrast_max);

} // namespace fluidbed
