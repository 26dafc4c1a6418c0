// Component test of the fastpoisson PC (src/fluid/fast_poisson.cpp) on any number of ranks, against the pressure
// operator the gas assembled at set-up (constant face coefficient: model B without drag, or a uniform void fraction):
//   - exactness: for a pseudo-random x set by natural index (the same field on every decomposition), y = PC(A x) equals
//     x, up to a constant where the operator has the constant null space: max |y - x - mean(y - x)| <= 1e-10 max |x|;
//   - symmetry: u . PC(v) = v . PC(u) to 1e-12 of |u| |PC(v)|, as CG needs;
//   - with -varying (a gas step with a void fraction of 0.4 in the lower half and a drag coefficient, so that the face
//     coefficients vary fivefold): CG with this PC solves A x = A x_ref to rtol 1e-10 in at most -max_its iterations
//     and recovers x_ref (up to the constant) to 1e-7;
//   - with -contrast as well: every seventh cell of the packed half is held at the void-fraction floor (0.05) with a
//     drag that makes its face coefficients about 0.005 of the freeboard's (a jump of 200, as single-grid cells packed
//     to the floor give on the 550 um bed, docs/ksp.md); -fluid_p_pc_fastpoisson_jacobi (Jacobi steps around the
//     inverse) must stay symmetric, converge within -max_its and in fewer iterations than the inverse alone.
// The weights A_a / h_a are computed here from the grid, not taken from the gas. One line per check; nonzero exit on
// the first failure.
#include "component_common.hpp"
#include "gas_scene.hpp"

#include "fluidbed/dmda_field.hpp"
#include "fluidbed/fast_poisson.hpp"
#include "fluidbed/fluid.hpp"

#include <cmath>
#include <cstring>
#include <vector>

using namespace fluidbed;
using component::Check;
using component::SetByNaturalIndex;

static const char help[] = "fastpoisson PC against the assembled pressure operator (-varying: also CG on a varying operator, -max_its N)\n";

namespace {

// max |y - x - c| over the cells, with c the mean of y - x where the operator has the constant null space (no outlet),
// else 0; d is scratch. The constant removed is returned in *c.
PetscErrorCode LargestDifference(Vec x, Vec y, PetscBool outlet, Vec d, PetscReal *dmax, PetscReal *c)
{
  PetscInt n;

  PetscFunctionBeginUser;
  *c = 0;
  PetscCall(VecWAXPY(d, -1.0, x, y));
  if (!outlet) {
    PetscCall(VecGetSize(d, &n));
    PetscCall(VecSum(d, c));
    *c /= (PetscReal)n;
    PetscCall(VecShift(d, -*c));
  }
  PetscCall(VecNorm(d, NORM_INFINITY, dmax));
  PetscFunctionReturn(0);
}

// u . PC(v) = v . PC(u) to 1e-12 of |u| |PC(v)| for two pseudo-random fields (drawn from rnd), as CG needs; like names
// the check's line. x is a vector of the grid's layout.
PetscErrorCode CheckSymmetric(MPI_Comm comm, PC pc, DM da, Vec x, const PetscInt n[3], component::Random &rnd, const char *like)
{
  Vec                    u, v, pu, pv;
  PetscReal              upv, vpu, nu, npv;
  std::vector<PetscReal> field((std::size_t)(n[0] * n[1] * n[2]));

  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(x, &u));
  PetscCall(VecDuplicate(x, &v));
  PetscCall(VecDuplicate(x, &pu));
  PetscCall(VecDuplicate(x, &pv));
  for (PetscReal &q : field) q = 2 * rnd.Uniform() - 1;
  PetscCall(SetByNaturalIndex(da, u, n, [&](PetscInt q) { return field[(std::size_t)q]; }));
  for (PetscReal &q : field) q = 2 * rnd.Uniform() - 1;
  PetscCall(SetByNaturalIndex(da, v, n, [&](PetscInt q) { return field[(std::size_t)q]; }));
  PetscCall(PCApply(pc, u, pu));
  PetscCall(PCApply(pc, v, pv));
  PetscCall(VecDot(u, pv, &upv));
  PetscCall(VecDot(v, pu, &vpu));
  PetscCall(VecNorm(u, NORM_2, &nu));
  PetscCall(VecNorm(pv, NORM_2, &npv));
  PetscCall(PetscPrintf(comm, "%s: u . PC(v) = %.15g, v . PC(u) = %.15g\n", like, (double)upv, (double)vpu));
  PetscCall(Check(comm, std::fabs(upv - vpu) <= 1e-12 * nu * npv, "  the PC is symmetric to 1e-12", 0));
  PetscCall(VecDestroy(&u));
  PetscCall(VecDestroy(&v));
  PetscCall(VecDestroy(&pu));
  PetscCall(VecDestroy(&pv));
  PetscFunctionReturn(0);
}

} // namespace

int main(int argc, char **argv)
{
  component::GasScene sc;
  PetscBool           varying = PETSC_FALSE, contrast = PETSC_FALSE;
  PetscInt            max_its = 30;
  DM                  da_s, da_v;
  Mat                 A;
  PC                  pc;
  Vec                 x, b, y, d;
  PetscReal           w[3];
  PetscInt            n[3] = {1, 1, 1};

  PetscCall(PetscInitialize(&argc, &argv, NULL, help));
  PetscCall(PetscOptionsGetBool(NULL, NULL, "-varying", &varying, NULL));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-max_its", &max_its, NULL));
  PetscCall(PetscOptionsGetBool(NULL, NULL, "-contrast", &contrast, NULL));
  varying = (PetscBool)(varying || contrast);
  PetscCall(component::GasSceneCreate(PETSC_COMM_WORLD, &sc));
  const MPI_Comm comm  = sc.comm;
  const Domain  &dom   = sc.dom;
  const Grids   &grids = sc.grids;
  Fluid         *fluid = sc.fluid;
  PetscReal      h[3];
  for (int a = 0; a < 3; ++a) {
    n[a] = a < dom.dim ? grids.fluid.n[a] : 1;
    h[a] = a < dom.dim ? grids.fluid.h[a] : dom.len[2];
  }
  for (int a = 0; a < 3; ++a) w[a] = h[(a + 1) % 3] * h[(a + 2) % 3] / h[a];
  const PetscBool outlet = (PetscBool)!std::strcmp(FluidBoundaryType(fluid, FACE_YHI), "pressure");
  PetscCall(FluidGetCellDMs(fluid, &da_s, &da_v));
  PetscCall(FluidGetPressureMatrix(fluid, &A));
  PetscCall(PetscPrintf(comm, "%dD grid %d x %d x %d, top %s, periodic %s%s%s\n", (int)dom.dim, (int)n[0], (int)n[1], (int)n[2],
                        FluidBoundaryType(fluid, FACE_YHI), dom.periodic[0] ? "x" : "", dom.periodic[1] ? "y" : "",
                        dom.periodic[2] ? "z" : ""));

  PetscCall(FastPoissonRegister());
  PetscCall(PCCreate(comm, &pc));
  PetscCall(PCSetType(pc, PCFASTPOISSON));
  PetscCall(PCFastPoissonSetGrid(pc, da_s, w, outlet));
  PetscCall(PCSetOperators(pc, A, A));
  PetscCall(PCSetUp(pc));
  PetscCall(DMCreateGlobalVector(da_s, &x));
  PetscCall(VecDuplicate(x, &b));
  PetscCall(VecDuplicate(x, &y));
  PetscCall(VecDuplicate(x, &d));

  // exactness on the set-up operator
  component::Random      rnd(11);
  std::vector<PetscReal> field((std::size_t)(n[0] * n[1] * n[2]));
  for (PetscReal &v : field) v = 2 * rnd.Uniform() - 1;
  PetscCall(SetByNaturalIndex(da_s, x, n, [&](PetscInt q) { return field[(std::size_t)q]; }));
  PetscCall(MatMult(A, x, b));
  PetscCall(PCApply(pc, b, y));
  PetscReal xmax, dmax, mean;
  PetscCall(LargestDifference(x, y, outlet, d, &dmax, &mean));
  PetscCall(VecNorm(x, NORM_INFINITY, &xmax));
  PetscCall(
    PetscPrintf(comm, "PC(A x) - x: largest %.3g of max |x| (after removing the constant %.3g)\n", (double)(dmax / xmax), (double)mean));
  PetscCall(Check(comm, dmax <= 1e-10 * xmax, "  PC(A x) = x to 1e-10 with a constant face coefficient", 0));

  // symmetry on two fields
  PetscCall(CheckSymmetric(comm, pc, da_s, x, n, rnd, "the inverse"));
  PetscCall(PCDestroy(&pc));

  if (varying) {
    // after a gas step with a packed lower half and an implicit drag the face coefficients vary (model B: c_f = eps_f /
    // (eps_f + dt beta_f / rho), 0.4 / 2.07 below against 1 above): CG + fastpoisson solves A x = A x_ref to rtol 1e-10.
    // With -contrast every seventh packed cell sits at the floor, eps 0.05, with dt beta / rho = 10 (c_f about 0.005).
    const PetscReal dt = 1e-4;
    PetscReal       rho, mu;
    Vec             eps, beta;
    PetscCall(FluidGetGasProperties(fluid, &rho, &mu));
    PetscCall(FluidGetVoidFraction(fluid, &eps));
    PetscCall(FluidGetDragCoefficient(fluid, &beta));
    auto packed = [&](PetscInt q) { return (q / n[0]) % n[1] < n[1] / 2; };
    auto floor  = [&](PetscInt q) { return contrast && packed(q) && q % 7 == 3; };
    PetscCall(SetByNaturalIndex(da_s, eps, n, [&](PetscInt q) { return floor(q) ? 0.05 : packed(q) ? 0.4 : 1.0; }));
    PetscCall(SetByNaturalIndex(da_s, beta, n, [&](PetscInt q) { return floor(q) ? 10 * rho / dt : packed(q) ? 2.0e4 : 0.0; }));
    PetscCall(FluidStep(fluid, dt));
    PetscCall(FluidGetPressureMatrix(fluid, &A));
    PetscInt its_alone = 0;
    for (int jacobi = 0; jacobi < (contrast ? 2 : 1); ++jacobi) {
      KSP       ksp;
      PetscInt  its;
      PetscReal emax;
      PetscCall(KSPCreate(comm, &ksp));
      PetscCall(KSPSetOptionsPrefix(ksp, jacobi ? "test_jacobi_" : "test_alone_"));
      PetscCall(PetscOptionsSetValue(NULL, "-test_jacobi_pc_fastpoisson_jacobi", "1"));
      PetscCall(PetscOptionsSetValue(NULL, "-test_alone_pc_fastpoisson_jacobi", "0")); // not on by the contrast
      PetscCall(KSPSetType(ksp, KSPCG));
      PetscCall(KSPGetPC(ksp, &pc));
      PetscCall(PCSetType(pc, PCFASTPOISSON));
      PetscCall(PCFastPoissonSetGrid(pc, da_s, w, outlet));
      PetscCall(KSPSetOperators(ksp, A, A));
      PetscCall(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED));
      PetscCall(KSPSetTolerances(ksp, 1e-10, PETSC_DEFAULT, PETSC_DEFAULT, 1000));
      PetscCall(KSPSetComputeSingularValues(ksp, PETSC_TRUE)); // before the set-up, which sizes CG's Lanczos arrays
      PetscCall(KSPSetFromOptions(ksp));
      if (jacobi) { // the Jacobi steps keep the PC symmetric on the jumping operator
        Vec       v, pv;
        PetscReal npv;
        PetscCall(KSPSetUp(ksp));
        PetscCall(CheckSymmetric(comm, pc, da_s, x, n, rnd, "with Jacobi steps"));
        PetscCall(VecDuplicate(x, &v));
        PetscCall(VecDuplicate(x, &pv));
        // positive on the checkerboard, which an undamped Jacobi step sends to minus itself (D^-1 A v = 2 v on a walled
        // grid: every neighbour has the other sign); the weight 2/3 keeps the smoother's part 2S - SAS positive there
        PetscReal vpv, vv;
        PetscCall(SetByNaturalIndex(da_s, v, n, [&](PetscInt q) {
          const PetscInt i = q % n[0], j = (q / n[0]) % n[1], k = q / (n[0] * n[1]);
          return (i + j + k) % 2 ? 1.0 : -1.0;
        }));
        PetscCall(PCApply(pc, v, pv));
        PetscCall(VecDot(v, pv, &vpv));
        PetscCall(VecNorm(pv, NORM_2, &npv));
        PetscCall(VecNorm(v, NORM_2, &vv));
        PetscCall(PetscPrintf(comm, "checkerboard v: v . PC(v) = %.6g of |v| |PC(v)|\n", (double)(vpv / (vv * npv))));
        PetscCall(Check(comm, vpv > 0.05 * vv * npv,
                        "  the PC with Jacobi steps is positive on the checkerboard (v . PC(v) > 0.05 |v| |PC(v)|)", 0));
        PetscCall(VecDestroy(&v));
        PetscCall(VecDestroy(&pv));
      }
      PetscCall(MatMult(A, x, b));
      PetscCall(VecZeroEntries(y));
      PetscCall(KSPSolve(ksp, b, y));
      PetscCall(KSPGetIterationNumber(ksp, &its));
      KSPConvergedReason reason;
      PetscReal          lmax, lmin; // CG's Lanczos estimates of the preconditioned operator's extreme eigenvalues
      PetscCall(KSPGetConvergedReason(ksp, &reason));
      PetscCall(KSPComputeExtremeSingularValues(ksp, &lmax, &lmin));
      PetscCall(PetscPrintf(comm, "  converged reason %s, eigenvalues of PC A in [%.4g, %.4g]\n", KSPConvergedReasons[reason], (double)lmin,
                            (double)lmax));
      PetscCall(Check(comm, reason > 0 && lmin > 0, "  CG converges and PC A is positive definite", (PetscInt)reason));
      PetscCall(LargestDifference(x, y, outlet, d, &emax, &mean));
      PetscCall(PetscPrintf(comm, "%s face coefficients, %s: %d CG iterations to 1e-10, largest error %.3g of max |x|\n",
                            contrast ? "jumping (0.005 at the floor cells, 0.19 packed, 1 above)" : "varying (0.19 below, 1 above)",
                            jacobi ? "inverse between Jacobi steps" : "inverse alone", (int)its, (double)(emax / xmax)));
      if (!contrast || jacobi) PetscCall(Check(comm, its <= max_its, "  CG + fastpoisson converges within -max_its", its));
      if (jacobi) PetscCall(Check(comm, its < its_alone, "  in fewer iterations than with the inverse alone", its));
      PetscCall(Check(comm, emax <= 1e-7 * xmax, "  and recovers x to 1e-7", 0));
      its_alone = its;
      PetscCall(KSPDestroy(&ksp));
    }
    { // unset, the Jacobi steps follow the contrast: on with the floor cells (about 15 here), off for the packed half alone (3.4)
      PetscBool is_fp;
      PetscInt  setups, jacobi_setups;
      PetscReal contrast_max;
      PetscCall(PCCreate(comm, &pc));
      PetscCall(PCSetType(pc, PCFASTPOISSON));
      PetscCall(PCFastPoissonSetGrid(pc, da_s, w, outlet));
      PetscCall(PCSetOperators(pc, A, A));
      PetscCall(PCSetFromOptions(pc));
      PetscCall(PCSetUp(pc));
      PetscCall(PCFastPoissonGetStats(pc, &is_fp, &setups, &jacobi_setups, &contrast_max));
      PetscCall(PetscPrintf(comm, "by default: contrast %.4g, Jacobi steps %s\n", (double)contrast_max, jacobi_setups ? "on" : "off"));
      PetscCall(Check(comm, is_fp && setups == 1 && (jacobi_setups == 1) == (bool)contrast,
                      contrast ? "  the contrast turns the Jacobi steps on" : "  without floor cells the Jacobi steps stay off",
                      jacobi_setups));
      PetscCall(PCDestroy(&pc));
    }
  }

  PetscCall(VecDestroy(&x));
  PetscCall(VecDestroy(&b));
  PetscCall(VecDestroy(&y));
  PetscCall(VecDestroy(&d));
  PetscCall(component::GasSceneDestroy(&sc));
  PetscCall(PetscFinalize());
  return 0;
}
