// Unit tests of the jet penetration height by first bubble detachment (seed chapter 4, "Jet Height") on
// constructed void fraction fields and height series. No MPI, no PETSc.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "fluidbed/kernels/jet_height.hpp"

using namespace fluidbed::kernels;

namespace {
// 2D bed of 10 x 20 cells of 1 mm, void fraction 0.65 (a dense bed); jet and bubble cells at 0.95. With the
// threshold 0.8 halfway between, the interpolated top of a region is its upper cell face.
const double kBed = 0.65, kVoid = 0.95;

CellGrid Grid2D()
{
  return cell_grid(2, {0, 0, 0}, {0.010, 0.020, 0.001}, 10, 20);
}

void Fill(const CellGrid &g, std::vector<double> &eps, int i0, int i1, int j0, int j1, double value)
{
  for (int j = j0; j < j1; ++j)
    for (int i = i0; i < i1; ++i) eps[cell_index(g, i, j, 0)] = value;
}

// A jet in columns 4-5 of `jet` cells, with a bubble in columns 3-6 over layers [b0, b1) (none if b1 <= b0).
std::vector<double> JetWithBubble(const CellGrid &g, int jet, int b0, int b1)
{
  std::vector<double> eps(static_cast<std::size_t>(cell_count(g)), kBed);
  Fill(g, eps, 4, 6, 0, jet, kVoid);
  if (b1 > b0) Fill(g, eps, 3, 7, b0, b1, kVoid);
  return eps;
}
} // namespace

TEST(JetHeight, InletCellsOfASlot)
{
  const CellGrid g = Grid2D();
  EXPECT_EQ(jet_inlet_cells(g, 0.004, 0.006), (std::vector<long>{4, 5})); // centres 4.5 and 5.5 mm
  EXPECT_EQ(jet_inlet_cells(g, 0.0042, 0.0044), (std::vector<long>{4}));  // narrower than a cell: the cell of its centre
  const CellGrid g3 = cell_grid(3, {0, 0, 0}, {0.006, 0.010, 0.004}, 6, 10, 4);
  const auto     c3 = jet_inlet_cells(g3, 0.002, 0.004, 0.001, 0.003); // x centres 2.5, 3.5; z centres 1.5, 2.5
  EXPECT_EQ(c3, (std::vector<long>{cell_index(g3, 2, 0, 1), cell_index(g3, 3, 0, 1), cell_index(g3, 2, 0, 2), cell_index(g3, 3, 0, 2)}));
}

TEST(JetHeight, AttachedJetOfKnownHeightIgnoresADetachedBubble)
{
  const CellGrid g     = Grid2D();
  const auto     inlet = jet_inlet_cells(g, 0.004, 0.006);
  // jet of 8 cells, a bubble over layers 10-12 separated by two dense layers: the jet is 8 mm high
  auto eps = JetWithBubble(g, 8, 10, 13);
  EXPECT_NEAR(jet_height(g, eps.data(), inlet), 0.008, 1e-12);
  const auto region = jet_region(g, eps.data(), inlet);
  EXPECT_TRUE(region[cell_index(g, 5, 7, 0)]);
  EXPECT_FALSE(region[cell_index(g, 4, 10, 0)]);
  // a one-cell neck in column 4 joins them: 13 mm
  Fill(g, eps, 4, 5, 8, 10, kVoid);
  EXPECT_NEAR(jet_height(g, eps.data(), inlet), 0.013, 1e-12);
  // a cell touching the jet's top corner only (faces, not corners, connect)
  auto corner = JetWithBubble(g, 8, 0, 0);
  Fill(g, corner, 6, 7, 8, 12, kVoid);
  EXPECT_NEAR(jet_height(g, corner.data(), inlet), 0.008, 1e-12);
}

TEST(JetHeight, InterpolatedTopGridTopAndBlockedInlet)
{
  const CellGrid g     = Grid2D();
  const auto     inlet = jet_inlet_cells(g, 0.004, 0.006);
  // cells above the jet at 0.5: the crossing is (0.95 - 0.8) / (0.95 - 0.5) = 1/3 of a cell above the top centre
  auto eps = JetWithBubble(g, 8, 0, 0);
  Fill(g, eps, 0, 10, 8, 9, 0.5);
  EXPECT_NEAR(jet_height(g, eps.data(), inlet), 0.0075 + 0.001 / 3, 1e-12);
  // one column a cell taller: the higher top counts
  Fill(g, eps, 5, 6, 8, 9, kVoid);
  EXPECT_NEAR(jet_height(g, eps.data(), inlet), 0.009, 1e-12);
  // a jet through the whole bed: the grid height
  auto through = JetWithBubble(g, 20, 0, 0);
  EXPECT_NEAR(jet_height(g, through.data(), inlet), 0.020, 1e-12);
  // closed inlet (both inlet cells dense): no jet
  auto closed = JetWithBubble(g, 8, 0, 0);
  Fill(g, closed, 4, 6, 0, 1, kBed);
  EXPECT_EQ(jet_height(g, closed.data(), inlet), 0.0);
  // another threshold: 0.9 is reached 1/6 of a cell above the jet's top centre (0.95 -> 0.65)
  EXPECT_NEAR(jet_height(g, JetWithBubble(g, 8, 0, 0).data(), inlet, 0.9), 0.0075 + 0.001 / 6, 1e-12);
}

TEST(JetHeight, ThreeDimensionalSlot)
{
  // 6 x 10 x 4 cells of 1 mm; slot over x 2-4 mm, z 1-3 mm (2 x 2 inlet cells); jet of 5 cells with one column 7.
  const CellGrid      g     = cell_grid(3, {0, 0, 0}, {0.006, 0.010, 0.004}, 6, 10, 4);
  const auto          inlet = jet_inlet_cells(g, 0.002, 0.004, 0.001, 0.003);
  std::vector<double> eps(static_cast<std::size_t>(cell_count(g)), kBed);
  for (int k = 1; k < 3; ++k)
    for (int j = 0; j < 5; ++j)
      for (int i = 2; i < 4; ++i) eps[cell_index(g, i, j, k)] = kVoid;
  EXPECT_NEAR(jet_height(g, eps.data(), inlet), 0.005, 1e-12);
  eps[cell_index(g, 3, 5, 2)] = eps[cell_index(g, 3, 6, 2)] = kVoid;
  EXPECT_NEAR(jet_height(g, eps.data(), inlet), 0.007, 1e-12);
  // a void region joined only through z faces counts in 3D
  eps[cell_index(g, 3, 6, 3)] = eps[cell_index(g, 3, 7, 3)] = eps[cell_index(g, 3, 8, 3)] = kVoid;
  EXPECT_NEAR(jet_height(g, eps.data(), inlet), 0.009, 1e-12);
}

TEST(JetHeight, SeriesOfHeightsWithKnownDetachments)
{
  // growth, pinch-off from 16 to 9 mm, growth, pinch-off from 19 to 10, a flicker 10.5 -> 10.3 (too small),
  // growth, pinch-off from 22 to 8: jet height (16 + 19 + 22) / 3 = 19 mm, standard deviation sqrt(6) mm.
  const std::vector<double> h{10, 12, 14, 16, 9, 11, 13, 15, 17, 19, 10, 10.5, 10.3, 12, 14, 18, 22, 8};
  std::vector<double>       m;
  for (double v : h) m.push_back(1e-3 * v);
  const JetHeightSeries s = jet_height_series(m, {0.002, 0.25});
  ASSERT_EQ(s.detachments.size(), 3u);
  EXPECT_EQ(s.detachments[0].sample, 3u);
  EXPECT_NEAR(s.detachments[1].height_before, 0.019, 1e-15);
  EXPECT_NEAR(s.detachments[2].height_after, 0.008, 1e-15);
  EXPECT_NEAR(s.mean_height, 0.019, 1e-15);
  EXPECT_NEAR(s.std_dev, 1e-3 * std::sqrt(6.0), 1e-15);
  // relative drops are 44%, 47% and 64%: all three pass 0.4, only the last passes 0.5
  EXPECT_EQ(jet_height_series(m, {0.0, 0.5}).detachments.size(), 1u);
  EXPECT_EQ(jet_height_series(m, {0.0, 0.4}).detachments.size(), 3u);
  // no detachment: a growing jet
  const JetHeightSeries none = jet_height_series({0.001, 0.002, 0.003});
  EXPECT_TRUE(none.detachments.empty());
  EXPECT_EQ(none.mean_height, 0.0);
}

TEST(JetHeight, SeriesFromSnapshotsOfPinchingBubbles)
{
  // Snapshots of a jet with a bubble that grows on top of it and pinches off, twice:
  //   jet 4 -> bubble attached over 4-6 (7 mm) -> over 4-8 (9 mm) -> pinched off, floating over 6-9 (4 mm)
  //   jet 5 -> bubble over 5-7 (8 mm) -> over 5-9 (10 mm) -> pinched off over 7-10 (5 mm)
  // Detachments from 9 and 10 mm: jet height 9.5 mm.
  const CellGrid      g     = Grid2D();
  const auto          inlet = jet_inlet_cells(g, 0.004, 0.006);
  std::vector<double> h;
  for (auto [jet, b0, b1] :
       std::vector<std::array<int, 3>>{{4, 0, 0}, {4, 4, 7}, {4, 4, 9}, {4, 6, 10}, {5, 0, 0}, {5, 5, 8}, {5, 5, 10}, {5, 7, 11}})
    h.push_back(jet_height(g, JetWithBubble(g, jet, b0, b1).data(), inlet));
  const std::vector<double> expect{4, 7, 9, 4, 5, 8, 10, 5};
  for (std::size_t t = 0; t < h.size(); ++t) EXPECT_NEAR(h[t], 1e-3 * expect[t], 1e-12) << t;
  const JetHeightSeries s = jet_height_series(h, {2 * g.h[1], 0.25});
  ASSERT_EQ(s.detachments.size(), 2u);
  EXPECT_EQ(s.detachments[0].sample, 2u);
  EXPECT_EQ(s.detachments[1].sample, 6u);
  EXPECT_NEAR(s.mean_height, 0.0095, 1e-12);
}
