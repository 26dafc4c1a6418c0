// fluidbed: CFD-DEM for fluidized and spouted beds, driven by PETSc options. Run with -help for every option.
#include "fluidbed/simulation.hpp"

static const char help[] =
  "fluidbed: soft-sphere DEM (and, with the gas on, CFD-DEM with a two-grid coupling) for fluidized and spouted beds.\n"
  "A scene is a set of PETSc options: -options_file examples/<scene>.opts, the command line, or PETSC_OPTIONS.\n"
  "Without options it runs a small default scene.\n\n";

namespace {

// Errors caused by the input (out-of-range or inconsistent options) get one clear line instead of a traceback.
bool IsInputError(PetscErrorCode n)
{
  return n == PETSC_ERR_ARG_OUTOFRANGE || n == PETSC_ERR_USER_INPUT || n == PETSC_ERR_ARG_WRONG || n == PETSC_ERR_USER ||
         n == PETSC_ERR_FILE_OPEN;
}

PetscErrorCode InputErrorHandler(MPI_Comm comm, int line, const char *func, const char *file, PetscErrorCode n, PetscErrorType p,
                                 const char *mess, void *ctx)
{
  if (p == PETSC_ERROR_INITIAL && IsInputError(n)) {
    PetscMPIInt rank = 0;
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank); // options errors are raised on every rank: print once
    if (!rank) fprintf(stderr, "fluidbed: error: %s\n", mess);
    return n;
  }
  if (p == PETSC_ERROR_REPEAT && IsInputError(n)) return n; // already reported
  return PetscTraceBackErrorHandler(comm, line, func, file, n, p, mess, ctx);
}

PetscErrorCode Run()
{
  fluidbed::Simulation *sim = nullptr;

  PetscFunctionBeginUser;
  PetscCall(fluidbed::SimulationCreate(PETSC_COMM_WORLD, &sim));
  PetscCall(fluidbed::SimulationSetUp(sim));
  PetscCall(fluidbed::SimulationRun(sim));
  PetscCall(fluidbed::SimulationDestroy(&sim));
  PetscFunctionReturn(0);
}

} // namespace

int main(int argc, char **argv)
{
  PetscCall(PetscInitialize(&argc, &argv, NULL, help));
  PetscCall(PetscPushErrorHandler(InputErrorHandler, NULL));
  const PetscErrorCode ierr = Run();
  if (ierr && ierr != PETSC_ERR_FILE_OPEN && IsInputError(ierr)) {
    // Options are read identically on every rank, so every rank stops here: finish cleanly with a nonzero status.
    PetscCall(PetscFinalize());
    return 2;
  }
  if (ierr) PETSCABORT(PETSC_COMM_WORLD, ierr);
  PetscCall(PetscFinalize());
  return 0;
}
