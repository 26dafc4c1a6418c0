// A uniform box of cells for measuring a bed: the fluid grid, the particle grid, or one rank's block of either.
//
// y is vertical (the distributor is the bottom face y = lo[1]), z is the depth. In 2D (dim == 2) the cells are
// one layer deep: n[2] == 1 and h[2] is the bed depth, which only enters volumes and areas. Cells are numbered
// as in a DMDA's natural ordering, x fastest, then y, then z: c = i + n[0] (j + n[1] k), so per-cell arrays
// map one to one onto a DMDA's local block when the grid describes that block.
//
// Vertical positions given to or returned by the analysis kernels are heights above the grid bottom,
// y - lo[1]; horizontal positions are coordinates.
#pragma once

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "fluidbed/kernels/vec3.hpp"

namespace fluidbed::kernels {

struct CellGrid {
  int    dim = 3;
  double lo[3]{0.0, 0.0, 0.0}; // lower corner, m
  double h[3]{1.0, 1.0, 1.0};  // cell size, m; in 2D h[2] is the bed depth
  int    n[3]{1, 1, 1};        // cells per direction; in 2D n[2] == 1
};

// The grid of nx x ny (x nz) cells covering the box [lo, hi]. In 2D nz is ignored: one layer of depth hi.z - lo.z.
inline CellGrid cell_grid(int dim, const Vec3 &lo, const Vec3 &hi, int nx, int ny, int nz = 1)
{
  if (dim != 2 && dim != 3) throw std::invalid_argument("cell_grid: dim must be 2 or 3");
  if (dim == 2) nz = 1;
  if (nx < 1 || ny < 1 || nz < 1) throw std::invalid_argument("cell_grid: every direction needs at least one cell");
  if (!(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z)) throw std::invalid_argument("cell_grid: the box must have positive extents");
  CellGrid g;
  g.dim   = dim;
  g.lo[0] = lo.x, g.lo[1] = lo.y, g.lo[2] = lo.z;
  g.n[0] = nx, g.n[1] = ny, g.n[2] = nz;
  g.h[0] = (hi.x - lo.x) / nx, g.h[1] = (hi.y - lo.y) / ny, g.h[2] = (hi.z - lo.z) / nz;
  return g;
}

inline long cell_count(const CellGrid &g)
{
  return static_cast<long>(g.n[0]) * g.n[1] * g.n[2];
}

// Cells in one horizontal layer (one height), n_x n_z.
inline long cells_per_layer(const CellGrid &g)
{
  return static_cast<long>(g.n[0]) * g.n[2];
}

inline double cell_volume(const CellGrid &g)
{
  return g.h[0] * g.h[1] * g.h[2];
}

// Area of a cell face normal to `axis` (0, 1, 2): the product of the other two cell sizes. In 2D the faces
// normal to x and y span the bed depth.
inline double face_area(const CellGrid &g, int axis)
{
  return g.h[(axis + 1) % 3] * g.h[(axis + 2) % 3];
}

// Horizontal cross-section of the grid, n_x h_x n_z h_z: the distributor area A_d (eq. 3.6-3.7) when the grid
// covers the bed.
inline double cross_section_area(const CellGrid &g)
{
  return g.n[0] * g.h[0] * g.n[2] * g.h[2];
}

inline double grid_height(const CellGrid &g)
{
  return g.n[1] * g.h[1];
}

inline long cell_index(const CellGrid &g, int i, int j, int k)
{
  return i + static_cast<long>(g.n[0]) * (j + static_cast<long>(g.n[1]) * k);
}

struct CellIjk {
  int i = 0, j = 0, k = 0;
};

inline CellIjk cell_ijk(const CellGrid &g, long c)
{
  CellIjk q;
  q.i = static_cast<int>(c % g.n[0]);
  c /= g.n[0];
  q.j = static_cast<int>(c % g.n[1]);
  q.k = static_cast<int>(c / g.n[1]);
  return q;
}

// Index along `axis` of the cell holding coordinate x, clamped to [0, n - 1] (a particle touching a wall, or a
// coordinate a round-off outside the grid, lands in the boundary cell).
inline int axis_cell(const CellGrid &g, int axis, double x)
{
  const double s = std::floor((x - g.lo[axis]) / g.h[axis]);
  if (!(s > 0.0)) return 0; // also catches NaN
  return s >= g.n[axis] - 1 ? g.n[axis] - 1 : static_cast<int>(s);
}

// Cell holding the point x (dim components: z is not read in 2D), clamped to the grid.
inline long cell_of_point(const CellGrid &g, const double *x)
{
  return cell_index(g, axis_cell(g, 0, x[0]), axis_cell(g, 1, x[1]), g.dim == 3 ? axis_cell(g, 2, x[2]) : 0);
}

inline long cell_of_point(const CellGrid &g, const Vec3 &p)
{
  const double x[3]{p.x, p.y, p.z};
  return cell_of_point(g, x);
}

// Coordinate of the centre of cell i along `axis`.
inline double cell_centre(const CellGrid &g, int axis, int i)
{
  return g.lo[axis] + (i + 0.5) * g.h[axis];
}

// Height above the grid bottom of the centre of layer j.
inline double layer_centre_height(const CellGrid &g, int j)
{
  return (j + 0.5) * g.h[1];
}

// Layer holding the height `height` above the grid bottom, clamped.
inline int layer_of_height(const CellGrid &g, double height)
{
  return axis_cell(g, 1, g.lo[1] + height);
}

} // namespace fluidbed::kernels
