// Ergun (1952) packed-bed drag, seed eq. 2.11.
#pragma once

#include "fluidbed/kernels/drag_common.hpp"

namespace fluidbed::kernels {

// Ergun (1952), eq. 2.11 with the gas viscosity restored (seed-errata 1), divided by (1 - eps):
// K = 150 (1 - eps) mu / (eps d^2) + 1.75 rho |u - v| / d.
inline double ergun_k(const DragInput &in)
{
  return 150.0 * (1.0 - in.eps) * in.mu_g / (in.eps * in.d * in.d) + 1.75 * in.rho_g * in.slip / in.d;
}
inline DragCellTerms ergun_cell(double)
{
  return {};
}
inline double ergun_k(const DragCellTerms &, const DragInput &in)
{
  return ergun_k(in);
}

} // namespace fluidbed::kernels
