// The bed's box, its boundaries as seen by the particles, and gravity.
//
// y is vertical, as in the seed's beds (height along y, depth along z). In 2D (-domain_dim 2) the grids and
// particle motion live in the x-y plane and the depth -domain_lz only enters cell volumes (solid fraction).
#pragma once

#include <petscviewer.h>

namespace fluidbed {

enum Face { FACE_XLO, FACE_XHI, FACE_YLO, FACE_YHI, FACE_ZLO, FACE_ZHI, FACE_COUNT };

extern const char *const FaceNames[FACE_COUNT];

struct Domain {
  PetscInt dim = 3;
  // Defaults (no scene options): a 20 x 40 x 20 mm box.
  PetscReal lo[3]{0, 0, 0};
  PetscReal hi[3]{0.02, 0.04, 0.02};
  PetscReal len[3]{0.02, 0.04, 0.02};
  PetscBool periodic[3]{PETSC_FALSE, PETSC_FALSE, PETSC_FALSE};
  PetscBool top_outlet = PETSC_FALSE; // particles leaving through y = hi[1] are removed and counted
  PetscReal gravity[3]{0.0, -9.81, 0.0};

  // A face that stops particles: not periodic, not the outlet, and inside the grid's dimension.
  bool IsParticleWall(int face) const
  {
    const int axis = face / 2;
    if (axis >= dim || periodic[axis]) return false;
    return !(face == FACE_YHI && top_outlet);
  }
  // Distance from the point x to the face's plane, positive inside the box: the gap a particle's centre keeps to a wall
  // (the contacts, their lists and the overlap diagnostics all measure it here).
  PetscReal WallGap(int face, const PetscReal x[3]) const
  {
    const int axis = face / 2;
    return (face % 2) ? hi[axis] - x[axis] : x[axis] - lo[axis];
  }
};

// Options with prefix -domain_ (dim, lx, ly, lz, periodic_x/y/z, top_outlet) and -gravity.
PetscErrorCode DomainSetFromOptions(MPI_Comm comm, Domain *domain);
PetscErrorCode DomainView(const Domain &domain, PetscViewer viewer);

} // namespace fluidbed
