// Initial particle arrangements: a lattice or a random non-overlapping fill of a box.
//
// Plain functions without MPI: every rank generates the same global list from the same seed and keeps the
// particles of its own subdomain, so the initial state (and every particle id) is independent of the number
// of ranks. The random numbers come from std::mt19937_64, whose output the C++ standard fixes, converted to
// doubles by hand (std::uniform_real_distribution differs between standard libraries).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "fluidbed/kernels/vec3.hpp"

namespace fluidbed::kernels {

struct Box {
  Vec3 lo, hi;
};

// Uniform double in [0, 1) with 53 random bits.
inline double uniform01(std::mt19937_64 &rng)
{
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

// Diameters drawn uniformly by number between dmin and dmax (dmin == dmax gives a monodisperse bed).
inline std::vector<double> draw_diameters(std::size_t n, double dmin, double dmax, std::mt19937_64 &rng)
{
  std::vector<double> d(n, dmin);
  if (dmax > dmin)
    for (auto &di : d) di = dmin + (dmax - dmin) * uniform01(rng);
  return d;
}

// Number of lattice cells of size s (>= the largest diameter) that fit in [lo, hi] along one axis; each sphere
// sits in its own cell, jitter included.
inline long lattice_count(double lo, double hi, double s)
{
  return static_cast<long>(std::floor((hi - lo) / s * (1.0 + 1e-12)));
}

// Simple-cubic lattice of cells of size `spacing`, filled from the bottom (y is vertical): x fastest, then z,
// then y, centred horizontally. In 2D (dim == 2) z is fixed at the box centre. jitter in [0, 1) moves each sphere
// randomly by up to jitter * (spacing - dmax) / 2 per axis, which keeps it inside its cell and breaks the
// lattice symmetry. Returns the first n sites, or throws when the box holds fewer.
inline std::vector<Vec3> lattice_fill(const Box &box, int dim, long n, double dmax, double spacing, double jitter, std::mt19937_64 &rng)
{
  const long nx = lattice_count(box.lo.x, box.hi.x, spacing);
  const long ny = lattice_count(box.lo.y, box.hi.y, spacing);
  const long nz = dim == 3 ? lattice_count(box.lo.z, box.hi.z, spacing) : 1;
  if (nx * ny * nz < n)
    throw std::runtime_error("the insertion region holds " + std::to_string(nx * ny * nz) + " lattice sites, fewer than the " +
                             std::to_string(n) + " particles requested");
  // centre the lattice horizontally in the region
  const double      x0  = 0.5 * (box.lo.x + box.hi.x) - 0.5 * (nx - 1) * spacing;
  const double      z0  = dim == 3 ? 0.5 * (box.lo.z + box.hi.z) - 0.5 * (nz - 1) * spacing : 0.5 * (box.lo.z + box.hi.z);
  const double      y0  = box.lo.y + 0.5 * spacing;
  const double      amp = 0.5 * jitter * (spacing - dmax);
  std::vector<Vec3> p;
  p.reserve(static_cast<std::size_t>(n));
  for (long k = 0; k < ny && static_cast<long>(p.size()) < n; ++k)
    for (long j = 0; j < nz && static_cast<long>(p.size()) < n; ++j)
      for (long i = 0; i < nx && static_cast<long>(p.size()) < n; ++i) {
        Vec3 q{x0 + i * spacing, y0 + k * spacing, z0 + (dim == 3 ? j * spacing : 0.0)};
        q.x += amp * (2.0 * uniform01(rng) - 1.0);
        q.y += amp * (2.0 * uniform01(rng) - 1.0);
        if (dim == 3) q.z += amp * (2.0 * uniform01(rng) - 1.0);
        p.push_back(q);
      }
  return p;
}

// Random sequential addition: each sphere is placed at a uniformly random point of the box where it overlaps
// no earlier sphere (gap >= min_gap), tried up to max_tries times. A hash of cells of size dmax + min_gap makes
// each test O(1). Throws when a sphere cannot be placed (the fill is near the RSA jamming limit, about 0.38 in
// 3D and 0.55 in 2D).
inline std::vector<Vec3> random_fill(const Box &box, int dim, const std::vector<double> &diam, double min_gap, std::mt19937_64 &rng,
                                     int max_tries = 2000)
{
  double dmax = 0.0;
  for (double d : diam) dmax = std::max(dmax, d);
  const double h   = dmax + min_gap;
  auto         key = [&](long i, long j, long k) {
    return (static_cast<std::int64_t>(i) * 73856093) ^ (static_cast<std::int64_t>(j) * 19349663) ^
           (static_cast<std::int64_t>(k) * 83492791);
  };
  auto cell = [&](double v, double lo) { return static_cast<long>(std::floor((v - lo) / h)); };
  std::unordered_multimap<std::int64_t, std::size_t> grid;
  grid.reserve(diam.size() * 2);
  std::vector<Vec3> p;
  p.reserve(diam.size());
  for (std::size_t n = 0; n < diam.size(); ++n) {
    const double r      = 0.5 * diam[n];
    bool         placed = false;
    for (int t = 0; t < max_tries && !placed; ++t) {
      Vec3 q{box.lo.x + r + (box.hi.x - box.lo.x - 2 * r) * uniform01(rng), box.lo.y + r + (box.hi.y - box.lo.y - 2 * r) * uniform01(rng),
             dim == 3 ? box.lo.z + r + (box.hi.z - box.lo.z - 2 * r) * uniform01(rng) : 0.5 * (box.lo.z + box.hi.z)};
      const long ci = cell(q.x, box.lo.x), cj = cell(q.y, box.lo.y), ck = dim == 3 ? cell(q.z, box.lo.z) : 0;
      bool       free = true;
      for (long a = -1; a <= 1 && free; ++a)
        for (long b = -1; b <= 1 && free; ++b)
          for (long c = (dim == 3 ? -1 : 0); c <= (dim == 3 ? 1 : 0) && free; ++c) {
            auto range = grid.equal_range(key(ci + a, cj + b, ck + c));
            for (auto it = range.first; it != range.second && free; ++it) {
              const std::size_t m    = it->second;
              const double      dmin = 0.5 * (diam[m] + diam[n]) + min_gap;
              if (norm2(p[m] - q) < dmin * dmin) free = false;
            }
          }
      if (free) {
        grid.emplace(key(ci, cj, ck), p.size());
        p.push_back(q);
        placed = true;
      }
    }
    if (!placed)
      throw std::runtime_error("random fill placed only " + std::to_string(n) + " of " + std::to_string(diam.size()) +
                               " particles: the insertion region is too small for a random fill of this many particles");
  }
  return p;
}

} // namespace fluidbed::kernels
