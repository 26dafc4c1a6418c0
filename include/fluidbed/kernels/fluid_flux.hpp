// Gas-phase kernels (seed eq. 2.19-2.20 on a staggered grid): the TVD limiters and the limited face value of the
// convective flux, the explicit time-step limits, and the check that an inlet slit has its edges on cell faces.
// Plain functions of numbers, tested without PETSc (tests/unit/test_fluid_flux.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <vector>

namespace fluidbed::kernels {

// Flux limiters psi(r) of the TVD family, r = ratio of consecutive gradients (upwind over local). All are 0 for
// r <= 0 (first-order upwind at extrema), psi(1) = 1 (second order on smooth data) except first-order upwind, and
// lie in the TVD region 0 <= psi <= min(2r, 2).
enum class Limiter { Upwind, VanLeer, Koren, Minmod, Superbee };

template <Limiter L>
inline double limiter_psi(double r)
{
  if (!(r > 0.0)) return 0.0; // also catches NaN
  if constexpr (L == Limiter::Upwind) return 0.0;
  else if constexpr (L == Limiter::VanLeer) return 2.0 * r / (1.0 + r);
  else if constexpr (L == Limiter::Koren) return std::max(0.0, std::min({2.0 * r, (1.0 + 2.0 * r) / 3.0, 2.0}));
  else if constexpr (L == Limiter::Minmod) return std::min(r, 1.0);
  else return std::max(std::min(2.0 * r, 1.0), std::min(r, 2.0));
}

// Calls fn(std::integral_constant<Limiter, L>{}) for the limiter l chosen at run time: loops over many faces
// dispatch once here and call the templates (the results are the same bit for bit).
template <class Fn>
inline decltype(auto) with_limiter(Limiter l, Fn &&fn)
{
  switch (l) {
  case Limiter::Upwind:
    return fn(std::integral_constant<Limiter, Limiter::Upwind>{});
  case Limiter::VanLeer:
    return fn(std::integral_constant<Limiter, Limiter::VanLeer>{});
  case Limiter::Koren:
    return fn(std::integral_constant<Limiter, Limiter::Koren>{});
  case Limiter::Minmod:
    return fn(std::integral_constant<Limiter, Limiter::Minmod>{});
  default:
    return fn(std::integral_constant<Limiter, Limiter::Superbee>{});
  }
}

// The same with the limiter chosen at run time.
inline double limiter_psi(Limiter l, double r)
{
  return with_limiter(l, [r](auto lc) { return limiter_psi<decltype(lc)::value>(r); });
}

// Largest value of psi: the explicit convective limit of a limited scheme is CFL <= 1 / (1 + psi_max / 2).
inline double limiter_psi_max(Limiter l)
{
  return l == Limiter::Upwind ? 0.0 : (l == Limiter::Minmod ? 1.0 : 2.0);
}

// Value carried through a face by a flow going from cell "u" (upwind) to cell "d" (downwind); "uu" is the cell
// upwind of u. phi_f = phi_u + psi(r) (phi_d - phi_u) / 2 with r = (phi_u - phi_uu) / (phi_d - phi_u). The result
// lies between phi_u and phi_d, which bounds the scheme (no new extrema next to a 45 m/s jet in still gas).
template <Limiter L>
inline double tvd_face_value(double uu, double u, double d)
{
  const double du = d - u;
  if (du == 0.0) return u;
  return u + 0.5 * limiter_psi<L>((u - uu) / du) * du;
}
inline double tvd_face_value(Limiter l, double uu, double u, double d)
{
  const double du = d - u;
  if (du == 0.0) return u;
  return u + 0.5 * limiter_psi(l, (u - uu) / du) * du;
}

// Limited value at the face between "lo" and "hi" (lo2, hi2 the next values outward) for the volume flux F through
// it, positive from lo to hi.
template <Limiter L>
inline double upwind_face_value(double flux, double lo2, double lo, double hi, double hi2)
{
  return flux >= 0.0 ? tvd_face_value<L>(lo2, lo, hi) : tvd_face_value<L>(hi2, hi, lo);
}
inline double upwind_face_value(Limiter l, double flux, double lo2, double lo, double hi, double hi2)
{
  return flux >= 0.0 ? tvd_face_value(l, lo2, lo, hi) : tvd_face_value(l, hi2, hi, lo);
}

// Explicit limits for forward Euler of the eps-weighted advection-diffusion of one velocity component, per cell:
// rate_conv = (1 + psi_max / 2) sum_a |u_a| / h_a, rate_visc = 2 nu sum_a 1 / h_a^2, both scaled by the largest
// ratio of a face void fraction to the cell's (eps_face / eps_cell >= 1 where eps varies). Returns the rates (1/s);
// the step is cfl / (max rate_conv + max rate_visc).
struct StepRates {
  double conv = 0.0, visc = 0.0;
};

// The parts of the rates that depend on the grid only, for evaluating many cells of one grid: the sum of 1 / h_a^2
// and the two factors, computed once (the rates come out the same bit for bit).
struct StepRateGrid {
  int    dim = 3;
  double h[3]{1.0, 1.0, 1.0};
  double inv_h2    = 0.0; // sum_a 1 / h_a^2
  double conv_gain = 1.0; // 1 + psi_max / 2
  double visc_gain = 0.0; // 2 nu
};
inline StepRateGrid step_rate_grid(int dim, const double h[3], double nu, double psi_max)
{
  StepRateGrid g;
  g.dim = dim;
  for (int a = 0; a < 3; ++a) g.h[a] = h[a];
  for (int a = 0; a < dim; ++a) g.inv_h2 += 1.0 / (h[a] * h[a]);
  g.conv_gain = 1.0 + 0.5 * psi_max;
  g.visc_gain = 2.0 * nu;
  return g;
}
// DIM = g.dim known to the compiler (loops over a grid's cells); the same numbers as the run-time form below.
template <int DIM>
inline StepRates explicit_step_rates(const StepRateGrid &g, const double speed[3], double eps_ratio)
{
  StepRates r;
  for (int a = 0; a < DIM; ++a) r.conv += std::fabs(speed[a]) / g.h[a];
  r.visc = g.inv_h2;
  r.conv *= g.conv_gain * eps_ratio;
  r.visc *= g.visc_gain * eps_ratio;
  return r;
}
inline StepRates explicit_step_rates(const StepRateGrid &g, const double speed[3], double eps_ratio)
{
  switch (g.dim) {
  case 1:
    return explicit_step_rates<1>(g, speed, eps_ratio);
  case 2:
    return explicit_step_rates<2>(g, speed, eps_ratio);
  default:
    return explicit_step_rates<3>(g, speed, eps_ratio);
  }
}
inline StepRates explicit_step_rates(int dim, const double speed[3], const double h[3], double nu, double psi_max, double eps_ratio)
{
  return explicit_step_rates(step_rate_grid(dim, h, nu, psi_max), speed, eps_ratio);
}

// An inlet slit [centre - width/2, centre + width/2] on a row of n cells of size h starting at x0. Its edges must
// lie on cell faces (to a tolerance of tol cells). When they do not, nearest_width is the valid width closest to
// the one asked for at the same centre (edges on faces need (2 centre / h) and the width in cells to have the same
// parity); when the centre itself is not on a face or a cell centre, there is none and nearest_centre is the
// closest centre that has valid widths.
struct JetSnap {
  bool   ok    = false;
  long   first = 0, last = 0;    // cells [first, last) covered when ok
  bool   centre_ok      = false; // centre on a face or a cell centre
  double nearest_width  = 0.0;   // m, valid width closest to the request (centre_ok only)
  long   nearest_cells  = 0;     // that width in cells
  double nearest_centre = 0.0;   // m, closest centre with valid widths
  bool   inside         = true;  // the slit lies within the row
};

inline JetSnap snap_jet(double centre, double width, double x0, double h, long n, double tol = 1e-3)
{
  JetSnap      s;
  const double lo = (centre - 0.5 * width - x0) / h, hi = (centre + 0.5 * width - x0) / h;
  const double c2  = 2.0 * (centre - x0) / h; // centre in half cells
  s.centre_ok      = std::fabs(c2 - std::round(c2)) <= 2.0 * tol;
  s.nearest_centre = x0 + 0.5 * h * std::round(c2);
  if (s.centre_ok) {
    // widths m h with m of the parity of round(c2), m >= 1
    const long parity = ((long)std::llround(c2) % 2 + 2) % 2;
    long       m      = (long)std::llround(width / h);
    if (((m % 2) + 2) % 2 != parity) {
      const long down = m - 1, up = m + 1;
      m = (std::fabs(down * h - width) < std::fabs(up * h - width) && down >= 1) ? down : up;
    }
    if (m < 1) m = parity ? 1 : 2;
    s.nearest_cells = m;
    s.nearest_width = m * h;
  }
  const bool on_faces = std::fabs(lo - std::round(lo)) <= tol && std::fabs(hi - std::round(hi)) <= tol;
  s.first             = std::lround(lo);
  s.last              = std::lround(hi);
  s.inside            = lo > -tol && hi < (double)n + tol;
  s.ok                = on_faces && s.inside && s.last > s.first;
  return s;
}

// The superficial inflow velocity of each bottom cell along x: the distributor's everywhere, each slit's over its
// cells (slits given as first cell, last cell (exclusive), velocity; later slits win where they overlap).
struct JetCells {
  long   first, last;
  double velocity;
};
inline std::vector<double> inlet_profile(long n, double distributor, const std::vector<JetCells> &jets)
{
  std::vector<double> v((std::size_t)n, distributor);
  for (const auto &j : jets)
    for (long i = std::max(0L, j.first); i < std::min(n, j.last); ++i) v[(std::size_t)i] = j.velocity;
  return v;
}

} // namespace fluidbed::kernels
