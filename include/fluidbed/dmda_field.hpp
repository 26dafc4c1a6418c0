// The DMDA plumbing every grid module shares (core layer: includes nothing of fluidbed): one creation of a 2D or
// 3D DMDA with a given process grid and ownership (the aligned fine and coarse grids of the two-grid method
// differ only in these), and one view of a DMDA vector's array addressed by global cell index.
#pragma once

#include <petscdmda.h>

namespace fluidbed {

// A DMDA array (global or ghosted local) addressed by global (i, j, k, component), in 2D with k = 0; a thin view
// on the vector's array.
struct DMDAField {
  PetscScalar *a = nullptr;
  PetscInt     s[3]{0, 0, 0}, m[3]{1, 1, 1}, dof = 1;

  PetscScalar &operator()(PetscInt i, PetscInt j, PetscInt k, PetscInt c = 0) const
  {
    return a[(((k - s[2]) * m[1] + (j - s[1])) * m[0] + (i - s[0])) * dof + c];
  }
  PetscScalar &at(const PetscInt p[3], PetscInt c = 0) const { return (*this)(p[0], p[1], p[2], c); }
  // Offset of cell (i, j, k) counted in cells (entry c of it: a[cell * dof + c]), and the offset between neighbours
  // along direction d: loops over cells step through the array with these instead of recomputing every index.
  PetscInt cell(PetscInt i, PetscInt j, PetscInt k) const { return ((k - s[2]) * m[1] + (j - s[1])) * m[0] + (i - s[0]); }
  PetscInt stride(int d) const { return d == 0 ? 1 : (d == 1 ? m[0] : m[0] * m[1]); }
  // Whether global cell c lies in the view's box.
  bool Contains(const PetscInt c[3]) const
  {
    for (int d = 0; d < 3; ++d)
      if (c[d] < s[d] || c[d] >= s[d] + m[d]) return false;
    return true;
  }
};

// The view of v (a vector of dm; ghosted: a local vector over the ghost corners) and its release.
PetscErrorCode DMDAFieldGet(DM dm, Vec v, PetscBool ghosted, DMDAField *view);
PetscErrorCode DMDAFieldRestore(Vec v, DMDAField *view);

// A set-up 2D (dim 2: the third entries are ignored) or 3D DMDA of N cells with the process grid procs and the
// cells per rank own[a] (NULL entries: PETSc's split), dof components and stencil width sw.
PetscErrorCode DMDACreateLayout(MPI_Comm comm, PetscInt dim, const DMBoundaryType bt[3], DMDAStencilType st, const PetscInt N[3],
                                const PetscInt procs[3], const PetscInt *const own[3], PetscInt dof, PetscInt sw, DM *da);

} // namespace fluidbed
