// Gas-particle drag laws: the common input and Reynolds number (seed eq. 2.17). One file per law:
// drag_ergun.hpp, drag_wen_yu.hpp, drag_huilin_gidaspow.hpp (the seed's blend), drag_di_felice.hpp.
//
// Every law returns the drag coefficient per unit particle volume, K = beta / (1 - eps) [N s / m^4], so that
// the drag on a particle is F = V_p K (u - v_p) (seed eq. 2.18, seed-errata 4). Writing the laws in K rather
// than beta removes the 0/0 of eq. 2.18 for a lone particle (eps -> 1). eps is the gas volume fraction of the
// particle's cell, u the gas velocity there, slip = |u - v_p|.
#pragma once

#include <cmath>

namespace fluidbed::kernels {

struct DragInput {
  double eps   = 1.0; // gas volume fraction
  double d     = 0.0; // particle diameter, m
  double rho_g = 0.0; // gas density, kg/m^3
  double mu_g  = 0.0; // gas viscosity, Pa s
  double slip  = 0.0; // |u - v_p|, m/s
};

// What a law computes from the void fraction alone: a coupling cell computes it once for all its particles (the
// powers of eps and the Ergun/Wen-Yu blend cost more than the rest of a law). Each law is a pair xxx_cell(eps),
// xxx_k(cell terms, input); its one-argument xxx_k(input) is their composition, the same value bit for bit.
struct DragCellTerms {
  double blend      = 0.0; // the Ergun/Wen-Yu blend phi(eps), eq. 2.13 (laws that blend)
  double wen_yu_pow = 0.0; // eps^-2.65, eq. 2.12 (laws with a Wen-Yu branch)
};

// Particle Reynolds number, eq. 2.17: Re_p = eps d |u - v| rho_g / mu_g.
inline double particle_reynolds(const DragInput &in)
{
  return in.eps * in.d * in.slip * in.rho_g / in.mu_g;
}

// Terminal settling speed of a lone sphere (eps = 1) under gravity g in a gas at rest, from the force balance
// K(u) u = (rho_p - rho_g) g, solved by bisection (K grows with u, so the balance has one root).
template <class Law>
double terminal_velocity(Law law, double d, double rho_p, double rho_g, double mu_g, double g)
{
  const double target = (rho_p - rho_g) * g;
  double       lo = 0.0, hi = 1.0;
  auto         residual = [&](double u) { return law(DragInput{1.0, d, rho_g, mu_g, u}) * u - target; };
  while (residual(hi) < 0.0) hi *= 2.0;
  for (int k = 0; k < 200; ++k) {
    const double mid                = 0.5 * (lo + hi);
    (residual(mid) < 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

} // namespace fluidbed::kernels
