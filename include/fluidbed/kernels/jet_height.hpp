// Jet penetration height by first bubble detachment (seed chapter 4, "Jet Height": the height at which the
// initial bubble detaches from the jet, after Merry 1975 and Rees et al. 2006).
//
// Per snapshot, the jet is the high-voidage region (gas void fraction above a threshold) connected through cell
// faces to the jet's inlet cells on the bottom row; its height is the top of that region. Over a time series the
// region grows as a bubble forms on the jet and drops abruptly when the bubble pinches off; the jet height is the
// mean of the heights just before those drops. Heights are above the grid bottom (the distributor).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "fluidbed/kernels/cell_grid.hpp"

namespace fluidbed::kernels {

// Default void fraction above which a cell belongs to the jet or a bubble.
constexpr double kJetVoidFraction = 0.8;

// The bottom-row cells (j = 0) of a jet whose slot spans [x_lo, x_hi] x [z_lo, z_hi]: those whose centre lies in
// the slot, or, for a slot narrower than a cell, the cell holding the slot's centre. The default z range is the
// whole depth (the seed's slits run through the bed depth); z is not read in 2D.
inline std::vector<long> jet_inlet_cells(const CellGrid &g, double x_lo, double x_hi,
                                         double z_lo = -std::numeric_limits<double>::infinity(),
                                         double z_hi = std::numeric_limits<double>::infinity())
{
  auto range = [&](int axis, double a, double b, int &first, int &last) {
    first = g.n[axis];
    last  = -1;
    for (int i = 0; i < g.n[axis]; ++i) {
      const double c = cell_centre(g, axis, i);
      if (c >= a && c <= b) {
        if (i < first) first = i;
        last = i;
      }
    }
    if (last < 0) first = last = axis_cell(g, axis, 0.5 * (std::max(a, g.lo[axis]) + std::min(b, g.lo[axis] + g.n[axis] * g.h[axis])));
  };
  int i0, i1, k0 = 0, k1 = 0;
  range(0, x_lo, x_hi, i0, i1);
  if (g.dim == 3) range(2, z_lo, z_hi, k0, k1);
  std::vector<long> cells;
  for (int k = k0; k <= k1; ++k)
    for (int i = i0; i <= i1; ++i) cells.push_back(cell_index(g, i, 0, k));
  return cells;
}

// The jet region: cells with void fraction above `threshold` connected to the inlet cells through faces (4
// neighbours in 2D, 6 in 3D; corners and edges do not connect). An inlet cell at or below the threshold seeds
// nothing. Returns one flag per cell.
inline std::vector<char> jet_region(const CellGrid &g, const double *void_fraction, const std::vector<long> &inlet_cells,
                                    double threshold = kJetVoidFraction)
{
  std::vector<char> in(static_cast<std::size_t>(cell_count(g)), 0);
  std::vector<long> stack;
  for (long c : inlet_cells)
    if (void_fraction[c] > threshold && !in[c]) {
      in[c] = 1;
      stack.push_back(c);
    }
  while (!stack.empty()) {
    const long    c = stack.back();
    const CellIjk q = cell_ijk(g, c);
    stack.pop_back();
    const int nb[6][3]{{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
    for (int a = 0; a < (g.dim == 3 ? 6 : 4); ++a) {
      const int i = q.i + nb[a][0], j = q.j + nb[a][1], k = q.k + nb[a][2];
      if (i < 0 || j < 0 || k < 0 || i >= g.n[0] || j >= g.n[1] || k >= g.n[2]) continue;
      const long e = cell_index(g, i, j, k);
      if (!in[e] && void_fraction[e] > threshold) {
        in[e] = 1;
        stack.push_back(e);
      }
    }
  }
  return in;
}

// Height of the jet region in one snapshot: the highest point where the void fraction crosses the threshold on
// leaving the region upwards. For each region cell whose upper neighbour is outside the region, the crossing is
// interpolated linearly between the two cell centres, y_c + h_y (eps_c - threshold) / (eps_c - eps_above); a region
// cell in the top layer gives the grid height. Returns 0 when no inlet cell is above the threshold. A jet of
// cells with void fraction eps_j under a bed at eps_b reads the cell face exactly when threshold is halfway.
inline double jet_height(const CellGrid &g, const double *void_fraction, const std::vector<long> &inlet_cells,
                         double threshold = kJetVoidFraction)
{
  const std::vector<char> in  = jet_region(g, void_fraction, inlet_cells, threshold);
  double                  top = 0.0;
  for (long c = 0; c < cell_count(g); ++c) {
    if (!in[c]) continue;
    const CellIjk q = cell_ijk(g, c);
    double        y;
    if (q.j == g.n[1] - 1) y = grid_height(g);
    else {
      const long up = cell_index(g, q.i, q.j + 1, q.k);
      if (in[up]) continue;
      const double e = void_fraction[c], ea = void_fraction[up];
      y = layer_centre_height(g, q.j) + g.h[1] * (e - threshold) / (e - ea);
    }
    if (y > top) top = y;
  }
  return top;
}

// What counts as a detachment in a series of jet heights: a drop from one sample to the next of at least
// max(min_drop, min_relative_drop x the height before). min_drop keeps the flicker of the top cell from counting
// (two cell heights is a reasonable choice); the relative drop asks for a bubble of a quarter of the jet's length.
struct DetachmentCriterion {
  double min_drop          = 0.0;  // m
  double min_relative_drop = 0.25; // of the height before
};

struct JetDetachment {
  std::size_t sample        = 0;   // index of the last sample before the drop
  double      height_before = 0.0; // m
  double      height_after  = 0.0; // m
};

struct JetHeightSeries {
  std::vector<JetDetachment> detachments;
  double                     mean_height = 0.0; // mean of height_before over the detachments; 0 if there were none
  double                     std_dev     = 0.0; // their standard deviation (divided by the count)
};

// Detachments in a time series of jet heights (one jet_height per snapshot, samples in time order) and the jet
// height as the mean of the heights just before them. Every sample-to-sample drop that meets the criterion is one
// detachment, also right after another (a second bubble pinching off lower). Average over jets by pooling the
// detachments or by averaging the per-jet means (the seed averages its 9 jets).
inline JetHeightSeries jet_height_series(const std::vector<double> &heights, const DetachmentCriterion &crit = {})
{
  JetHeightSeries r;
  for (std::size_t t = 0; t + 1 < heights.size(); ++t) {
    const double before = heights[t], after = heights[t + 1];
    const double need = std::max(crit.min_drop, crit.min_relative_drop * before);
    if (before - after > 0.0 && before - after >= need) r.detachments.push_back({t, before, after});
  }
  if (r.detachments.empty()) return r;
  const double n = static_cast<double>(r.detachments.size());
  double       s = 0.0, s2 = 0.0;
  for (const auto &d : r.detachments) s += d.height_before;
  r.mean_height = s / n;
  for (const auto &d : r.detachments) s2 += (d.height_before - r.mean_height) * (d.height_before - r.mean_height);
  r.std_dev = std::sqrt(s2 / n);
  return r;
}

} // namespace fluidbed::kernels
