// Unit tests of the run-time guards' decision rules (kernels/guard_rules.hpp) and of the contact's elastic energy
// that the energy guard sums (kernels/contact_lsd.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "fluidbed/kernels/contact_lsd.hpp"
#include "fluidbed/kernels/guard_rules.hpp"

using namespace fluidbed::kernels;

TEST(GuardRules, SustainedExceedanceNeedsNInARow)
{
  SustainedExceedance s;
  // above, above, below (resets), then three above: trips at the third of those with n = 3
  EXPECT_FALSE(s.add(2.5, 2.0, 3));
  EXPECT_FALSE(s.add(3.0, 2.0, 3));
  EXPECT_FALSE(s.add(1.0, 2.0, 3));
  EXPECT_EQ(s.run, 0);
  EXPECT_FALSE(s.add(2.1, 2.0, 3));
  EXPECT_FALSE(s.add(2.1, 2.0, 3));
  EXPECT_TRUE(s.add(2.1, 2.0, 3));
  EXPECT_EQ(s.longest, 3);
  // the limit itself is not above it; NaN is
  SustainedExceedance t;
  EXPECT_FALSE(t.add(2.0, 2.0, 1));
  EXPECT_TRUE(t.add(std::numeric_limits<double>::quiet_NaN(), 2.0, 1));
}

TEST(GuardRules, EnergyGrowthOverTheLeastEnergy)
{
  EnergyWatch w;
  EXPECT_DOUBLE_EQ(w.add(10.0), 0.0);
  EXPECT_DOUBLE_EQ(w.add(8.0), 0.0);   // dissipation: no growth
  EXPECT_DOUBLE_EQ(w.add(9.0), 0.125); // (9 - 8) / 8
  EXPECT_DOUBLE_EQ(w.least, 8.0);
  EXPECT_TRUE(std::isnan(w.add(std::numeric_limits<double>::quiet_NaN())));
}

TEST(GuardRules, EnergyGrowthFloorNearRest)
{
  // a gas that cooled to 1e-9 of its start: the floor (1e-3 of the first sample) keeps round-off from counting
  EnergyWatch w;
  w.add(1.0);
  w.add(1e-9);
  EXPECT_NEAR(w.add(2e-9), 1e-9 / 1e-3, 1e-15);
  // a system that starts at rest and gains energy from nothing: infinite growth
  EnergyWatch z;
  z.add(0.0);
  EXPECT_TRUE(std::isinf(z.add(1e-6)));
}

TEST(GuardRules, VoidFractionVerdict)
{
  // 12 of 1000 cells at the floor
  VoidFractionVerdict v = void_fraction_verdict(0.02, 1.0, 12, 1000);
  EXPECT_DOUBLE_EQ(v.share_at_floor, 0.012);
  EXPECT_FALSE(v.outside);
  // a cell whose particle centres hold more solid than its volume
  EXPECT_TRUE(void_fraction_verdict(-0.3, 1.0, 1, 1000).outside);
  EXPECT_TRUE(void_fraction_verdict(0.0, 1.0, 1, 1000).outside);
  EXPECT_TRUE(void_fraction_verdict(std::numeric_limits<double>::quiet_NaN(), 1.0, 0, 1000).outside);
  EXPECT_TRUE(void_fraction_verdict(0.4, 1.5, 0, 1000).outside);
  EXPECT_FALSE(void_fraction_verdict(0.4, 1.0, 0, 0).outside);
}

TEST(ContactEnergy, ElasticEnergyOfBothSprings)
{
  const LsdModel m = lsd_model(800.0, 400.0, 0.9, 0.3);
  // 1/2 800 (1e-5)^2 + 1/2 400 ((3e-6)^2 + (4e-6)^2)
  EXPECT_NEAR(lsd_elastic_energy(m, 1e-5, Vec3{3e-6, 0.0, 4e-6}), 4e-8 + 5e-9, 1e-20);
}

TEST(ContactEnergy, HeadOnCollisionConservesKineticPlusSpringEnergy)
{
  // Two equal spheres, e = 1, integrated by velocity Verlet through a head-on contact: kinetic + elastic energy stays
  // within (dt / t_cr)^2 of its start at every step (the energy guard's premise for a closed system).
  const double   m = 1e-6, r = 5e-4, k = 800.0, v0 = 0.5;
  const LsdModel model = lsd_model(k, k, 1.0, 0.0);
  const double   meff = 0.5 * m, tcr = critical_time(k, 1.0, meff), dt = tcr / 50;
  double         x[2] = {0.0, 2 * r + 1e-6}, v[2] = {v0, -v0}, f[2] = {0, 0};
  const double   e0     = m * v0 * v0;
  double         worst  = 0;
  auto           forces = [&]() {
    const double overlap = 2 * r - (x[1] - x[0]);
    f[0] = f[1] = 0;
    if (overlap > 0) {
      f[0] = -k * overlap;
      f[1] = k * overlap;
    }
    return overlap;
  };
  forces();
  for (int s = 0; s < 200; ++s) {
    for (int i = 0; i < 2; ++i) {
      v[i] += 0.5 * dt * f[i] / m;
      x[i] += dt * v[i];
    }
    const double overlap = forces();
    for (int i = 0; i < 2; ++i) v[i] += 0.5 * dt * f[i] / m;
    const double e = 0.5 * m * (v[0] * v[0] + v[1] * v[1]) + (overlap > 0 ? lsd_elastic_energy(model, overlap, Vec3{}) : 0.0);
    worst          = std::max(worst, std::abs(e - e0) / e0);
  }
  EXPECT_LT(worst, 10.0 * (dt / tcr) * (dt / tcr));
}
