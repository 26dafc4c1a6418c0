// Di Felice (1994) drag.
#pragma once

#include <cmath>

#include "fluidbed/kernels/drag_common.hpp"

namespace fluidbed::kernels {

// Di Felice (1994): F = C_D rho pi d^2 eps^(2 - chi) |u - v| (u - v) / 8 with C_D = (0.63 + 4.8 / sqrt(Re))^2,
// chi = 3.7 - 0.65 exp(-(1.5 - log10 Re)^2 / 2), Re = eps rho d |u - v| / mu; K = 3/4 C_D rho eps^(2-chi) |u-v| / d.
// Written with sqrt(C_D) Re^0.5 = 0.63 Re^0.5 + 4.8 so that Re -> 0 stays finite.
// (its exponent depends on Re: nothing is per cell)
inline DragCellTerms di_felice_cell(double)
{
  return {};
}
inline double di_felice_k(const DragInput &in)
{
  const double re   = particle_reynolds(in);
  const double chi  = 3.7 - 0.65 * std::exp(-0.5 * std::pow(1.5 - std::log10(std::fmax(re, 1e-12)), 2));
  const double a    = 0.63 * std::sqrt(re) + 4.8;                             // sqrt(C_D Re)
  const double cdre = a * a;                                                  // C_D Re
  return 0.75 * cdre * in.mu_g * std::pow(in.eps, 1.0 - chi) / (in.d * in.d); // 3/4 C_D rho eps^(2-chi) |u-v| / d
}

inline double di_felice_k(const DragCellTerms &, const DragInput &in)
{
  return di_felice_k(in);
}

} // namespace fluidbed::kernels
