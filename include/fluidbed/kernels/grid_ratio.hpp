// Choice of the two-grid ratio (seed chapter 5): each particle cell holds r_x x r_y x r_z whole fluid cells, so
// r must divide the fluid cell count in its direction. Plain functions, tested without PETSc.
#pragma once

#include <cmath>
#include <string>
#include <vector>

namespace fluidbed::kernels {

inline std::vector<long> divisors(long n)
{
  std::vector<long> d;
  for (long k = 1; k <= n; ++k)
    if (n % k == 0) d.push_back(k);
  return d;
}

// The divisor of n closest to target in ratio (|log(r / target)| smallest; ties go to the larger divisor, which
// keeps more particles per cell). target <= 1 gives 1.
inline long nearest_divisor(long n, double target)
{
  long   best = 1;
  double err  = INFINITY;
  if (!(target > 1.0)) return 1;
  for (long r : divisors(n)) {
    const double e = std::fabs(std::log(static_cast<double>(r) / target));
    if (e < err - 1e-12 || (std::fabs(e - err) <= 1e-12 && r > best)) {
      best = r;
      err  = e;
    }
  }
  return best;
}

inline std::string divisor_list(long n)
{
  std::string s;
  for (long r : divisors(n)) s += (s.empty() ? "" : ", ") + std::to_string(r);
  return s;
}

} // namespace fluidbed::kernels
