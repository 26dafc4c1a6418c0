// Pressure systems of a running bed, written for offline solver studies (scripts/ksp_compare.py, docs/ksp.md).
//
// A frozen bed (scripts/bench_pressure.sh) shows the operator of one void-fraction field; the solver that suits a
// bed must also cope with the fields the bed goes through (bubbles, a spout, the drag of a dense bed) and with a
// preconditioner kept across steps while the matrix changes. -fluid_p_dump_interval / -fluid_p_dump_steps write,
// for selected gas steps, the matrix, the right-hand side, the initial guess, the solution, the void fraction and
// the drag coefficient that made them, in PETSc binary format and natural ordering (i fastest), so that a system
// dumped on any number of ranks loads on any other; a JSON file next to each says what it is.
#include "fluid_impl.hpp"
#include "fluidbed/files.hpp"
#include "fluidbed/options.hpp"

#include <petscdmda.h>

#include <dirent.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace fluidbed {

namespace {

constexpr PetscInt kMaxListedSteps = 1000;

std::string DumpName(PetscInt64 step, const char *ext)
{
  char buf[64];
  snprintf(buf, sizeof(buf), "pressure_step%08lld.%s", (long long)step, ext);
  return buf;
}

// A previous run's dumps in the same directory would mix with this run's: remove them (our names only) before
// the first dump, and say so.
PetscErrorCode RemovePreviousDumps(MPI_Comm comm, const std::string &dir)
{
  PetscMPIInt rank;
  int         removed = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) {
    if (DIR *d = opendir(dir.c_str())) {
      for (struct dirent *e; (e = readdir(d));) {
        const std::string name = e->d_name;
        const bool ours = name.rfind("pressure_step", 0) == 0 && (name.size() > 4 && (name.compare(name.size() - 4, 4, ".bin") == 0 ||
                                                                                      name.compare(name.size() - 5, 5, ".json") == 0 ||
                                                                                      name.compare(name.size() - 4, 4, ".tmp") == 0));
        if (ours && !unlink((dir + "/" + name).c_str())) ++removed;
      }
      closedir(d);
    }
  }
  PetscCallMPI(MPI_Bcast(&removed, 1, MPI_INT, 0, comm));
  if (removed) PetscCall(PetscPrintf(comm, "Pressure dump: removed %d file(s) of a previous run from %s\n", removed, dir.c_str()));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode FluidSetOutputDirectory(Fluid *f, const char *dir)
{
  PetscFunctionBeginUser;
  f->output_dir = dir;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidDumpSetFromOptions(Fluid *f)
{
  Fluid::Dump &d                       = f->dump;
  char         dir[PETSC_MAX_PATH_LEN] = "";
  PetscInt     steps[kMaxListedSteps] = {0}, nsteps = kMaxListedSteps; // 0 in -help: none listed
  PetscBool    set_steps = PETSC_FALSE, set_dir = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscOptionsBegin(f->comm, "fluid_p_", "Pressure systems written for solver studies (scripts/ksp_compare.py)", "Fluid");
  PetscCall(OptionsInt(PetscOptionsObject, "-dump_interval",
                       "Write the pressure system (matrix, rhs, initial guess, solution, void fraction, drag) of every N-th eligible gas "
                       "step (0: none)",
                       0, PETSC_MAX_INT, &d.interval, NULL));
  PetscCall(OptionsInt(PetscOptionsObject, "-dump_start_step", "First gas step (1-based) eligible for -fluid_p_dump_interval", 1,
                       PETSC_MAX_INT, &d.start_step, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-dump_start_time",
                        "Gas steps ending before this time are not eligible for -fluid_p_dump_interval", "s", NonNegative(1e6),
                        &d.start_time, NULL));
  PetscCall(OptionsInt(PetscOptionsObject, "-dump_count", "Most systems -fluid_p_dump_interval writes (0: no limit)", 0, PETSC_MAX_INT,
                       &d.count, NULL));
  PetscCall(
    OptionsIntArray(PetscOptionsObject, "-dump_steps",
                    "Gas steps (1-based; a-b: a to b-1, PETSc's ranges) whose pressure system is written, besides -fluid_p_dump_interval",
                    1, PETSC_MAX_INT, steps, &nsteps, &set_steps));
  PetscCall(OptionsString(PetscOptionsObject, "-dump_dir",
                          "Directory of the pressure dumps (default <-output_dir>/pressure_dump; its previous pressure_step* files are "
                          "removed at the first dump)",
                          "a directory", dir, sizeof(dir), &set_dir));
  PetscOptionsEnd();
  if (set_steps) {
    d.steps.assign(steps, steps + nsteps);
    std::sort(d.steps.begin(), d.steps.end());
  }
  if (set_dir) d.dir = dir;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidDumpBeforeSolve(Fluid *f, PetscReal dt)
{
  Fluid::Dump   &d    = f->dump;
  const PetscInt step = (PetscInt)(f->stats.steps + 1);

  PetscFunctionBeginUser;
  d.now = PETSC_FALSE;
  if (d.interval <= 0 && d.steps.empty()) PetscFunctionReturn(0);
  // Every rank holds the same step counters and gas clock, so every rank takes the same decision.
  if (d.interval > 0 && step >= d.start_step && f->time + dt >= d.start_time * (1 - 1e-12) && (d.count == 0 || d.by_interval < d.count)) {
    if (d.eligible % d.interval == 0) {
      d.now = PETSC_TRUE;
      d.by_interval++;
    }
    d.eligible++;
  }
  if (std::binary_search(d.steps.begin(), d.steps.end(), step)) d.now = PETSC_TRUE;
  if (!d.now) PetscFunctionReturn(0);
  if (!d.x0) PetscCall(VecDuplicate(f->phi, &d.x0));
  PetscCall(VecCopy(f->phi, d.x0));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidDumpAfterSolve(Fluid *f, PetscReal dt, PetscBool pc_rebuilt)
{
  Fluid::Dump &d = f->dump;
  PetscMPIInt  size;
  PetscBool    aij;
  Mat          A = f->A;
  PetscViewer  v;

  PetscFunctionBeginUser;
  if (!d.now) PetscFunctionReturn(0);
  d.now = PETSC_FALSE;
  PetscCallMPI(MPI_Comm_size(f->comm, &size));
  const std::string dir = d.dir.empty() ? f->output_dir + "/pressure_dump" : d.dir;
  if (d.written == 0) {
    PetscCall(MakeDirectory(f->comm, dir.c_str()));
    PetscCall(RemovePreviousDumps(f->comm, dir));
  }
  // PETSc's hypre structured matrix has no binary viewer: the same operator is assembled again into an AIJ matrix
  // of the same DMDA (whose viewer writes natural ordering on any number of ranks).
  PetscCall(PetscObjectTypeCompareAny((PetscObject)f->A, &aij, MATSEQAIJ, MATMPIAIJ, MATAIJ, ""));
  if (!aij) {
    if (!d.A) {
      MatType type;
      PetscCall(DMGetMatType(f->da_p, &type));
      const std::string keep = type;
      PetscCall(DMSetMatType(f->da_p, MATAIJ));
      PetscCall(DMCreateMatrix(f->da_p, &d.A));
      PetscCall(DMSetMatType(f->da_p, keep.c_str()));
    }
    PetscCall(FluidAssembleOperator(f, d.A, f->dt_last));
    A = d.A;
  }
  const PetscInt64  step = f->stats.steps + 1;
  const std::string bin = dir + "/" + DumpName(step, "bin"), json_path = dir + "/" + DumpName(step, "json");
  PetscCall(PetscObjectSetName((PetscObject)A, "pressure_matrix"));
  PetscCall(PetscObjectSetName((PetscObject)f->rhs, "rhs"));
  PetscCall(PetscObjectSetName((PetscObject)d.x0, "initial_guess"));
  PetscCall(PetscObjectSetName((PetscObject)f->phi, "solution"));
  PetscCall(PetscViewerCreate(f->comm, &v));
  PetscCall(PetscViewerSetType(v, PETSCVIEWERBINARY));
  PetscCall(PetscViewerBinarySetSkipInfo(v, PETSC_TRUE));
  PetscCall(PetscViewerFileSetMode(v, FILE_MODE_WRITE));
  PetscCall(PetscViewerFileSetName(v, (bin + ".tmp").c_str()));
  PetscCall(MatView(A, v));
  PetscCall(VecView(f->rhs, v));
  PetscCall(VecView(d.x0, v));
  PetscCall(VecView(f->phi, v));
  PetscCall(VecView(f->eps, v));
  PetscCall(VecView(f->drag, v));
  PetscCall(PetscViewerDestroy(&v));
  PetscCall(CommitFile(f->comm, bin));

  PetscReal emin, emax, esum, bmax, bnorm, x0norm;
  PetscInt  ncells;
  PetscCall(VecMin(f->eps, NULL, &emin));
  PetscCall(VecMax(f->eps, NULL, &emax));
  PetscCall(VecSum(f->eps, &esum));
  PetscCall(VecMax(f->drag, NULL, &bmax));
  PetscCall(VecNorm(f->rhs, NORM_2, &bnorm));
  PetscCall(VecNorm(d.x0, NORM_2, &x0norm));
  PetscCall(VecGetSize(f->eps, &ncells));
  const char *ktype, *ptype;
  MatType     mtype;
  PetscReal   rtol;
  PetscCall(FluidSolverNames(f, &ktype, &ptype));
  PetscCall(MatGetType(f->A, &mtype));
  PetscCall(KSPGetTolerances(f->ksp, &rtol, NULL, NULL, NULL));

  JsonWriter j;
  j.String("format", "fluidbed pressure dump 1");
  j.String("file", DumpName(step, "bin"));
  j.StringArray("objects",
                {"Mat pressure_matrix", "Vec rhs", "Vec initial_guess", "Vec solution", "Vec void_fraction", "Vec drag_coefficient"});
  j.String("ordering", "natural: cell (i, j, k) is entry i + nx (j + ny k)");
  j.String("unknown", "phi = dt p / rho (m^2/s); the matrix is the volume integral of -div(c grad phi), c the face coefficient");
  j.Integer("step", (long long)step);
  j.Number("time", (double)(f->time + dt));
  j.Number("dt", (double)dt);
  j.Number("gas_steps_per_simulated_second", (double)(1.0 / dt));
  j.Integer("dim", (long long)f->dim);
  j.IntegerArray("n", {(long long)f->n[0], (long long)f->n[1], (long long)f->n[2]});
  j.Integer("cells", (long long)ncells);
  j.NumberArray("h", {(double)f->h[0], (double)f->h[1], (double)f->h[2]});
  j.NumberArray("lo", {(double)f->dom->lo[0], (double)f->dom->lo[1], (double)f->dom->lo[2]});
  j.NumberArray("length", {(double)f->dom->len[0], (double)f->dom->len[1], (double)f->dom->len[2]});
  j.BoolArray("periodic", {(bool)f->periodic[0], (bool)f->periodic[1], (bool)f->periodic[2]});
  j.String("model", FluidModelTypes[f->model]);
  j.String("face_coefficient", f->model == FLUID_MODEL_B ? "1 (model B)" : "eps_f (model A)");
  j.Bool("implicit_drag", (bool)f->has_drag);
  j.Number("drag_coefficient_max", (double)bmax);
  j.Number("dt_of_assembly", (double)f->dt_last);
  {
    std::vector<std::string> bc;
    for (int face = 0; face < 2 * f->dim; ++face) bc.push_back(f->periodic[face / 2] ? "periodic" : FluidBCTypes[f->bc[face]]);
    j.StringArray("bc", bc); // xlo, xhi, ylo, yhi[, zlo, zhi]
  }
  j.Bool("pressure_outlet", (bool)f->has_dirichlet);
  j.Bool("constant_null_space", !f->has_dirichlet);
  j.Number("rho", (double)f->rho);
  j.Number("eps_min", (double)emin);
  j.Number("eps_max", (double)emax);
  j.Number("eps_mean", (double)(esum / ncells));
  j.Number("rhs_norm", (double)bnorm);
  j.Number("initial_guess_norm", (double)x0norm);
  j.Integer("ranks", (long long)size);
  j.IntegerArray("process_grid", {(long long)f->grid->own[0].size(), (long long)(f->dim > 1 ? f->grid->own[1].size() : 1),
                                  (long long)(f->dim > 2 ? f->grid->own[2].size() : 1)});
  j.String("run_ksp_type", ktype);
  j.String("run_pc_type", ptype);
  j.String("run_mat_type", mtype);
  j.Number("run_rtol", (double)rtol);
  j.Integer("run_pc_reuse", (long long)f->pc_reuse);
  j.Bool("run_pc_rebuilt_this_step", (bool)pc_rebuilt);
  j.Integer("run_ksp_iterations", (long long)f->stats.ksp_its);
  j.Integer("run_ksp_reason", (long long)f->stats.ksp_reason);
  j.Number("run_ksp_residual", (double)f->stats.ksp_rnorm);
  j.Number("run_ksp_time", (double)f->stats.ksp_time);
  PetscCall(JsonWrite(f->comm, json_path.c_str(), j));
  d.written++;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidDumpDestroy(Fluid *f)
{
  PetscFunctionBeginUser;
  PetscCall(MatDestroy(&f->dump.A));
  PetscCall(VecDestroy(&f->dump.x0));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
