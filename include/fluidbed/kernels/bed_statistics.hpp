// Per-cell particle statistics of a bed: instantaneous sums, the quantities of seed chapters 3-5 built from them
// (solid fraction, cell-average particle velocity, granular temperature), their time average, and profiles.
//
// Building blocks for the solver's plumbing: every per-cell record is a standard-layout struct of doubles, so an
// array of them is a DMDA array with that many dof (kCellSumsDof, kCellAverageSumsDof, kCellMeansDof), and
// every sum is additive: sums of particle subsets (ranks, batches) add up to the sums of the whole, and per-layer
// sums of a rank's block reduce with MPI_SUM. See docs/analysis.md.
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "fluidbed/kernels/cell_grid.hpp"
#include "fluidbed/kernels/vec3.hpp"

namespace fluidbed::kernels {

// ---------------------------------------------------------------------------------------------------------
// Particles as plain arrays.

// The particles of one snapshot, not owned. Positions are read with stride x_stride (a DMSwarm's coordinates
// have dim components per particle), velocities with stride v_stride (3 in the solver's swarm; the first
// dim components are read). Diameters come from d, or from `diameter` for every particle when d is null.
struct ParticleView {
  std::size_t   n        = 0;
  const double *x        = nullptr;
  int           x_stride = 3;
  const double *v        = nullptr;
  int           v_stride = 3;
  const double *d        = nullptr;
  double        diameter = 0.0; // m, used when d == nullptr
};

inline double sphere_volume(double d)
{
  return (M_PI / 6.0) * d * d * d;
}

// ---------------------------------------------------------------------------------------------------------
// Instantaneous per-cell sums.

// Sums over the particles whose centre lies in a cell (each particle's whole volume counts for that cell, as in
// eq. 5.2). Velocity components beyond dim stay zero.
struct CellSums {
  double count        = 0.0;                      // N
  double solid_volume = 0.0;                      // sum V_p, m^3
  double mass         = 0.0;                      // sum m_p, kg
  double velocity[3]{0.0, 0.0, 0.0};              // sum v_p, m/s
  double velocity_sq[3]{0.0, 0.0, 0.0};           // sum v_p,i^2 per component, m^2/s^2
  double solid_volume_velocity[3]{0.0, 0.0, 0.0}; // sum V_p v_p, m^4/s: the cell's solid volume flux times V_cell
};
constexpr int kCellSumsDof = 12;
static_assert(sizeof(CellSums) == kCellSumsDof * sizeof(double), "CellSums must be a flat record of doubles");

inline CellSums &operator+=(CellSums &a, const CellSums &b)
{
  a.count += b.count;
  a.solid_volume += b.solid_volume;
  a.mass += b.mass;
  for (int c = 0; c < 3; ++c) {
    a.velocity[c] += b.velocity[c];
    a.velocity_sq[c] += b.velocity_sq[c];
    a.solid_volume_velocity[c] += b.solid_volume_velocity[c];
  }
  return a;
}

// Adds the particles of p to sums[cell_of_point(g, x_p)] (cell_count(g) entries, not cleared first: call it for
// several particle sets to sum them). Particles outside the grid are clamped into the boundary cells, so on a
// rank's block pass only the particles the rank owns. rho_p is the particle density (kg/m^3).
inline void add_particles_to_cells(const CellGrid &g, const ParticleView &p, double rho_p, CellSums *sums)
{
  for (std::size_t q = 0; q < p.n; ++q) {
    const double *xq = p.x + q * p.x_stride;
    const double *vq = p.v + q * p.v_stride;
    const double  vp = sphere_volume(p.d ? p.d[q] : p.diameter);
    CellSums     &s  = sums[cell_of_point(g, xq)];
    s.count += 1.0;
    s.solid_volume += vp;
    s.mass += rho_p * vp;
    for (int c = 0; c < g.dim; ++c) {
      s.velocity[c] += vq[c];
      s.velocity_sq[c] += vq[c] * vq[c];
      s.solid_volume_velocity[c] += vp * vq[c];
    }
  }
}

inline std::vector<CellSums> cell_sums(const CellGrid &g, const ParticleView &p, double rho_p)
{
  std::vector<CellSums> sums(static_cast<std::size_t>(cell_count(g)));
  add_particles_to_cells(g, p, rho_p, sums.data());
  return sums;
}

// Solid volume fraction of a cell, eq. 5.2: eps_s = sum V_p / V_cell.
inline double solid_fraction(const CellSums &s, double cell_volume)
{
  return s.solid_volume / cell_volume;
}

// Gas volume fraction, eq. 5.3: eps = 1 - eps_s.
inline double void_fraction(const CellSums &s, double cell_volume)
{
  return 1.0 - solid_fraction(s, cell_volume);
}

// Number-average particle velocity of a cell, eq. 4.3: V_av = sum v_p / N; zero in an empty cell.
inline Vec3 mean_velocity(const CellSums &s)
{
  if (!(s.count > 0.0)) return {};
  return {s.velocity[0] / s.count, s.velocity[1] / s.count, s.velocity[2] / s.count};
}

// Granular temperature needs at least two particles in a cell: with one particle C = 0 identically, which says
// nothing about the fluctuations. Callers may ask for more (a noisy estimate from a few particles).
constexpr double kMinParticlesForTemperature = 2.0;

inline bool has_granular_temperature(const CellSums &s, double min_count = kMinParticlesForTemperature)
{
  return s.count >= min_count && s.count >= 2.0;
}

// Granular temperature of a cell, eq. 3.4: theta = (1/n) (1/N) sum_p |C_p|^2 with C_p = v_p - V_av the particle's
// fluctuation about the cell's average velocity and n = dim (only the first dim components count). Divided by N
// as in the seed (not N - 1). Computed from the sums as (1/(n N)) sum_i (sum v_i^2 - (sum v_i)^2 / N), clamped at
// zero; the round-off is about 1e-16 |V_av|^2 absolute. Returns 0 where has_granular_temperature() is false
// (fewer than min_count particles): the caller keeps those cells out of averages.
inline double granular_temperature(const CellSums &s, int dim, double min_count = kMinParticlesForTemperature)
{
  if (!has_granular_temperature(s, min_count)) return 0.0;
  double c2 = 0.0;
  for (int c = 0; c < dim; ++c) c2 += s.velocity_sq[c] - s.velocity[c] * s.velocity[c] / s.count;
  return c2 > 0.0 ? c2 / (dim * s.count) : 0.0;
}

// ---------------------------------------------------------------------------------------------------------
// Time averages over a window of snapshots.

// Weighted sums over the samples of a window, per cell. Each sample enters with a weight w (1 for samples at
// equal intervals; the time the sample stands for otherwise); the window's total weight is kept once per
// window, not per cell (TimeAverage::weight).
struct CellAverageSums {
  double solid_fraction = 0.0;         // sum w eps_s
  double count          = 0.0;         // sum w N
  double velocity[3]{0.0, 0.0, 0.0};   // sum w sum_p v_p
  double solid_flux[3]{0.0, 0.0, 0.0}; // sum w (sum_p V_p v_p) / V_cell: the solid volume flux eps_s v, m/s
  double granular_temperature = 0.0;   // sum w theta over the samples where theta is defined
  double temperature_weight   = 0.0;   // sum w over those samples
};
constexpr int kCellAverageSumsDof = 10;
static_assert(sizeof(CellAverageSums) == kCellAverageSumsDof * sizeof(double), "CellAverageSums must be a flat record of doubles");

inline CellAverageSums &operator+=(CellAverageSums &a, const CellAverageSums &b)
{
  a.solid_fraction += b.solid_fraction;
  a.count += b.count;
  for (int c = 0; c < 3; ++c) {
    a.velocity[c] += b.velocity[c];
    a.solid_flux[c] += b.solid_flux[c];
  }
  a.granular_temperature += b.granular_temperature;
  a.temperature_weight += b.temperature_weight;
  return a;
}

// Adds one snapshot's sums of a cell with weight w.
inline void add_sample(CellAverageSums &a, const CellSums &s, double cell_volume, int dim, double w = 1.0,
                       double min_count = kMinParticlesForTemperature)
{
  a.solid_fraction += w * solid_fraction(s, cell_volume);
  a.count += w * s.count;
  for (int c = 0; c < 3; ++c) {
    a.velocity[c] += w * s.velocity[c];
    a.solid_flux[c] += w * s.solid_volume_velocity[c] / cell_volume;
  }
  if (has_granular_temperature(s, min_count)) {
    a.granular_temperature += w * granular_temperature(s, dim, min_count);
    a.temperature_weight += w;
  }
}

// The time-averaged fields of a cell.
struct CellMeans {
  double solid_fraction = 0.0;       // <eps_s>: the mean over the window's samples
  Vec3   velocity;                   // sum v_p / sum N over the window (eq. 4.3 over the window); zero if no particle came
  double granular_temperature = 0.0; // mean theta over the samples where it was defined; zero if it never was
  double temperature_coverage = 0.0; // fraction of the window (by weight) in which theta was defined
  Vec3   solid_flux;                 // <eps_s v>: the exact mean solid volume flux (m/s); rho_p times it is the mass flux
};
constexpr int kCellMeansDof = 9;
static_assert(sizeof(CellMeans) == kCellMeansDof * sizeof(double), "CellMeans must be a flat record of doubles");

// Means of a cell's sums over a window of total weight window_weight (the number of samples when every weight is 1).
inline CellMeans cell_means(const CellAverageSums &a, double window_weight)
{
  CellMeans m;
  if (!(window_weight > 0.0)) return m;
  m.solid_fraction = a.solid_fraction / window_weight;
  if (a.count > 0.0) m.velocity = {a.velocity[0] / a.count, a.velocity[1] / a.count, a.velocity[2] / a.count};
  if (a.temperature_weight > 0.0) m.granular_temperature = a.granular_temperature / a.temperature_weight;
  m.temperature_coverage = a.temperature_weight / window_weight;
  m.solid_flux           = {a.solid_flux[0] / window_weight, a.solid_flux[1] / window_weight, a.solid_flux[2] / window_weight};
  return m;
}

// A window's accumulator: plain data (a sample counter, the total weight and one CellAverageSums per cell), so the
// plumbing can keep the per-cell sums in a PETSc Vec and the two scalars in a checkpoint.
struct TimeAverage {
  CellGrid                     grid;
  long                         samples = 0;   // snapshots added
  double                       weight  = 0.0; // their total weight
  std::vector<CellAverageSums> cells;
};

inline TimeAverage time_average(const CellGrid &g)
{
  TimeAverage t;
  t.grid = g;
  t.cells.assign(static_cast<std::size_t>(cell_count(g)), CellAverageSums{});
  return t;
}

// Adds one snapshot (cell_count(grid) sums) with weight w.
inline void add_sample(TimeAverage &t, const CellSums *sums, double w = 1.0, double min_count = kMinParticlesForTemperature)
{
  const double vc = cell_volume(t.grid);
  for (std::size_t c = 0; c < t.cells.size(); ++c) add_sample(t.cells[c], sums[c], vc, t.grid.dim, w, min_count);
  t.samples += 1;
  t.weight += w;
}

inline std::vector<CellMeans> cell_means(const TimeAverage &t)
{
  std::vector<CellMeans> m(t.cells.size());
  for (std::size_t c = 0; c < t.cells.size(); ++c) m[c] = cell_means(t.cells[c], t.weight);
  return m;
}

// Instantaneous fields as CellMeans (a window of one sample), for measures applied to a single snapshot.
inline std::vector<CellMeans> snapshot_fields(const CellGrid &g, const CellSums *sums, double min_count = kMinParticlesForTemperature)
{
  std::vector<CellMeans> m(static_cast<std::size_t>(cell_count(g)));
  const double           vc = cell_volume(g);
  for (std::size_t c = 0; c < m.size(); ++c) {
    CellAverageSums a;
    add_sample(a, sums[c], vc, g.dim, 1.0, min_count);
    m[c] = cell_means(a, 1.0);
  }
  return m;
}

// ---------------------------------------------------------------------------------------------------------
// Profiles of a per-cell field. `field` is any callable double(long cell), e.g.
// [&](long c) { return means[c].velocity.y; }.

// Sum of the field over each layer (n_y entries). On a rank's block these are partial sums: reduce them with
// MPI_SUM over the ranks that share the layers and divide by the global cells_per_layer.
template <class Field>
std::vector<double> layer_sums(const CellGrid &g, Field field)
{
  std::vector<double> s(static_cast<std::size_t>(g.n[1]), 0.0);
  for (int k = 0; k < g.n[2]; ++k)
    for (int j = 0; j < g.n[1]; ++j)
      for (int i = 0; i < g.n[0]; ++i) s[j] += field(cell_index(g, i, j, k));
  return s;
}

// Cross-section-averaged profile along y: the mean of the field over the n_x n_z cells of each layer (all cells
// have the same area, so this is the area average), at heights layer_centre_height(g, j).
template <class Field>
std::vector<double> cross_section_profile(const CellGrid &g, Field field)
{
  std::vector<double> s = layer_sums(g, field);
  for (double &v : s) v /= static_cast<double>(cells_per_layer(g));
  return s;
}

// Horizontal profile in layer j: n_x values at x = cell_centre(g, 0, i), each the mean over z (in 3D) of the
// field. In 2D the single cell.
template <class Field>
std::vector<double> layer_profile(const CellGrid &g, int j, Field field)
{
  std::vector<double> p(static_cast<std::size_t>(g.n[0]), 0.0);
  for (int k = 0; k < g.n[2]; ++k)
    for (int i = 0; i < g.n[0]; ++i) p[i] += field(cell_index(g, i, j, k));
  for (double &v : p) v /= g.n[2];
  return p;
}

// Horizontal profile at a height above the grid bottom: the layer holding that height (clamped), as the seed's
// profiles "at y = 10, 30, 60 mm" are the cell values there.
template <class Field>
std::vector<double> horizontal_profile(const CellGrid &g, double height, Field field)
{
  return layer_profile(g, layer_of_height(g, height), field);
}

// Vertical profile in the column holding coordinate x (clamped): n_y values at layer_centre_height(g, j), each
// the mean over z (in 3D), e.g. the seed's variation with height at the jet centre (Fig. 3.10).
template <class Field>
std::vector<double> vertical_profile(const CellGrid &g, double x, Field field)
{
  const int           i = axis_cell(g, 0, x);
  std::vector<double> p(static_cast<std::size_t>(g.n[1]), 0.0);
  for (int k = 0; k < g.n[2]; ++k)
    for (int j = 0; j < g.n[1]; ++j) p[j] += field(cell_index(g, i, j, k));
  for (double &v : p) v /= g.n[2];
  return p;
}

// Value of a per-layer profile (n_y values at the layer centres) at a height above the grid bottom: linear between
// centres, and in the half layers beyond the first and last centres the line through the two nearest centres (so
// that the pressure at the distributor or at the outlet carries the gradient of the layers next to it, rather than
// the value half a cell away); heights outside the grid take the value at its bottom or top face.
inline double interpolate_profile(const CellGrid &g, const std::vector<double> &profile, double height)
{
  const std::size_t n = profile.size();
  if (n < 2) return profile.front();
  // position in layers above the first centre, held to the grid: -0.5 at its bottom face, n - 0.5 at its top face
  const double      s = std::min(std::max(height / g.h[1] - 0.5, -0.5), static_cast<double>(n) - 0.5);
  const std::size_t j = s <= 0.0 ? 0 : std::min(static_cast<std::size_t>(std::floor(s)), n - 2);
  const double      w = s - static_cast<double>(j);
  return (1.0 - w) * profile[j] + w * profile[j + 1];
}

} // namespace fluidbed::kernels
