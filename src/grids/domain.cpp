#include "fluidbed/domain.hpp"
#include "fluidbed/options.hpp"

namespace fluidbed {

const char *const FaceNames[FACE_COUNT] = {"x-", "x+", "y- (bottom)", "y+ (top)", "z-", "z+"};

PetscErrorCode DomainSetFromOptions(MPI_Comm comm, Domain *d)
{
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, "domain_", "Domain: the bed's box (y vertical)", "Domain");
  PetscCall(OptionsInt(PetscOptionsObject, "-dim", "Spatial dimension of the grids and of particle motion", 2, 3, &d->dim, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-lx", "Bed width (x)", "m", Positive(100.0), &d->len[0], NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-ly", "Bed height (y, vertical)", "m", Positive(100.0), &d->len[1], NULL));
  PetscCall(
    OptionsReal(PetscOptionsObject, "-lz", "Bed depth (z); in 2D the depth used for cell volumes", "m", Positive(100.0), &d->len[2], NULL));
  PetscCall(OptionsBool(PetscOptionsObject, "-periodic_x", "Periodic in x (particles wrap, no side walls)", &d->periodic[0], NULL));
  PetscCall(OptionsBool(PetscOptionsObject, "-periodic_y", "Periodic in y", &d->periodic[1], NULL));
  PetscCall(OptionsBool(PetscOptionsObject, "-periodic_z", "Periodic in z (3D only)", &d->periodic[2], NULL));
  PetscCall(OptionsBool(PetscOptionsObject, "-top_outlet", "Open top: particles leaving through y = ly are removed and counted",
                        &d->top_outlet, NULL));
  PetscOptionsEnd();

  PetscOptionsBegin(comm, "", "Body force", "Domain");
  {
    PetscInt n = 3;
    PetscCall(OptionsRealArray(PetscOptionsObject, "-gravity", "Gravitational acceleration gx,gy,gz", "m/s^2", Closed(-1000.0, 1000.0),
                               d->gravity, &n, PETSC_TRUE, NULL));
  }
  PetscOptionsEnd();

  PetscCheck(!(d->periodic[1] && d->top_outlet), comm, PETSC_ERR_USER_INPUT,
             "-domain_periodic_y and -domain_top_outlet exclude each other");
  if (d->dim == 2) d->periodic[2] = PETSC_FALSE;
  for (int a = 0; a < 3; ++a) d->hi[a] = d->lo[a] + d->len[a];
  PetscFunctionReturn(0);
}

PetscErrorCode DomainView(const Domain &d, PetscViewer viewer)
{
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "Domain: %dD, %.6g x %.6g x %.6g m (y vertical)%s%s%s%s, gravity (%.6g, %.6g, %.6g) m/s^2\n",
                                   (int)d.dim, (double)d.len[0], (double)d.len[1], (double)d.len[2], d.periodic[0] ? ", periodic x" : "",
                                   d.periodic[1] ? ", periodic y" : "", d.periodic[2] ? ", periodic z" : "",
                                   d.top_outlet ? ", open top" : "", (double)d.gravity[0], (double)d.gravity[1], (double)d.gravity[2]));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
