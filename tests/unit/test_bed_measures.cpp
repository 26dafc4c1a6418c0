// Unit tests of the whole-bed measures of seed chapter 3: expanded bed height (cut-off and expanded volume), bulk
// solid fraction (eq. 3.7), horizontal mass flow (eq. 3.5), counter-current circulation (eq. 3.6), convective and
// diffusive power (eq. 3.8-3.9), pressure drop. Fields are built by hand. No MPI, no PETSc.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "fluidbed/kernels/bed_measures.hpp"

using namespace fluidbed::kernels;

namespace {
const double kRho = 2500.0;

// A 2D bed of nx x ny cells of 1 x h mm, 1 mm deep, with the solid fraction given per cell.
template <class Eps>
std::vector<CellMeans> Field(const CellGrid &g, Eps eps)
{
  std::vector<CellMeans> m(static_cast<std::size_t>(cell_count(g)));
  for (long c = 0; c < cell_count(g); ++c) m[c].solid_fraction = eps(cell_ijk(g, c));
  return m;
}

std::vector<double> CrossSection(const CellGrid &g, const std::vector<CellMeans> &m)
{
  return cross_section_profile(g, [&](long c) { return m[c].solid_fraction; });
}
} // namespace

TEST(BedHeight, StepProfile)
{
  // eps_s = 0.6 in the 7 bottom layers of 2 mm, 0 above: the surface is at 14 mm.
  // Cut-off: between the centres 13 and 15 mm, 13 + 2 (0.6 - 0.1) / 0.6 = 14 + 2/3 mm (h (1/2 - 0.1/0.6) above
  // the surface). Expanded volume: 7 x 4 cells / 4-cell cross-section = 7 layers = 14 mm.
  const CellGrid g = cell_grid(2, {0, 0, 0}, {0.004, 0.040, 0.001}, 4, 20);
  const auto     m = Field(g, [](CellIjk q) { return q.j < 7 ? 0.6 : 0.0; });
  EXPECT_NEAR(cutoff_bed_height(g, CrossSection(g, m)), 0.014 + 0.002 / 3, 1e-12);
  EXPECT_NEAR(expanded_volume_bed_height(g, m.data()), 0.014, 1e-12);
  // eq. 3.7 with the bed's own mass and the expanded-volume height gives back 0.6
  const double mass = solid_mass(g, m.data(), kRho);
  EXPECT_NEAR(mass, kRho * 0.6 * 0.004 * 0.014 * 0.001, 1e-12 * mass);
  EXPECT_NEAR(bulk_solid_fraction(mass, kRho, expanded_volume_bed_height(g, m.data()), cross_section_area(g)), 0.6, 1e-12);
}

TEST(BedHeight, LinearRampIsExact)
{
  // Cross-section average 0.5 - 20 y (y in m, at the layer centres 1, 3, ... mm), 0 from 25 mm: it crosses 0.1 at
  // y = 20 mm exactly (linear interpolation of a linear profile). In 3D, alternating columns carry +-0.05 so that
  // only the average is linear (where the ramp exceeds 0.06, so no cell goes negative). Expanded volume: the
  // cells above 0.01 are the 12 layers with centres 1 to 23 mm (ramp 0.04 at 23 mm, 0 at 25 mm): 24 mm.
  const CellGrid g    = cell_grid(3, {0, 0, 0}, {0.004, 0.040, 0.002}, 4, 20, 2);
  auto           ramp = [&](int j) { return std::max(0.0, 0.5 - 20.0 * layer_centre_height(g, j)); };
  const auto     m    = Field(g, [&](CellIjk q) { return ramp(q.j) + (ramp(q.j) > 0.06 ? ((q.i + q.k) % 2 ? 0.05 : -0.05) : 0.0); });
  const auto     cs   = CrossSection(g, m);
  for (int j = 0; j < 20; ++j) EXPECT_NEAR(cs[j], ramp(j), 1e-12);
  EXPECT_NEAR(cutoff_bed_height(g, cs), 0.020, 1e-12);
  // layer centres 1..23 mm have ramp >= 0.04 > 0.01; 25 mm and above are empty
  EXPECT_NEAR(expanded_volume_bed_height(g, m.data()), 0.024, 1e-12);
  EXPECT_NEAR(cutoff_bed_height(g, cs, 0.3), 0.010, 1e-12); // any cut-off: 0.5 - 20 y = 0.3 at 10 mm
}

TEST(BedHeight, DetachedFountainSeparatesTheTwoMethods)
{
  // A bed of 0.55 up to 20 mm (1 mm layers, 10 columns), a gap of 5 layers with a trace of particles (0.005,
  // below the 0.01 threshold), and a fountain cloud of 0.3 in the 6 middle columns from 25 to 35 mm (its cross-section
  // average, 0.18, is above the cut-off). The cut-off method stops at the bed surface, 19.5 + (0.55 - 0.1) / (0.55 - 0.005) mm;
  // the expanded volume counts the cloud: 200 + 60 cells over 10 columns = 26 mm (seed chapter 3, 3 U_mf: 50 mm
  // against 88.5 mm).
  const CellGrid g  = cell_grid(2, {0, 0, 0}, {0.010, 0.050, 0.001}, 10, 50);
  const auto     m  = Field(g, [](CellIjk q) {
    if (q.j < 20) return 0.55;
    if (q.j < 25) return 0.005;
    if (q.j < 35 && q.i >= 2 && q.i < 8) return 0.3;
    return 0.0;
  });
  const double   hc = cutoff_bed_height(g, CrossSection(g, m));
  const double   hv = expanded_volume_bed_height(g, m.data());
  EXPECT_NEAR(hc, 0.0195 + 0.001 * 0.45 / 0.545, 1e-12);
  EXPECT_NEAR(hv, 0.026, 1e-12);
  EXPECT_NEAR(expanded_volume_bed_height(g, m.data(), 0.001), 0.031, 1e-12); // a lower threshold counts the trace
}

TEST(BedHeight, CutoffEdgeCases)
{
  const CellGrid g = cell_grid(2, {0, 0, 0}, {0.004, 0.010, 0.001}, 4, 5);
  EXPECT_EQ(cutoff_bed_height(g, {0.05, 0.02, 0, 0, 0}), 0.0);            // never reaches the cut-off: no bed
  EXPECT_NEAR(cutoff_bed_height(g, {0.5, 0.5, 0.5, 0.5, 0.4}), 0.010, 0); // never falls below: the grid height
  // a dilute bottom layer (a jet's inlet row) does not end the bed: the bed surface is between 5 and 7 mm
  EXPECT_NEAR(cutoff_bed_height(g, {0.05, 0.5, 0.5, 0.0, 0.0}), 0.005 + 0.002 * 0.4 / 0.5, 1e-12);
}

TEST(MassFlow, HandBuiltFieldFluxesCirculationAndPower)
{
  // 2 x 2 cells of 10 x 20 mm, 5 mm deep (2D): A_x = 20 x 5 mm^2 = 1e-4 m^2, A_y = 10 x 5 mm^2 = 5e-5 m^2.
  //   cell    eps_s   v (m/s)        theta (m^2/s^2)
  //   (0,0)   0.5     ( 0.1,  0.2)   0.01
  //   (1,0)   0.4     (-0.1, -0.3)   0.02
  //   (0,1)   0.2     ( 0.0, -0.1)   0
  //   (1,1)   0.005   ( 0.5, -1.0)   0.1     (below the occupied threshold 0.01)
  const CellGrid         g = cell_grid(2, {0, 0, 0}, {0.02, 0.04, 0.005}, 2, 2);
  std::vector<CellMeans> m(4);
  const double           eps[4]{0.5, 0.4, 0.2, 0.005}, vx[4]{0.1, -0.1, 0.0, 0.5}, vy[4]{0.2, -0.3, -0.1, -1.0}, th[4]{0.01, 0.02, 0, 0.1};
  for (int c = 0; c < 4; ++c) {
    m[c].solid_fraction       = eps[c];
    m[c].velocity             = {vx[c], vy[c], 0.0};
    m[c].granular_temperature = th[c];
  }
  // eq. 3.5: mdot_x = rho_p eps_s A_x v_x; (0,0): 2500 x 0.5 x 1e-4 x 0.1 = 0.0125 kg/s; (1,0): -0.01 kg/s
  EXPECT_NEAR(cell_mass_flow(g, kRho, m[0], 0), 0.0125, 1e-15);
  EXPECT_NEAR(cell_mass_flow(g, kRho, m[1], 0), -0.01, 1e-15);
  EXPECT_NEAR(cell_mass_flow(g, kRho, m[1], 1), -0.015, 1e-15); // 2500 x 0.4 x 5e-5 x -0.3
  const auto prof = horizontal_mass_flow_profile(g, m.data(), kRho, 0.005);
  ASSERT_EQ(prof.size(), 2u);
  EXPECT_NEAR(prof[0], 0.0125, 1e-15);
  EXPECT_NEAR(prof[1], -0.01, 1e-15);
  EXPECT_NEAR(normalised_particle_flux(0.5, 0.1, 4.37), 0.05 / 4.37, 1e-15); // eq. 4.4

  // Counter-current model (eq. 3.6): bed cells (0,0), (1,0), (0,1) with solid volumes 0.5, 0.4, 0.2 V_cell;
  // moving down: (1,0) at 0.3 m/s and (0,1) at 0.1 m/s. f_neg = 0.6 / 1.1, |v_neg| = (0.4 x 0.3 + 0.2 x 0.1) / 0.6.
  const DownflowSums s  = downflow_sums(g, m.data());
  const double       vc = cell_volume(g);
  EXPECT_NEAR(s.bed_solid_volume, 1.1 * vc, 1e-15 * vc);
  const double                    esb = 0.45; // a bulk solid fraction from eq. 3.7
  const CounterCurrentCirculation cc  = counter_current_circulation(s, kRho, esb, cross_section_area(g));
  EXPECT_NEAR(cc.fraction_moving_down, 0.6 / 1.1, 1e-14);
  EXPECT_NEAR(cc.mean_downward_speed, 0.14 / 0.6, 1e-14);
  EXPECT_NEAR(cc.mass_flow, 2500 * 0.45 * (0.14 / 1.1) * (0.02 * 0.005), 1e-15);
  // only the bottom layer (centres below 15 mm): bed volume 0.9, down 0.4 at 0.3 m/s
  const auto low = counter_current_circulation(downflow_sums(g, m.data(), kOccupiedSolidFraction, 0.015), kRho, esb, 1.0);
  EXPECT_NEAR(low.fraction_moving_down, 0.4 / 0.9, 1e-14);
  EXPECT_NEAR(low.mean_downward_speed, 0.3, 1e-14);
  // partial sums over two blocks add up to the whole
  DownflowSums a = downflow_sums(g, m.data(), kOccupiedSolidFraction, 0.015), b = s;
  b.bed_solid_volume -= a.bed_solid_volume, b.down_solid_volume -= a.down_solid_volume,
    b.down_solid_volume_speed -= a.down_solid_volume_speed;
  a += b;
  EXPECT_NEAR(a.down_solid_volume_speed, s.down_solid_volume_speed, 1e-20);

  // Convective power (eq. 3.8), sum_i |mdot_i| v_i^2 per cell:
  //   (0,0): mdot = (0.0125, 0.0125): 0.0125 x 0.01 + 0.0125 x 0.04   = 6.25e-4 W
  //   (1,0): mdot = (-0.01, -0.015):  0.01 x 0.01 + 0.015 x 0.09      = 1.45e-3 W
  //   (0,1): mdot = (0, -0.0025):     0.0025 x 0.01                   = 2.5e-5 W
  //   (1,1): mdot = (6.25e-4, -6.25e-4): 6.25e-4 x (0.25 + 1)         = 7.8125e-4 W
  EXPECT_NEAR(cell_convective_power(g, kRho, m[0]), 6.25e-4, 1e-18);
  EXPECT_NEAR(cell_convective_power(g, kRho, m[1]), 1.45e-3, 1e-18);
  EXPECT_NEAR(convective_power(g, kRho, m.data()), 6.25e-4 + 1.45e-3 + 2.5e-5 + 7.8125e-4, 1e-17);
  // Diffusive power (eq. 3.9), |mdot| theta per cell:
  //   (0,0): 0.0125 sqrt(2) x 0.01; (1,0): sqrt(0.01^2 + 0.015^2) x 0.02; (0,1): 0; (1,1): 6.25e-4 sqrt(2) x 0.1
  EXPECT_NEAR(cell_net_mass_flow(g, kRho, m[1]), std::sqrt(3.25e-4), 1e-16);
  const double pd = 0.0125 * std::sqrt(2.0) * 0.01 + std::sqrt(3.25e-4) * 0.02 + 6.25e-4 * std::sqrt(2.0) * 0.1;
  EXPECT_NEAR(diffusive_power(g, kRho, m.data()), pd, 1e-17);
  EXPECT_EQ(cell_diffusive_power(g, kRho, m[2]), 0.0);
}

TEST(MassFlow, ThreeDimensionsAndDepthSum)
{
  // 3D cells of 1 x 2 x 4 mm: A_x = 8, A_y = 4, A_z = 2 mm^2. One cell, eps_s 0.3, v = (1, -2, 3) m/s:
  // mdot = 2500 x 0.3 x (8e-6, -8e-6, 6e-6) kg/s; P_c = 750 (8e-6 x 1 + 4e-6 x 8 + 2e-6 x 27) W.
  const CellGrid         g = cell_grid(3, {0, 0, 0}, {0.001, 0.002, 0.008}, 1, 1, 2);
  std::vector<CellMeans> m(2);
  for (auto &c : m) c.solid_fraction = 0.3, c.velocity = {1, -2, 3};
  EXPECT_NEAR(cell_mass_flow(g, kRho, m[0], 2), 750 * 6e-6, 1e-15);
  EXPECT_NEAR(cell_convective_power(g, kRho, m[0]), 750 * (8e-6 + 32e-6 + 54e-6), 1e-15);
  EXPECT_NEAR(cell_net_mass_flow(g, kRho, m[0]), 750 * std::sqrt(64e-12 + 64e-12 + 36e-12), 1e-15);
  // the horizontal mass flow profile sums the two depth cells: the flow through the full depth
  EXPECT_NEAR(horizontal_mass_flow_profile(g, m.data(), kRho, 0.001)[0], 2 * 750 * 8e-6, 1e-15);
}

TEST(Pressure, DropBetweenHeights)
{
  // p = 1000 - 5e4 y at the layer centres (1 mm layers): the drop between 2.3 and 7.8 mm is 5e4 x 5.5e-3
  const CellGrid      g = cell_grid(2, {0, 0, 0}, {0.004, 0.010, 0.001}, 4, 10);
  std::vector<double> p(10);
  for (int j = 0; j < 10; ++j) p[j] = 1000.0 - 5e4 * layer_centre_height(g, j);
  EXPECT_NEAR(pressure_drop(g, p, 0.0023, 0.0078), 275.0, 1e-9);
  // the outer half layers continue the line of the nearest centres: the drop across the whole grid, from the
  // distributor to the top, is the linear profile's 5e4 x 10 mm
  EXPECT_NEAR(pressure_drop(g, p, 0.0, 0.010), 500.0, 1e-9);
  EXPECT_NEAR(bed_weight_pressure_drop(0.1, 9.81, 0.0564 * 0.00495), 0.981 / (0.0564 * 0.00495), 1e-9);
}
