// Unit tests of the gas-phase kernels: TVD limiters and limited face values, the explicit step rates, and the
// inlet slit check. No MPI, no PETSc.
#include <gtest/gtest.h>

#include "fluidbed/kernels/fluid_flux.hpp"

#include <cstdint>
#include <cstring>
#include <limits>
#include <random>

using namespace fluidbed::kernels;

namespace {
const Limiter kAll[]         = {Limiter::Upwind, Limiter::VanLeer, Limiter::Koren, Limiter::Minmod, Limiter::Superbee};
const Limiter kSecondOrder[] = {Limiter::VanLeer, Limiter::Koren, Limiter::Minmod, Limiter::Superbee};

std::uint64_t Bits(double x)
{
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

// The limiter as first written (a switch on every call): the templates must give the same numbers bit for bit.
double ReferencePsi(Limiter l, double r)
{
  if (!(r > 0.0)) return 0.0;
  switch (l) {
  case Limiter::Upwind:
    return 0.0;
  case Limiter::VanLeer:
    return 2.0 * r / (1.0 + r);
  case Limiter::Koren:
    return std::max(0.0, std::min({2.0 * r, (1.0 + 2.0 * r) / 3.0, 2.0}));
  case Limiter::Minmod:
    return std::min(r, 1.0);
  case Limiter::Superbee:
    return std::max(std::min(2.0 * r, 1.0), std::min(r, 2.0));
  }
  return 0.0;
}
double ReferenceFaceValue(Limiter l, double flux, double lo2, double lo, double hi, double hi2)
{
  const bool   pos = flux >= 0.0;
  const double uu = pos ? lo2 : hi2, u = pos ? lo : hi, d = pos ? hi : lo, du = d - u;
  if (du == 0.0) return u;
  return u + 0.5 * ReferencePsi(l, (u - uu) / du) * du;
}

// Velocity-like samples: repeated values (du = 0), signed zeros, tiny and large magnitudes.
double Sample(std::mt19937_64 &rng)
{
  static const double                special[] = {0.0, -0.0, 1.0, -1.0, 45.3, 1e-300, -2.5, 3.0};
  std::uniform_int_distribution<int> pick(0, 3);
  std::uniform_real_distribution<>   x(-50.0, 50.0);
  std::uniform_int_distribution<int> s(0, 7);
  return pick(rng) == 0 ? special[s(rng)] : x(rng);
}

template <Limiter L>
void ExpectTemplateMatchesReference()
{
  std::mt19937_64 rng(20260101);
  const double    rs[] = {-1.0, 0.0, -0.0, 1e-300, 0.25, 1.0, 3.0, 1e300, std::numeric_limits<double>::infinity(), std::nan("")};
  for (double r : rs) {
    EXPECT_EQ(Bits(limiter_psi<L>(r)), Bits(ReferencePsi(L, r))) << "r = " << r;
    EXPECT_EQ(Bits(limiter_psi(L, r)), Bits(ReferencePsi(L, r))) << "r = " << r;
  }
  for (int n = 0; n < 20000; ++n) {
    const double flux = Sample(rng), lo2 = Sample(rng), lo = Sample(rng), hi = Sample(rng), hi2 = Sample(rng);
    const double ref = ReferenceFaceValue(L, flux, lo2, lo, hi, hi2);
    EXPECT_EQ(Bits(upwind_face_value<L>(flux, lo2, lo, hi, hi2)), Bits(ref));
    EXPECT_EQ(Bits(upwind_face_value(L, flux, lo2, lo, hi, hi2)), Bits(ref));
    EXPECT_EQ(Bits(tvd_face_value<L>(lo2, lo, hi)), Bits(tvd_face_value(L, lo2, lo, hi)));
  }
}
} // namespace

TEST(Limiter, TemplatesMatchTheRuntimeChoiceBitForBit)
{
  ExpectTemplateMatchesReference<Limiter::Upwind>();
  ExpectTemplateMatchesReference<Limiter::VanLeer>();
  ExpectTemplateMatchesReference<Limiter::Koren>();
  ExpectTemplateMatchesReference<Limiter::Minmod>();
  ExpectTemplateMatchesReference<Limiter::Superbee>();
}

TEST(Limiter, StaysInTheTvdRegion)
{
  for (Limiter l : kAll) {
    for (double r = -5.0; r <= 50.0; r += 0.01) {
      const double psi = limiter_psi(l, r);
      EXPECT_GE(psi, 0.0) << "r = " << r;
      EXPECT_LE(psi, 2.0 * std::max(r, 0.0) + 1e-15) << "r = " << r;
      EXPECT_LE(psi, limiter_psi_max(l) + 1e-15) << "r = " << r;
    }
    EXPECT_EQ(limiter_psi(l, -1.0), 0.0);
    EXPECT_EQ(limiter_psi(l, std::nan("")), 0.0);
  }
}

TEST(Limiter, SecondOrderOnSmoothData)
{
  for (Limiter l : kSecondOrder) EXPECT_NEAR(limiter_psi(l, 1.0), 1.0, 1e-15);
  EXPECT_NEAR(limiter_psi(Limiter::VanLeer, 3.0), 1.5, 1e-15);
  EXPECT_NEAR(limiter_psi(Limiter::Koren, 0.25), 0.5, 1e-15);
  EXPECT_NEAR(limiter_psi(Limiter::Koren, 1.0), 1.0, 1e-15);
  EXPECT_EQ(limiter_psi(Limiter::Upwind, 1.0), 0.0);
}

TEST(FaceValue, ExactOnLinearDataAndUpwindAtExtrema)
{
  for (Limiter l : kSecondOrder) {
    // linear data: the face value is the midpoint, whatever the slope
    EXPECT_NEAR(tvd_face_value(l, 1.0, 2.0, 3.0), 2.5, 1e-15);
    EXPECT_NEAR(tvd_face_value(l, 3.0, 2.0, 1.0), 1.5, 1e-15);
    // an extremum at the upwind cell: first-order upwind
    EXPECT_EQ(tvd_face_value(l, 1.0, 2.0, 1.0), 2.0);
    EXPECT_EQ(tvd_face_value(l, 0.0, 0.0, 0.0), 0.0);
  }
}

TEST(FaceValue, BoundedBetweenUpwindAndDownwind)
{
  // a 45.3 m/s jet next to still gas: every face value lies between its two neighbours
  const double values[] = {0.0, 0.0, 45.3, 45.3, 45.3, 0.0, 0.0, 12.0, -3.0, 45.3};
  for (Limiter l : kAll)
    for (int i = 1; i + 1 < 10; ++i) {
      const double v = tvd_face_value(l, values[i - 1], values[i], values[i + 1]);
      EXPECT_GE(v, std::min(values[i], values[i + 1]) - 1e-12);
      EXPECT_LE(v, std::max(values[i], values[i + 1]) + 1e-12);
    }
}

TEST(FaceValue, UpwindSideFollowsTheFlux)
{
  // lo2, lo, hi, hi2 = 0, 1, 2, 4: positive flux uses (0, 1, 2), negative (4, 2, 1)
  EXPECT_NEAR(upwind_face_value(Limiter::VanLeer, 1.0, 0.0, 1.0, 2.0, 4.0), 1.5, 1e-15);
  EXPECT_NEAR(upwind_face_value(Limiter::VanLeer, -1.0, 0.0, 1.0, 2.0, 4.0), tvd_face_value(Limiter::VanLeer, 4.0, 2.0, 1.0), 1e-15);
  EXPECT_NEAR(upwind_face_value(Limiter::Upwind, -1.0, 0.0, 1.0, 2.0, 4.0), 2.0, 1e-15);
}

TEST(StepRates, ConvectiveAndViscousLimits)
{
  const double h[3] = {1e-3, 2e-3, 4e-3}, speed[3] = {10.0, -20.0, 5.0};
  const double nu = 1.5e-5;
  StepRates    r  = explicit_step_rates(3, speed, h, nu, 2.0, 1.0);
  EXPECT_NEAR(r.conv, 2.0 * (1e4 + 1e4 + 1.25e3), 1e-9);
  EXPECT_NEAR(r.visc, 2.0 * nu * (1e6 + 2.5e5 + 6.25e4), 1e-9);
  // 2D ignores z; a void-fraction ratio of 2 halves the step
  StepRates r2 = explicit_step_rates(2, speed, h, nu, 0.0, 2.0);
  EXPECT_NEAR(r2.conv, 2.0 * 2e4, 1e-9);
  EXPECT_NEAR(r2.visc, 2.0 * 2.0 * nu * (1e6 + 2.5e5), 1e-9);
}

TEST(StepRates, GridFormMatchesTheFormulaBitForBit)
{
  // the rates as first written, everything per cell
  auto reference = [](int dim, const double speed[3], const double h[3], double nu, double psi_max, double eps_ratio) {
    StepRates r;
    for (int a = 0; a < dim; ++a) {
      r.conv += std::fabs(speed[a]) / h[a];
      r.visc += 1.0 / (h[a] * h[a]);
    }
    r.conv *= (1.0 + 0.5 * psi_max) * eps_ratio;
    r.visc *= 2.0 * nu * eps_ratio;
    return r;
  };
  std::mt19937_64                  rng(7);
  std::uniform_real_distribution<> u(-60.0, 60.0), ratio(1.0, 3.0);
  const double                     h[3] = {0.0564 / 175, 0.28 / 200, 0.00495 / 5}, nu = 1.8e-5 / 1.205;
  for (int dim = 2; dim <= 3; ++dim)
    for (double psi : {0.0, 1.0, 2.0}) {
      const StepRateGrid g = step_rate_grid(dim, h, nu, psi);
      for (int n = 0; n < 2000; ++n) {
        const double    speed[3] = {u(rng), n % 7 ? u(rng) : 0.0, u(rng)}, e = n % 5 ? ratio(rng) : 1.0;
        const StepRates want = reference(dim, speed, h, nu, psi, e), got = explicit_step_rates(g, speed, e),
                        direct = explicit_step_rates(dim, speed, h, nu, psi, e);
        EXPECT_EQ(Bits(got.conv), Bits(want.conv));
        EXPECT_EQ(Bits(got.visc), Bits(want.visc));
        EXPECT_EQ(Bits(direct.conv), Bits(want.conv));
        EXPECT_EQ(Bits(direct.visc), Bits(want.visc));
      }
    }
}

TEST(JetSnap, EdgesOnFaces)
{
  // the seed's bed: 56.4 mm in 175 cells; a 5-cell slit at the centre (87.5 cells)
  const double h = 0.0564 / 175;
  JetSnap      s = snap_jet(0.0282, 5 * h, 0.0, h, 175);
  ASSERT_TRUE(s.ok);
  EXPECT_EQ(s.first, 85);
  EXPECT_EQ(s.last, 90);
}

TEST(JetSnap, SeedWidthIsNotOnFacesAndNearestIsFiveCells)
{
  const double h = 0.0564 / 175;
  JetSnap      s = snap_jet(0.0282, 0.0016, 0.0, h, 175); // 1.6 mm = 4.96 cells
  EXPECT_FALSE(s.ok);
  EXPECT_TRUE(s.centre_ok);
  EXPECT_EQ(s.nearest_cells, 5); // centre on a cell centre: odd widths
  EXPECT_NEAR(s.nearest_width, 5 * h, 1e-15);
  // centre on a face: even widths only; 4.4 cells -> 4
  JetSnap e = snap_jet(0.0, 4.4e-3, -0.01, 1e-3, 20);
  EXPECT_FALSE(e.ok);
  EXPECT_EQ(e.nearest_cells, 4);
  // 3.2 cells at a face centre: 3 has the wrong parity; 4 (0.8 cells off) beats 2 (1.2 cells off)
  JetSnap t = snap_jet(0.0, 3.2e-3, -0.01, 1e-3, 20);
  EXPECT_EQ(t.nearest_cells, 4);
}

TEST(JetSnap, CentreOffTheHalfCellGrid)
{
  JetSnap s = snap_jet(0.00033, 1e-3, 0.0, 1e-3, 10);
  EXPECT_FALSE(s.ok);
  EXPECT_FALSE(s.centre_ok);
  EXPECT_NEAR(s.nearest_centre, 0.0005, 1e-15);
}

TEST(JetSnap, OutsideTheBottom)
{
  JetSnap s = snap_jet(0.0005, 2e-3, 0.0, 1e-3, 10);
  EXPECT_FALSE(s.ok);
  EXPECT_FALSE(s.inside);
}

TEST(InletProfile, DistributorAndSlits)
{
  const std::vector<double> v      = inlet_profile(6, 0.5, {{1, 3, 40.0}, {5, 6, -1.0}});
  const std::vector<double> expect = {0.5, 40.0, 40.0, 0.5, 0.5, -1.0};
  EXPECT_EQ(v, expect);
}
