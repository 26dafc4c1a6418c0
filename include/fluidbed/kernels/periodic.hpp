// Minimum-image separation along a periodic direction.
#pragma once

namespace fluidbed::kernels {

// d reduced to [-period/2, period/2] for period > 0; unchanged for period == 0. Odd in d bit for bit
// (min_image(-d) == -min_image(d)), which keeps pair forces exactly antisymmetric.
inline double min_image(double d, double period)
{
  if (period > 0.0) {
    if (d > 0.5 * period) d -= period;
    else if (d < -0.5 * period) d += period;
  }
  return d;
}

} // namespace fluidbed::kernels
