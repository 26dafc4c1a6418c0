// Unit tests of the drag laws (seed eq. 2.11-2.18) at known points and limits.
#include <gtest/gtest.h>

#include <cmath>

#include "fluidbed/kernels/drag_di_felice.hpp"
#include "fluidbed/kernels/drag_huilin_gidaspow.hpp"

using namespace fluidbed::kernels;

namespace {
const double mu = 1.8e-5, rho = 1.205; // air, seed Table 2.1
}

TEST(Drag, ReynoldsNumberEq217)
{
  EXPECT_NEAR(particle_reynolds({0.5, 1e-3, rho, mu, 2.0}), 0.5 * 1e-3 * 2.0 * rho / mu, 1e-12);
}

TEST(Drag, ErgunByHand)
{
  // eps 0.4, d 1 mm, slip 0.3 m/s: 150 * 0.6 * 1.8e-5 / (0.4 * 1e-6) + 1.75 * 1.205 * 0.3 / 1e-3
  const DragInput in{0.4, 1e-3, rho, mu, 0.3};
  EXPECT_NEAR(ergun_k(in), 4050.0 + 632.625, 1e-9);
}

TEST(Drag, WenYuStokesLimitIsStokesDrag)
{
  // eps = 1, Re -> 0: V_p K = 3 pi mu d
  const double d = 1e-4;
  const double K = wen_yu_k({1.0, d, rho, mu, 1e-9});
  EXPECT_NEAR(M_PI / 6 * d * d * d * K, 3 * M_PI * mu * d, 1e-6 * 3 * M_PI * mu * d);
}

TEST(Drag, WenYuNewtonRegime)
{
  // Re > 1000: C_D = 0.44, K = 3/4 0.44 eps rho slip eps^-2.65 / d
  const DragInput in{0.9, 4e-3, rho, mu, 10.0};
  ASSERT_GT(particle_reynolds(in), 1000.0);
  EXPECT_NEAR(wen_yu_k(in), 0.75 * 0.44 * 0.9 * rho * 10.0 * std::pow(0.9, -2.65) / 4e-3, 1e-9);
  // and the Schiller-Naumann branch below: C_D at Re = 100
  EXPECT_NEAR(cd_times_re(100.0) / 100.0, 24.0 / 100.0 * (1 + 0.15 * std::pow(100.0, 0.687)), 1e-14);
}

TEST(Drag, BlendIsHalfAtPointEightAndContinuous)
{
  EXPECT_NEAR(ergun_wen_yu_blend(0.8), 0.5, 1e-15);
  const DragInput a{0.8 - 1e-9, 0.75e-3, rho, mu, 1.0}, b{0.8 + 1e-9, 0.75e-3, rho, mu, 1.0};
  EXPECT_NEAR(huilin_gidaspow_k(a), huilin_gidaspow_k(b), 1e-6 * huilin_gidaspow_k(a));
  // far from 0.8 the blend is the pure law
  const DragInput dense{0.4, 0.75e-3, rho, mu, 1.0}, dilute{0.99, 0.75e-3, rho, mu, 1.0};
  EXPECT_NEAR(huilin_gidaspow_k(dense), ergun_k(dense), 0.01 * ergun_k(dense));
  EXPECT_NEAR(huilin_gidaspow_k(dilute), wen_yu_k(dilute), 0.01 * wen_yu_k(dilute));
  // Gidaspow's sharp switch jumps where the blend is smooth
  EXPECT_GT(std::fabs(gidaspow_k(a) - gidaspow_k(b)), 0.05 * gidaspow_k(a));
}

TEST(Drag, DiFeliceDiluteLimit)
{
  // eps = 1: chi drops out and K = 3/4 C_D rho slip / d with C_D = (0.63 + 4.8/sqrt(Re))^2
  const DragInput in{1.0, 1e-3, rho, mu, 0.5};
  const double    re = particle_reynolds(in), cd = std::pow(0.63 + 4.8 / std::sqrt(re), 2);
  EXPECT_NEAR(di_felice_k(in), 0.75 * cd * rho * 0.5 / 1e-3, 1e-9 * di_felice_k(in));
}

TEST(Drag, TerminalVelocityBalancesWeight)
{
  const double d = 1e-3, rho_p = 2500;
  const double ut = terminal_velocity([](const DragInput &in) { return wen_yu_k(in); }, d, rho_p, rho, mu, 9.81);
  EXPECT_NEAR(wen_yu_k({1.0, d, rho, mu, ut}) * ut, (rho_p - rho) * 9.81, 1e-9 * rho_p * 9.81);
  // a 1 mm glass bead in air falls at about 7-8 m/s (Schiller-Naumann)
  EXPECT_GT(ut, 6.0);
  EXPECT_LT(ut, 9.0);
}

TEST(Drag, CellTermsGiveTheSameLawBitForBit)
{
  // The coupling evaluates each law as K(cell terms of eps, input), the terms once per cell: the same value as the
  // one-argument law, to the last bit, over dense to dilute beds and slow to fast slip.
  for (double eps : {0.36, 0.45, 0.6, 0.79, 0.8, 0.81, 0.95, 1.0})
    for (double slip : {1e-6, 0.05, 0.5, 3.0, 40.0}) {
      const DragInput in{eps, 7.5e-4, rho, mu, slip};
      EXPECT_EQ(huilin_gidaspow_k(huilin_gidaspow_cell(eps), in), huilin_gidaspow_k(in));
      EXPECT_EQ(gidaspow_k(gidaspow_cell(eps), in), gidaspow_k(in));
      EXPECT_EQ(wen_yu_k(wen_yu_cell(eps), in), wen_yu_k(in));
      EXPECT_EQ(ergun_k(ergun_cell(eps), in), ergun_k(in));
      EXPECT_EQ(di_felice_k(di_felice_cell(eps), in), di_felice_k(in));
    }
}
