// Unit tests of the per-cell bed statistics (seed eq. 3.4, 4.3, 5.2), their time average and profiles.
// No MPI, no PETSc.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "fluidbed/kernels/bed_statistics.hpp"
#include "fluidbed/kernels/packing.hpp"

using namespace fluidbed::kernels;

namespace {
// Particles stored as the solver stores them: dim coordinates per particle, 3 velocity components.
struct Particles {
  int                 dim = 3;
  std::vector<double> x, v, d;

  void add(const Vec3 &p, const Vec3 &u, double diam)
  {
    x.push_back(p.x), x.push_back(p.y);
    if (dim == 3) x.push_back(p.z);
    v.push_back(u.x), v.push_back(u.y), v.push_back(u.z);
    d.push_back(diam);
  }
  ParticleView view() const { return {d.size(), x.data(), dim, v.data(), 3, d.data(), 0.0}; }
};

// Standard normal deviate by Box-Muller from the packing kernel's portable uniform01.
double normal(std::mt19937_64 &rng)
{
  const double u1 = 1.0 - uniform01(rng), u2 = uniform01(rng);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

const double kRho = 2500.0; // glass, kg/m^3
} // namespace

TEST(CellGrid, IndexingVolumesAndClamping)
{
  const CellGrid g = cell_grid(3, {0, 0, 0}, {0.03, 0.08, 0.01}, 3, 4, 2);
  EXPECT_EQ(cell_count(g), 24);
  EXPECT_EQ(cells_per_layer(g), 6);
  EXPECT_NEAR(cell_volume(g), 0.01 * 0.02 * 0.005, 1e-18);
  EXPECT_NEAR(face_area(g, 0), 0.02 * 0.005, 1e-18);
  EXPECT_NEAR(face_area(g, 1), 0.01 * 0.005, 1e-18);
  EXPECT_NEAR(face_area(g, 2), 0.01 * 0.02, 1e-18);
  EXPECT_NEAR(cross_section_area(g), 0.03 * 0.01, 1e-18);
  for (long c = 0; c < cell_count(g); ++c) {
    const CellIjk q = cell_ijk(g, c);
    EXPECT_EQ(cell_index(g, q.i, q.j, q.k), c);
  }
  EXPECT_EQ(cell_index(g, 1, 2, 1), 1 + 3 * (2 + 4 * 1)); // x fastest, then y, then z (DMDA order)
  EXPECT_EQ(cell_of_point(g, Vec3{0.015, 0.05, 0.007}), cell_index(g, 1, 2, 1));
  // points on or beyond the boundary land in the boundary cells
  EXPECT_EQ(cell_of_point(g, Vec3{0.03, 0.08, 0.01}), cell_index(g, 2, 3, 1));
  EXPECT_EQ(cell_of_point(g, Vec3{-1e-9, -1.0, 0.0}), cell_index(g, 0, 0, 0));
  EXPECT_EQ(layer_of_height(g, 0.039), 1);
  EXPECT_NEAR(layer_centre_height(g, 1), 0.03, 1e-15);
  EXPECT_NEAR(cell_centre(g, 0, 2), 0.025, 1e-15);
}

TEST(CellGrid, TwoDimensionalCellsSpanTheDepth)
{
  const CellGrid g = cell_grid(2, {0, 0, 0}, {0.02, 0.04, 0.00055}, 2, 4, 7); // nz ignored in 2D
  EXPECT_EQ(g.n[2], 1);
  EXPECT_NEAR(g.h[2], 0.00055, 1e-18);
  EXPECT_NEAR(cell_volume(g), 0.01 * 0.01 * 0.00055, 1e-18);
  const double x[2]{0.015, 0.035}; // two coordinates: z is not read
  EXPECT_EQ(cell_of_point(g, x), cell_index(g, 1, 3, 0));
  EXPECT_THROW(cell_grid(2, {0, 0, 0}, {0.02, 0.0, 0.001}, 2, 4), std::invalid_argument);
}

TEST(BedStatistics, SumsCountMassVolumeAndVelocity)
{
  const CellGrid g = cell_grid(2, {0, 0, 0}, {0.02, 0.02, 0.001}, 2, 2);
  Particles      p;
  p.dim = 2;
  p.add({0.005, 0.005, 0}, {1, 2, 0}, 1e-3);
  p.add({0.006, 0.004, 0}, {3, -2, 0}, 0.5e-3);
  p.add({0.015, 0.015, 0}, {0, 0.5, 0}, 1e-3);
  const auto s = cell_sums(g, p.view(), kRho);
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s[0].count, 2.0);
  const double v0 = M_PI / 6 * (1e-9 + 0.125e-9);
  EXPECT_NEAR(s[0].solid_volume, v0, 1e-24);
  EXPECT_NEAR(s[0].mass, kRho * v0, 1e-18);
  EXPECT_NEAR(solid_fraction(s[0], cell_volume(g)), v0 / (0.01 * 0.01 * 0.001), 1e-14);      // eq. 5.2
  EXPECT_NEAR(void_fraction(s[0], cell_volume(g)), 1.0 - v0 / (0.01 * 0.01 * 0.001), 1e-14); // eq. 5.3
  const Vec3 u = mean_velocity(s[0]);                                                        // eq. 4.3
  EXPECT_DOUBLE_EQ(u.x, 2.0);
  EXPECT_DOUBLE_EQ(u.y, 0.0);
  EXPECT_DOUBLE_EQ(s[0].velocity_sq[0], 10.0);
  EXPECT_NEAR(s[0].solid_volume_velocity[0], M_PI / 6 * (1e-9 * 1 + 0.125e-9 * 3), 1e-24);
  EXPECT_EQ(s[1].count + s[2].count, 0.0);
  EXPECT_EQ(mean_velocity(s[1]).x, 0.0); // empty cell: zero, not NaN
  EXPECT_EQ(s[3].count, 1.0);
  // sums of two particle sets add up
  Particles a, b;
  a.dim = b.dim = 2;
  a.add({0.005, 0.005, 0}, {1, 2, 0}, 1e-3);
  b.add({0.006, 0.004, 0}, {3, -2, 0}, 0.5e-3);
  b.add({0.015, 0.015, 0}, {0, 0.5, 0}, 1e-3);
  auto sa = cell_sums(g, a.view(), kRho);
  add_particles_to_cells(g, b.view(), kRho, sa.data());
  for (int c = 0; c < 4; ++c) EXPECT_EQ(sa[c].count, s[c].count);
  EXPECT_DOUBLE_EQ(sa[0].velocity_sq[1], s[0].velocity_sq[1]);
  // a monodisperse view without a diameter array
  ParticleView mono = a.view();
  mono.d            = nullptr;
  mono.diameter     = 2e-3;
  EXPECT_NEAR(cell_sums(g, mono, kRho)[0].solid_volume, M_PI / 6 * 8e-9, 1e-22);
}

TEST(BedStatistics, LatticeGivesItsExactSolidFraction)
{
  // Simple cubic lattice of spacing s in a box 4 s wide: cells 2 s wide hold 8 spheres each, so
  // eps_s = 8 (pi/6) d^3 / (2 s)^3 = (pi/6) (d/s)^3 in every cell.
  const double    d = 1e-3, s = 1.25e-3;
  std::mt19937_64 rng(1);
  const Box       box{{0, 0, 0}, {4 * s, 4 * s, 4 * s}};
  const auto      pos = lattice_fill(box, 3, 64, d, s, 0.0, rng);
  Particles       p;
  for (const auto &q : pos) p.add(q, {}, d);
  const CellGrid g   = cell_grid(3, box.lo, box.hi, 2, 2, 2);
  const auto     sum = cell_sums(g, p.view(), kRho);
  for (const auto &c : sum) {
    EXPECT_EQ(c.count, 8.0);
    EXPECT_NEAR(solid_fraction(c, cell_volume(g)), M_PI / 6 * std::pow(d / s, 3), 1e-12);
  }
}

namespace {
// Random sequential fill of a box with spheres of diameter d; the grid covers the region their centres can reach
// ([lo + r, hi - r]), so the centres are uniform over the grid and every cell expects the same solid fraction
// phi = N V_p / V_grid. Checks each cell against phi within 4 sigma, sigma = phi / sqrt(N_cell) the Poisson
// estimate for N_cell = phi V_cell / V_p particles expected per cell. Poisson overestimates the spread of a
// non-overlapping fill (its counts are sub-Poisson: S(0) < 1), so this bound is conservative; the rms deviation
// over the cells must also stay below sigma. Over 30 seeds of the two fills below the largest deviation was
// 2.3 sigma and the rms 0.72 sigma (3D) and 0.45 sigma (2D); the cells at the grid's faces read 1-2% above phi
// (the fill's denser layer at the walls), well inside the bound.
void CheckRandomFill(int dim, const Box &box, const CellGrid &g, std::size_t n, double d, unsigned seed)
{
  std::mt19937_64 rng(seed);
  const auto      pos = random_fill(box, dim, std::vector<double>(n, d), 0.0, rng);
  Particles       p;
  p.dim = dim;
  for (const auto &q : pos) p.add(q, {}, d);
  const auto   sums  = cell_sums(g, p.view(), kRho);
  const double vc    = cell_volume(g);
  const double phi   = n * sphere_volume(d) / (vc * cell_count(g));
  const double ncell = phi * vc / sphere_volume(d);
  const double sigma = phi / std::sqrt(ncell);
  double       mean = 0.0, sq = 0.0;
  for (const auto &c : sums) {
    const double e = solid_fraction(c, vc);
    EXPECT_NEAR(e, phi, 4 * sigma);
    mean += e;
    sq += (e - phi) * (e - phi);
  }
  mean /= sums.size();
  EXPECT_NEAR(mean, phi, 1e-12 * phi); // every particle is counted once
  EXPECT_LT(std::sqrt(sq / sums.size()), sigma);
}
} // namespace

TEST(BedStatistics, RandomFillGivesItsSolidFractionWithinSamplingError3D)
{
  // 2000 spheres of 1 mm in a 20 mm cube (phi = 0.153 over the centres' 19 mm cube), 4 x 4 x 4 cells of
  // 4.75 mm: about 31 particles per cell, sigma = 18% of phi.
  const double d = 1e-3;
  const Box    box{{0, 0, 0}, {0.02, 0.02, 0.02}};
  CheckRandomFill(3, box, cell_grid(3, {0.5 * d, 0.5 * d, 0.5 * d}, {0.02 - 0.5 * d, 0.02 - 0.5 * d, 0.02 - 0.5 * d}, 4, 4, 4), 2000, d, 7);
}

TEST(BedStatistics, RandomFillGivesItsSolidFractionWithinSamplingError2D)
{
  // A bed one particle deep (the seed's 2D beds): 1800 spheres of 1 mm in 60 x 60 x 1 mm (area fraction 0.39), 6 x 6
  // cells of 9.83 mm: 50 particles per cell, eps_s = N V_p / (h_x h_y depth) = 0.27, sigma = 14% of it.
  const double d = 1e-3;
  const Box    box{{0, 0, 0}, {0.06, 0.06, d}};
  CheckRandomFill(2, box, cell_grid(2, {0.5 * d, 0.5 * d, 0.0}, {0.06 - 0.5 * d, 0.06 - 0.5 * d, d}, 6, 6), 1800, d, 11);
}

TEST(GranularTemperature, RigidTranslationIsZero)
{
  const CellGrid  g = cell_grid(3, {0, 0, 0}, {0.01, 0.01, 0.01}, 2, 2, 2);
  std::mt19937_64 rng(5);
  Particles       p;
  const Vec3      u{0.3, -1.2, 0.7};
  for (int q = 0; q < 500; ++q) p.add({0.01 * uniform01(rng), 0.01 * uniform01(rng), 0.01 * uniform01(rng)}, u, 5e-4);
  for (const auto &c : cell_sums(g, p.view(), kRho)) {
    ASSERT_GE(c.count, 2.0);
    EXPECT_NEAR(granular_temperature(c, 3), 0.0, 1e-14 * norm2(u)); // round-off of the one-pass sums only
    EXPECT_NEAR(mean_velocity(c).y, u.y, 1e-13);                    // sum v / N over ~60 particles
  }
}

TEST(GranularTemperature, PlusMinusAGivesASquaredOverN)
{
  // Two particles at U +- a e_x: C = +-a, <C^2> = a^2, theta = a^2 / n (eq. 3.4), whatever U is.
  const double a = 0.2;
  for (int dim : {2, 3}) {
    const CellGrid g = cell_grid(dim, {0, 0, 0}, {0.01, 0.01, 0.01}, 1, 1, 1);
    Particles      p;
    p.dim = dim;
    p.add({0.002, 0.003, 0.004}, {5.0 + a, -1.0, 0.0}, 1e-3);
    p.add({0.007, 0.006, 0.005}, {5.0 - a, -1.0, 0.0}, 1e-3);
    const auto s = cell_sums(g, p.view(), kRho);
    EXPECT_NEAR(granular_temperature(s[0], dim), a * a / dim, 1e-14);
  }
  // fluctuations in every direction: v = U + a e_i and U - a e_i for i = x, y, z: <C^2> = a^2, theta = a^2 / 3
  const CellGrid g = cell_grid(3, {0, 0, 0}, {0.01, 0.01, 0.01}, 1, 1, 1);
  Particles      p;
  const Vec3     U{1, 2, 3};
  for (Vec3 e : {Vec3{a, 0, 0}, Vec3{0, a, 0}, Vec3{0, 0, a}}) {
    p.add({0.005, 0.005, 0.005}, U + e, 1e-3);
    p.add({0.005, 0.005, 0.005}, U - e, 1e-3);
  }
  EXPECT_NEAR(granular_temperature(cell_sums(g, p.view(), kRho)[0], 3), a * a / 3, 1e-14);
}

TEST(GranularTemperature, TwoDimensionsReadOnlyInPlaneVelocities)
{
  // In 2D only x and y count (n = 2): a z velocity, if a caller had one, is ignored.
  const CellGrid g = cell_grid(2, {0, 0, 0}, {0.01, 0.01, 0.001}, 1, 1);
  Particles      p;
  p.dim = 2;
  p.add({0.002, 0.003, 0}, {0, 0.1, 7.0}, 1e-3);
  p.add({0.007, 0.006, 0}, {0, -0.1, -7.0}, 1e-3);
  const auto s = cell_sums(g, p.view(), kRho);
  EXPECT_NEAR(granular_temperature(s[0], 2), 0.01 / 2, 1e-15);
  EXPECT_EQ(s[0].velocity[2], 0.0);
}

TEST(GranularTemperature, MaxwellianSampleGivesItsVariance)
{
  // 20000 particles with independent normal velocity components of variance sigma^2 about a mean U: theta is
  // the sample variance per component, E[theta] = sigma^2 (N - 1) / N, with standard deviation
  // sigma^2 sqrt(2 / (n N)) = 0.0058 sigma^2; tested to 4 of those.
  const CellGrid  g = cell_grid(3, {0, 0, 0}, {0.01, 0.01, 0.01}, 1, 1, 1);
  std::mt19937_64 rng(2024);
  const double    sig = 0.05;
  const int       n   = 20000;
  Particles       p;
  for (int q = 0; q < n; ++q) p.add({0.005, 0.005, 0.005}, {0.4 + sig * normal(rng), -0.2 + sig * normal(rng), sig * normal(rng)}, 5e-4);
  const double theta = granular_temperature(cell_sums(g, p.view(), kRho)[0], 3);
  EXPECT_NEAR(theta, sig * sig * (n - 1.0) / n, 4 * sig * sig * std::sqrt(2.0 / (3.0 * n)));
}

TEST(GranularTemperature, SmallFluctuationOnAFastMean)
{
  // U = 10 m/s, +-1 mm/s: theta = 1e-6 / 3 despite the cancellation of the one-pass sums (error ~ 1e-16 U^2)
  const CellGrid g = cell_grid(3, {0, 0, 0}, {0.01, 0.01, 0.01}, 1, 1, 1);
  Particles      p;
  p.add({0.005, 0.005, 0.005}, {10.001, 0, 0}, 1e-3);
  p.add({0.005, 0.005, 0.005}, {9.999, 0, 0}, 1e-3);
  EXPECT_NEAR(granular_temperature(cell_sums(g, p.view(), kRho)[0], 3), 1e-6 / 3, 1e-6 * 1e-6);
}

TEST(GranularTemperature, UndefinedBelowTwoParticles)
{
  CellSums none, one;
  one.count       = 1;
  one.velocity[0] = 2.0, one.velocity_sq[0] = 4.0;
  EXPECT_FALSE(has_granular_temperature(none));
  EXPECT_FALSE(has_granular_temperature(one));
  EXPECT_EQ(granular_temperature(one, 3), 0.0);
  CellSums five = one;
  five.count    = 5;
  EXPECT_TRUE(has_granular_temperature(five));
  EXPECT_FALSE(has_granular_temperature(five, 10.0)); // a caller asking for more particles
  EXPECT_FALSE(has_granular_temperature(one, 0.0));   // never fewer than two
}

TEST(TimeAverage, TwoSnapshotsOfOneCell)
{
  // Snapshot 1: two particles at vx = 1 and 3 (theta = (1 + 1) / 2 / 3 = 1/3 in 3D); snapshot 2: one particle at
  // vx = 8 (theta undefined). Window velocity = sum v / sum N = (1 + 3 + 8) / 3 = 4, where the mean of the two
  // cell means would be (2 + 8) / 2 = 5; the window's theta is snapshot 1's.
  const CellGrid g  = cell_grid(3, {0, 0, 0}, {0.01, 0.01, 0.01}, 1, 1, 1);
  const double   vc = cell_volume(g), d = 1e-3, vp = sphere_volume(d);
  Particles      s1, s2;
  s1.add({0.005, 0.005, 0.005}, {1, 0, 0}, d);
  s1.add({0.005, 0.005, 0.005}, {3, 0, 0}, d);
  s2.add({0.005, 0.005, 0.005}, {8, 0, 0}, d);
  TimeAverage t = time_average(g);
  add_sample(t, cell_sums(g, s1.view(), kRho).data());
  add_sample(t, cell_sums(g, s2.view(), kRho).data());
  EXPECT_EQ(t.samples, 2);
  EXPECT_EQ(t.weight, 2.0);
  const CellMeans m = cell_means(t)[0];
  EXPECT_NEAR(m.solid_fraction, (2 * vp / vc + vp / vc) / 2, 1e-15);
  EXPECT_NEAR(m.velocity.x, (1.0 + 3.0 + 8.0) / 3.0, 1e-15); // number-weighted: 4, not the mean of means 5
  EXPECT_NEAR(m.granular_temperature, 1.0 / 3.0, 1e-15);     // only snapshot 1 defines theta
  EXPECT_NEAR(m.temperature_coverage, 0.5, 1e-15);
  EXPECT_NEAR(m.solid_flux.x, ((1 + 3) * vp / vc + 8 * vp / vc) / 2, 1e-15); // <eps_s v>
}

TEST(TimeAverage, WeightsAndMergedWindows)
{
  // Two cells, two snapshots with weights 1 and 3; the same window accumulated in two halves and merged.
  const CellGrid g = cell_grid(2, {0, 0, 0}, {0.02, 0.01, 0.001}, 2, 1);
  Particles      a, b;
  a.dim = b.dim = 2;
  a.add({0.005, 0.005, 0}, {0, 1, 0}, 1e-3);
  a.add({0.005, 0.005, 0}, {0, 3, 0}, 1e-3);
  b.add({0.005, 0.005, 0}, {0, -2, 0}, 1e-3);
  b.add({0.005, 0.005, 0}, {0, -4, 0}, 1e-3);
  b.add({0.015, 0.005, 0}, {1, 0, 0}, 1e-3);
  const auto  sa = cell_sums(g, a.view(), kRho), sb = cell_sums(g, b.view(), kRho);
  TimeAverage t = time_average(g), h1 = time_average(g), h2 = time_average(g);
  add_sample(t, sa.data(), 1.0);
  add_sample(t, sb.data(), 3.0);
  add_sample(h1, sa.data(), 1.0);
  add_sample(h2, sb.data(), 3.0);
  const auto m = cell_means(t);
  // cell 0: velocity (1 * (1 + 3) + 3 * (-2 - 4)) / (1 * 2 + 3 * 2) = -14 / 8; theta (1 * 1/2 + 3 * 1/2) / 4
  EXPECT_NEAR(m[0].velocity.y, -14.0 / 8.0, 1e-15);
  EXPECT_NEAR(m[0].granular_temperature, 0.5, 1e-15);
  // cell 1: one particle in the second sample only: eps_s = 3/4 of its one-particle value
  EXPECT_NEAR(m[1].solid_fraction, 0.75 * sphere_volume(1e-3) / cell_volume(g), 1e-15);
  EXPECT_EQ(m[1].temperature_coverage, 0.0);
  EXPECT_EQ(m[1].granular_temperature, 0.0);
  for (std::size_t c = 0; c < h1.cells.size(); ++c) h1.cells[c] += h2.cells[c];
  const auto mm = cell_means(h1.cells[0], h1.weight + h2.weight);
  EXPECT_NEAR(mm.velocity.y, m[0].velocity.y, 1e-15);
  EXPECT_NEAR(mm.solid_fraction, m[0].solid_fraction, 1e-15);
  // a one-sample window is the snapshot
  const auto snap = snapshot_fields(g, sb.data());
  EXPECT_NEAR(snap[0].velocity.y, -3.0, 1e-15);
  EXPECT_NEAR(snap[0].granular_temperature, 0.5, 1e-15);
}

TEST(Profiles, CrossSectionHorizontalVerticalAndInterpolation)
{
  // field = i + 10 j + 100 k on 4 x 5 x 3 cells of 1 x 2 x 1 mm
  const CellGrid g     = cell_grid(3, {0, 0, 0}, {0.004, 0.010, 0.003}, 4, 5, 3);
  auto           field = [&](long c) {
    const CellIjk q = cell_ijk(g, c);
    return q.i + 10.0 * q.j + 100.0 * q.k;
  };
  const auto cs = cross_section_profile(g, field);
  ASSERT_EQ(cs.size(), 5u);
  for (int j = 0; j < 5; ++j) EXPECT_NEAR(cs[j], 1.5 + 10.0 * j + 100.0, 1e-12); // mean i = 1.5, mean k = 1
  const auto ls = layer_sums(g, field);
  EXPECT_NEAR(ls[2], 12 * cs[2], 1e-12);
  const auto hp = horizontal_profile(g, 0.0045, field); // layer 2 holds heights 4-6 mm
  ASSERT_EQ(hp.size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(hp[i], i + 20.0 + 100.0, 1e-12);
  const auto vp = vertical_profile(g, 0.0025, field); // column 2
  ASSERT_EQ(vp.size(), 5u);
  for (int j = 0; j < 5; ++j) EXPECT_NEAR(vp[j], 2 + 10.0 * j + 100.0, 1e-12);
  // linear between layer centres (1, 3, 5, 7, 9 mm); in the outer half layers the line of the two nearest centres,
  // held at the faces (0 and 10 mm) beyond the grid
  const std::vector<double> prof{0, 10, 20, 40, 80};
  EXPECT_NEAR(interpolate_profile(g, prof, 0.004), 15.0, 1e-12);
  EXPECT_NEAR(interpolate_profile(g, prof, 0.0065), 35.0, 1e-12);
  EXPECT_NEAR(interpolate_profile(g, prof, 0.0005), -2.5, 1e-12);
  EXPECT_NEAR(interpolate_profile(g, prof, 0.0100), 100.0, 1e-12);
  EXPECT_NEAR(interpolate_profile(g, prof, -0.003), -5.0, 1e-12);
  EXPECT_NEAR(interpolate_profile(g, prof, 0.0150), 100.0, 1e-12);
  EXPECT_EQ(interpolate_profile(g, std::vector<double>{7.0}, 0.004), 7.0);
  // in 2D the horizontal profile is the layer itself
  const CellGrid g2 = cell_grid(2, {0, 0, 0}, {0.004, 0.010, 0.001}, 4, 5);
  const auto     h2 = horizontal_profile(g2, 0.009, [&](long c) { return double(c); });
  for (int i = 0; i < 4; ++i) EXPECT_EQ(h2[i], cell_index(g2, i, 4, 0));
}
