// Decision rules of the run-time guards (src/guards): when a measured figure counts as a failure. Free of PETSc so
// that the unit tests call them directly; docs/reliability.md gives each guard's default limit and why.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace fluidbed::kernels {

// A limit that only counts as broken when it is exceeded for n samples in a row. The gas Courant number of a
// coupled run exceeds 1 for a few gas steps when a jet first enters a packed bed (the implicit drag keeps those
// steps bounded); it is a failure when the gas step stays beyond the explicit limit.
struct SustainedExceedance {
  long run     = 0; // samples in a row above the limit, up to the last one
  long longest = 0; // the longest such run so far

  // Adds a sample; true when value > limit for the last n samples (n >= 1). NaN counts as above the limit.
  bool add(double value, double limit, long n)
  {
    if (!(value <= limit)) ++run;
    else run = 0;
    longest = std::max(longest, run);
    return run >= n;
  }
};

// The mechanical energy of a closed system (pure DEM: no gas, no inflow, walls at rest): kinetic + gravitational +
// the elastic energy held in the contact springs. Contacts only dissipate (e <= 1, Coulomb sliding), so the
// energy never rises above its past values beyond the integration error, which velocity Verlet keeps to a small
// fraction (docs/dem.md: about 1% over 20 bounces at t_cr/10). A step too long for the contacts feeds energy in and
// the growth is exponential.
struct EnergyWatch {
  double first = std::numeric_limits<double>::quiet_NaN(); // the first sample
  double least = std::numeric_limits<double>::infinity();  // the least sample so far

  // Adds a sample and returns the growth over the least energy seen, (E - E_min) / max(E_min, floor * E_first):
  // the floor (a fraction of the first sample) keeps a system that has nearly come to rest from reporting its
  // round-off as growth. NaN energy returns NaN.
  double add(double e, double floor = 1e-3)
  {
    if (std::isnan(first)) first = e;
    least            = std::min(least, e);
    const double ref = std::max(least, floor * std::abs(first));
    if (std::isnan(e)) return e;
    if (ref <= 0) return e > least ? std::numeric_limits<double>::infinity() : 0.0;
    return (e - least) / ref;
  }
};

// The share of cells held at the void-fraction floor, and whether the void fraction left (0, 1]: a cell whose
// particle centres hold more solid than its volume (raw void fraction <= 0) cannot be represented at all, and
// many cells at the floor mean the cells are too small for the particle-centre deposit (seed chapter 5).
struct VoidFractionVerdict {
  double share_at_floor = 0; // cells at the floor / cells
  bool   outside        = false;
};
inline VoidFractionVerdict void_fraction_verdict(double raw_min, double eps_max, long long at_floor, long long cells)
{
  VoidFractionVerdict v;
  v.share_at_floor = cells > 0 ? (double)at_floor / (double)cells : 0.0;
  v.outside        = !(raw_min > 0.0) || !(eps_max <= 1.0 + 1e-12);
  return v;
}

} // namespace fluidbed::kernels
