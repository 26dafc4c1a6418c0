// Wen & Yu (1966) drag with the Schiller-Naumann coefficient, seed eq. 2.12 and 2.15-2.16.
#pragma once

#include <cmath>

#include "fluidbed/kernels/drag_common.hpp"

namespace fluidbed::kernels {

// Schiller-Naumann drag coefficient times Re_p (eq. 2.15-2.16): C_D Re = 24 (1 + 0.15 Re^0.687) for Re <= 1000,
// 0.44 Re above. Returned as C_D Re so that Re -> 0 stays finite.
inline double cd_times_re(double re)
{
  return re <= 1000.0 ? 24.0 * (1.0 + 0.15 * std::pow(re, 0.687)) : 0.44 * re;
}

// Wen & Yu (1966), eq. 2.12 divided by (1 - eps): K = 3/4 C_D eps rho |u - v| eps^-2.65 / d
//                                                  = 3/4 (C_D Re) mu eps^-2.65 / d^2   (using Re = eps d |u-v| rho / mu).
// At eps = 1 and Re -> 0 it is Stokes drag, V_p K = 3 pi mu d.
inline DragCellTerms wen_yu_cell(double eps)
{
  DragCellTerms t;
  t.wen_yu_pow = std::pow(eps, -2.65);
  return t;
}
inline double wen_yu_k(const DragCellTerms &t, const DragInput &in)
{
  return 0.75 * cd_times_re(particle_reynolds(in)) * in.mu_g * t.wen_yu_pow / (in.d * in.d);
}
inline double wen_yu_k(const DragInput &in)
{
  return wen_yu_k(wen_yu_cell(in.eps), in);
}

} // namespace fluidbed::kernels
