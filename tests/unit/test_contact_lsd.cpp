// Unit tests of the linear spring-dashpot contact kernel (seed eq. 2.3-2.10, 3.2-3.3). No MPI, no PETSc.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fluidbed/kernels/contact_lsd.hpp"
#include "fluidbed/kernels/packing.hpp"
#include "fluidbed/kernels/verlet.hpp"

using namespace fluidbed::kernels;

namespace {
double glass_mass(double d)
{
  return 2500.0 * M_PI / 6.0 * d * d * d;
}
} // namespace

// Eq. 3.2-3.3 with m_eff = m/2, k_n = 800 N/m, e = 0.9: the seed quotes 3.675e-5 s for 550 um glass (ch. 3) and
// 5.838e-5 s for 750 um glass (ch. 5). Since t_cr scales as d^1.5 the two quotes differ from each other by 0.24%
// (3.675e-5 corresponds to 551 um); we match 750 um to 0.05% and 550 um to 0.3%.
TEST(CriticalTime, ReproducesSeedValues)
{
  EXPECT_NEAR(critical_time(800.0, 0.9, 0.5 * glass_mass(550e-6)), 3.675e-5, 0.003 * 3.675e-5);
  EXPECT_NEAR(critical_time(800.0, 0.9, 0.5 * glass_mass(750e-6)), 5.838e-5, 0.0005 * 5.838e-5);
}

TEST(CriticalTime, ElasticLimitIsHalfPeriod)
{
  EXPECT_EQ(restitution_damping_ratio(1.0), 0.0);
  const double m = 1e-6, k = 800;
  EXPECT_NEAR(critical_time(k, 1.0, m), M_PI * std::sqrt(m / k), 1e-15);
}

// The kernel's force on j (computed from j's side with the negated history) is exactly minus the force on i.
TEST(LsdContact, PairForceIsExactlyAntisymmetric)
{
  std::mt19937_64 rng(7);
  auto            u = [&]() { return 2.0 * uniform01(rng) - 1.0; };
  const LsdModel  m = lsd_model(800.0, 700.0, 0.7, 0.3);
  for (int trial = 0; trial < 1000; ++trial) {
    const double ri = 5e-4 * (1 + 0.5 * uniform01(rng)), rj = 5e-4 * (1 + 0.5 * uniform01(rng));
    Vec3         dir{u(), u(), u()};
    dir               = (1.0 / norm(dir)) * dir;
    const double dist = (ri + rj) * (1 - 0.01 * uniform01(rng));
    const Vec3   xi{u(), u(), u()};
    const Vec3   xj = xi + dist * dir;
    const Vec3   vi{u(), u(), u()}, vj{u(), u(), u()}, wi{100 * u(), 100 * u(), 100 * u()}, wj{100 * u(), 100 * u(), 100 * u()};
    const double mi = glass_mass(2 * ri), mj = glass_mass(2 * rj);
    Vec3         hi{1e-6 * u(), 1e-6 * u(), 1e-6 * u()};
    Vec3         hj  = -hi;
    const Vec3   dij = xj - xi, dji = xi - xj;
    auto         ki = pair_kinematics(dij, norm(dij), ri, rj, vi, vj, wi, wj, sqrt_effective_mass(mi, mj));
    auto         kj = pair_kinematics(dji, norm(dji), rj, ri, vj, vi, wj, wi, sqrt_effective_mass(mj, mi));
    auto         fi = lsd_contact(m, ki, 1e-6, hi);
    auto         fj = lsd_contact(m, kj, 1e-6, hj);
    EXPECT_EQ(fi.normal.x, -fj.normal.x);
    EXPECT_EQ(fi.normal.y, -fj.normal.y);
    EXPECT_EQ(fi.normal.z, -fj.normal.z);
    EXPECT_EQ(fi.tangential.x, -fj.tangential.x);
    EXPECT_EQ(fi.tangential.y, -fj.tangential.y);
    EXPECT_EQ(fi.tangential.z, -fj.tangential.z);
    EXPECT_EQ(hi.x, -hj.x);
    EXPECT_EQ(hi.y, -hj.y);
    EXPECT_EQ(hi.z, -hj.z);
  }
}

TEST(LsdContact, StaticOverlapGivesHookeForcePushingApart)
{
  const LsdModel m  = lsd_model(800.0, 800.0, 0.9, 0.3);
  const Vec3     d  = {1e-3 - 1e-6, 0, 0}; // j to the right of i, overlap 1 um
  auto           k  = pair_kinematics(d, norm(d), 5e-4, 5e-4, {}, {}, {}, {}, sqrt_effective_mass(1e-6, 1e-6));
  Vec3           xi = {};
  auto           f  = lsd_contact(m, k, 1e-6, xi);
  EXPECT_NEAR(k.overlap, 1e-6, 1e-18);
  EXPECT_NEAR(f.normal.x, -800.0 * 1e-6, 1e-15); // i pushed to -x, away from j
  EXPECT_EQ(f.normal.y, 0.0);
  EXPECT_EQ(norm(f.tangential), 0.0);
}

TEST(LsdContact, CoulombSliderLimitsTangentialForce)
{
  const LsdModel m = lsd_model(800.0, 800.0, 0.9, 0.25);
  const Vec3     d = {0, -(5e-4 - 2e-6), 0}; // wall below, overlap 2 um
  auto           k = wall_kinematics({0, -1, 0}, 5e-4 - 2e-6, 5e-4, {0.5, 0, 0}, {}, 1e-6);
  (void)d;
  Vec3 xi = {1e-3, 0, 0}; // far beyond the slider
  auto f  = lsd_contact(m, k, 1e-6, xi);
  EXPECT_NEAR(norm(f.tangential), 0.25 * norm(f.normal), 1e-12 * norm(f.normal));
  EXPECT_LT(f.tangential.x, 0.0); // opposes sliding to +x
  // the stored displacement reproduces the limited force at the same velocity
  const double eta_t = m.damp_t * k.sqrt_meff;
  const Vec3   vt    = k.v_rel - dot(k.v_rel, k.n) * k.n;
  const Vec3   again = -m.kt * xi - eta_t * vt;
  EXPECT_NEAR(again.x, f.tangential.x, 1e-12);
}

// The slider is written as selects (for the contact loop's SIMD lanes): a contact that sticks keeps its force and
// history exactly, and without a tangential spring a sliding contact holds no displacement.
TEST(LsdContact, SliderSelectsKeepStickingContactsAndClearHistoryWithoutSpring)
{
  const LsdModel m     = lsd_model(800.0, 800.0, 0.9, 0.25);
  auto           k     = wall_kinematics({0, -1, 0}, 5e-4 - 2e-6, 5e-4, {1e-4, 0, 0}, {}, 1e-6);
  Vec3           xi    = {1e-9, 0, 0};
  const Vec3     vt    = k.v_rel - dot(k.v_rel, k.n) * k.n;
  const Vec3     xi_in = xi - dot(xi, k.n) * k.n + 1e-6 * vt;
  auto           f     = lsd_contact(m, k, 1e-6, xi);
  ASSERT_LT(norm(f.tangential), 0.25 * norm(f.normal)); // sticks
  EXPECT_EQ(xi.x, xi_in.x);                             // the history as projected and advanced, bit for bit
  EXPECT_EQ(f.tangential.x, (-m.kt * xi_in - m.damp_t * k.sqrt_meff * vt).x);

  LsdModel no_spring = lsd_model(800.0, 800.0, 0.9, 0.25);
  no_spring.kt       = 0.0; // a tangential dashpot alone
  auto fast          = wall_kinematics({0, -1, 0}, 5e-4 - 2e-6, 5e-4, {50.0, 0, 0}, {}, 1e-6);
  Vec3 h             = {1e-3, 0, 0};
  auto g             = lsd_contact(no_spring, fast, 1e-6, h);
  EXPECT_NEAR(norm(g.tangential), 0.25 * norm(g.normal), 1e-12 * norm(g.normal)); // slides
  EXPECT_EQ(h.x, 0.0);
  EXPECT_EQ(h.y, 0.0);
  EXPECT_EQ(h.z, 0.0);
}

TEST(LsdContact, HistoryProjectionLiesInTangentPlane)
{
  const Vec3 n  = (1.0 / std::sqrt(3.0)) * Vec3{1, 1, 1};
  const Vec3 xi = {1e-6, -2e-6, 0.5e-6};
  const Vec3 p  = project_history(xi, n);
  EXPECT_NEAR(dot(p, n), 0.0, 1e-20);
  EXPECT_NEAR(norm2(p), norm2(xi) - dot(xi, n) * dot(xi, n), 1e-24); // only the normal part is removed
  // a tangential history is unchanged
  const Vec3 t = p;
  EXPECT_NEAR(norm(project_history(t, n) - t), 0.0, 1e-20);
}

// Kernel + velocity Verlet with the predicted damping velocity: a head-on collision returns restitution e
// (seed eq. 3.3) to 0.5% at dt = t_cr/50 and lasts t_cr (eq. 3.2) to 1%.
TEST(LsdContact, HeadOnRestitutionAndDuration)
{
  for (double e : {0.5, 0.9, 1.0}) {
    const double   r = 5e-4, mass = glass_mass(2 * r), v0 = 0.5;
    const LsdModel m   = lsd_model(800.0, 800.0, e, 0.0);
    const double   tcr = critical_time(800.0, e, 0.5 * mass), dt = tcr / 50, h = dt / 2;
    Vec3           xi{-r - 1e-7, 0, 0}, xj{r + 1e-7, 0, 0}, vi{v0, 0, 0}, vj{-v0, 0, 0}, f_prev, hist;
    double         t = 0, t_in = -1, t_out = -1, prev_gap = 2e-7;
    for (int s = 0; s < 400 && t_out < 0; ++s) {
      kick(vi, f_prev, 1 / mass, h);
      kick(vj, -f_prev, 1 / mass, h);
      drift(xi, vi, dt);
      drift(xj, vj, dt);
      t += dt;
      const Vec3   d   = xj - xi;
      const double gap = norm(d) - 2 * r;
      Vec3         f; // force on i
      if (gap < 0) {
        const Vec3 vpi = predicted_velocity(vi, f_prev, 1 / mass, h), vpj = predicted_velocity(vj, -f_prev, 1 / mass, h);
        auto       k  = pair_kinematics(d, norm(d), r, r, vpi, vpj, {}, {}, sqrt_effective_mass(mass, mass));
        auto       cf = lsd_contact(m, k, dt, hist);
        f             = cf.normal + cf.tangential;
      }
      if (prev_gap >= 0 && gap < 0) t_in = t - dt * gap / (gap - prev_gap);
      if (prev_gap < 0 && gap >= 0) t_out = t - dt * gap / (gap - prev_gap);
      prev_gap = gap;
      kick(vi, f, 1 / mass, h);
      kick(vj, -f, 1 / mass, h);
      f_prev = f;
    }
    ASSERT_GT(t_out, 0.0);
    EXPECT_NEAR(-vi.x / v0, e, 0.01 * e) << "e = " << e;
    EXPECT_NEAR((t_out - t_in) / tcr, 1.0, 0.01) << "e = " << e;
  }
}

// The force loop (src/contact/contact_forces.cpp) adds a zero contribution for a listed pair that is apart where it
// used to skip the pair, and adds -1 * c for a contribution c evaluated from the partner's side where it used to add
// -c. Both give the same bits: sums start at +0 and under round-to-nearest a sum is -0 only when both terms are, so
// they never become -0 and adding +0 or -0 leaves them unchanged; -1 * c is -c.
TEST(LsdContact, ZeroAndMirroredContributionsSumBitForBit)
{
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 1000; ++trial) {
    double before = 0.0, now = 0.0; // the old and the new way
    for (int k = 0; k < 12; ++k) {
      const double u = uniform01(rng);
      if (u < 0.4) { // a pair apart: skipped before, now +0 (own) or -1 * +0 = -0 (the partner's)
        now += (u < 0.2) ? 0.0 : -1.0 * 0.0;
        continue;
      }
      const double c = (u > 0.9) ? before : 1e-3 * (2.0 * uniform01(rng) - 1.0); // exact cancellations too
      if (u > 0.65) {                                                            // evaluated by the partner
        before += -c;
        now += -1.0 * c;
      } else {
        before += c;
        now += c;
      }
    }
    EXPECT_EQ(std::signbit(before), std::signbit(now));
    EXPECT_EQ(before, now);
  }
}
