// Unit tests of the insertion arrangements and the grid-ratio choice. No MPI, no PETSc.
#include <gtest/gtest.h>

#include "fluidbed/kernels/grid_ratio.hpp"
#include "fluidbed/kernels/packing.hpp"

using namespace fluidbed::kernels;

namespace {
void ExpectNoOverlapInside(const std::vector<Vec3> &p, const std::vector<double> &d, const Box &box)
{
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double r = 0.5 * d[i];
    EXPECT_GE(p[i].x - r, box.lo.x - 1e-15);
    EXPECT_LE(p[i].x + r, box.hi.x + 1e-15);
    EXPECT_GE(p[i].y - r, box.lo.y - 1e-15);
    EXPECT_LE(p[i].y + r, box.hi.y + 1e-15);
    EXPECT_GE(p[i].z - r, box.lo.z - 1e-15);
    EXPECT_LE(p[i].z + r, box.hi.z + 1e-15);
    for (std::size_t j = 0; j < i; ++j) ASSERT_GE(norm(p[i] - p[j]), 0.5 * (d[i] + d[j])) << i << " overlaps " << j;
  }
}
} // namespace

TEST(Packing, LatticeFillsFromTheBottomWithoutOverlap)
{
  std::mt19937_64 rng(3);
  const Box       box{{0, 0, 0}, {0.01, 0.02, 0.005}};
  auto            p = lattice_fill(box, 3, 300, 1e-3, 1.1e-3, 0.5, rng);
  ASSERT_EQ(p.size(), 300u);
  ExpectNoOverlapInside(p, std::vector<double>(p.size(), 1e-3), box);
  // 9 x 4 sites per layer: 300 particles fill 8 layers and part of a ninth
  double ymax = 0;
  for (auto &q : p) ymax = std::max(ymax, q.y);
  EXPECT_LT(ymax, 0.55e-3 + 8 * 1.1e-3 + 0.03e-3); // ninth layer centre plus the largest jitter
}

TEST(Packing, LatticeRejectsTooManyParticles)
{
  std::mt19937_64 rng(3);
  EXPECT_THROW(lattice_fill({{0, 0, 0}, {0.003, 0.003, 0.003}}, 3, 100, 1e-3, 1.1e-3, 0.0, rng), std::runtime_error);
}

TEST(Packing, RandomFillIsReproducibleAndNonOverlapping)
{
  const Box       box{{0, 0, 0}, {0.01, 0.01, 0.01}};
  std::mt19937_64 a(42), b(42);
  auto            da = draw_diameters(400, 0.8e-3, 1.2e-3, a);
  auto            db = draw_diameters(400, 0.8e-3, 1.2e-3, b);
  auto            pa = random_fill(box, 3, da, 0.0, a);
  auto            pb = random_fill(box, 3, db, 0.0, b);
  ASSERT_EQ(pa.size(), 400u);
  for (std::size_t i = 0; i < pa.size(); ++i) EXPECT_EQ(pa[i].x, pb[i].x);
  ExpectNoOverlapInside(pa, da, box);
  for (double d : da) {
    EXPECT_GE(d, 0.8e-3);
    EXPECT_LE(d, 1.2e-3);
  }
}

TEST(Packing, RandomFillReportsAnImpossibleFill)
{
  std::mt19937_64     rng(1);
  std::vector<double> d(2000, 1e-3); // solid fraction 1.05 of a 1 cm^3 box
  EXPECT_THROW(random_fill({{0, 0, 0}, {0.01, 0.01, 0.01}}, 3, d, 0.0, rng, 50), std::runtime_error);
}

// Seed chapter 5: 175 x 200 x 5 fluid cells of 0.322 x 1.40 x 0.99 mm and particle cells of about 2.25 mm.
TEST(GridRatio, SeedTwoGridBed)
{
  EXPECT_EQ(nearest_divisor(175, 2.25 / (56.4 / 175)), 7);
  EXPECT_EQ(nearest_divisor(200, 2.25 / 1.4), 2);
  EXPECT_EQ(nearest_divisor(5, 2.25 / 0.99), 5); // 5 is closer than 1 in ratio (2.2x vs 2.27x)
  EXPECT_EQ(nearest_divisor(12, 0.5), 1);
  EXPECT_EQ(divisor_list(12), "1, 2, 3, 4, 6, 12");
}
