// Unit tests of the gas-phase kernels: TVD limiters and limited face values, the explicit step rates, and the
// inlet slit check. No MPI, no PETSc.
#include <gtest/gtest.h>

#include "fluidbed/kernels/fluid_flux.hpp"

using namespace fluidbed::kernels;

namespace {
const Limiter kAll[]         = {Limiter::Upwind, Limiter::VanLeer, Limiter::Koren, Limiter::Minmod, Limiter::Superbee};
const Limiter kSecondOrder[] = {Limiter::VanLeer, Limiter::Koren, Limiter::Minmod, Limiter::Superbee};
} // namespace

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
