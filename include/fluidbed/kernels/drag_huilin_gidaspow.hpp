// Ergun / Wen-Yu switched at eps = 0.8: the seed's smooth blend (eq. 2.13-2.14) and Gidaspow's sharp switch.
#pragma once

#include <cmath>

#include "fluidbed/kernels/drag_ergun.hpp"
#include "fluidbed/kernels/drag_wen_yu.hpp"

namespace fluidbed::kernels {

// Smooth switch between Ergun and Wen-Yu at eps = 0.8 (Huilin et al. 2003), eq. 2.13 with seed-errata 3:
// phi = arctan(150 x 1.75 (eps - 0.8)) / pi + 0.5.
inline double ergun_wen_yu_blend(double eps)
{
  return std::atan(150.0 * 1.75 * (eps - 0.8)) / M_PI + 0.5;
}

// The seed's drag, eq. 2.14: K = (1 - phi) K_Ergun + phi K_WenYu.
inline DragCellTerms huilin_gidaspow_cell(double eps)
{
  DragCellTerms t = wen_yu_cell(eps);
  t.blend         = ergun_wen_yu_blend(eps);
  return t;
}
inline double huilin_gidaspow_k(const DragCellTerms &t, const DragInput &in)
{
  return (1.0 - t.blend) * ergun_k(in) + t.blend * wen_yu_k(t, in);
}
inline double huilin_gidaspow_k(const DragInput &in)
{
  return huilin_gidaspow_k(huilin_gidaspow_cell(in.eps), in);
}

// Gidaspow (1994): Ergun below eps = 0.8, Wen-Yu above, without smoothing.
inline DragCellTerms gidaspow_cell(double eps)
{
  return wen_yu_cell(eps);
}
inline double gidaspow_k(const DragCellTerms &t, const DragInput &in)
{
  return in.eps < 0.8 ? ergun_k(in) : wen_yu_k(t, in);
}
inline double gidaspow_k(const DragInput &in)
{
  return gidaspow_k(gidaspow_cell(in.eps), in);
}

} // namespace fluidbed::kernels
