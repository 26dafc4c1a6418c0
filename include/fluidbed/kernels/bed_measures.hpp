// Whole-bed measures of seed chapter 3 (and 4): expanded bed height by cut-off and by expanded volume, bulk solid
// fraction, horizontal solid mass flow, solid circulation by the counter-current model, convective and diffusive
// power, and the pressure drop between two heights.
//
// Inputs are the per-cell fields of bed_statistics.hpp (CellMeans, usually time averages; snapshot_fields() for
// one snapshot) on a CellGrid. Sums over cells are additive: on a rank's block they are partial sums to be
// reduced with MPI_SUM (DownflowSums member by member). Heights are above the grid bottom (the distributor).
// Definitions where the seed is vague are stated at each function and collected in docs/analysis.md.
#pragma once

#include <cmath>
#include <limits>
#include <vector>

#include "fluidbed/kernels/bed_statistics.hpp"
#include "fluidbed/kernels/cell_grid.hpp"
#include "fluidbed/kernels/vec3.hpp"

namespace fluidbed::kernels {

inline double component(const Vec3 &v, int axis)
{
  return axis == 0 ? v.x : (axis == 1 ? v.y : v.z);
}

// ---------------------------------------------------------------------------------------------------------
// Expanded bed height (seed chapter 3, "Expanded Bed Height"; chapter 4, "Bed Expansion").

// Cut-off value of the cross-section-averaged solid fraction that marks the bed surface (seed chapter 3).
constexpr double kBedSurfaceSolidFraction = 0.1;

// Time-averaged solid fraction above which a cell counts as holding particles, for the expanded-volume method and
// the counter-current model. A choice (the seed says "cells having particles in them"): 1% solids, about half a
// particle's volume in a cell 3 diameters wide (one particle fills 1.9% of it), so cells that particles visit
// now and then in the freeboard count, and cells that see one particle in a long window do not.
constexpr double kOccupiedSolidFraction = 0.01;

// (a) Cut-off method: going up from the distributor, the height where the cross-section-averaged solid fraction
// (n_y values at the layer centres, cross_section_profile) first falls below `cutoff`, interpolated linearly
// between the centres of the last layer at or above the cut-off and the first below it. The scan starts at the
// first layer at or above the cut-off (a dilute bottom layer does not end the bed). Returns 0 when no layer
// reaches the cut-off and grid_height(g) when the profile never falls below it. For a sharp bed surface at a cell
// face with solid fraction eps_b below it, the result lies h_y (1/2 - cutoff/eps_b) above the surface: the method
// resolves the surface to a cell. A fountain or detached cloud above a gap is not counted.
inline double cutoff_bed_height(const CellGrid &g, const std::vector<double> &solid_fraction_profile,
                                double cutoff = kBedSurfaceSolidFraction)
{
  const std::size_t ny = solid_fraction_profile.size();
  std::size_t       j  = 0;
  while (j < ny && !(solid_fraction_profile[j] >= cutoff)) ++j;
  if (j == ny) return 0.0;
  while (j < ny && solid_fraction_profile[j] >= cutoff) ++j;
  if (j == ny) return grid_height(g);
  const double above = solid_fraction_profile[j - 1], below = solid_fraction_profile[j];
  return layer_centre_height(g, static_cast<int>(j) - 1) + g.h[1] * (above - cutoff) / (above - below);
}

// Volume of the cells whose solid fraction exceeds `threshold`.
inline double occupied_volume(const CellGrid &g, const CellMeans *m, double threshold = kOccupiedSolidFraction)
{
  long n = 0;
  for (long c = 0; c < cell_count(g); ++c)
    if (m[c].solid_fraction > threshold) ++n;
  return static_cast<double>(n) * cell_volume(g);
}

// (b) Expanded-volume method: the volume of all cells holding particles (solid fraction above `threshold`)
// divided by the cross-section area (seed: the expanded volume over the total bed volume times the bed's
// height, which is the same). Counts a detached fountain, unlike (a). On a rank's block, reduce
// occupied_volume and divide by the global cross_section_area.
inline double expanded_volume_bed_height(const CellGrid &g, const CellMeans *m, double threshold = kOccupiedSolidFraction)
{
  return occupied_volume(g, m, threshold) / cross_section_area(g);
}

// Bulk solid fraction of the expanded bed, eq. 3.7 and 4.5: eps_s,b = m_bed / (rho_p h_exp A_d).
inline double bulk_solid_fraction(double bed_mass, double rho_p, double expanded_height, double distributor_area)
{
  return bed_mass / (rho_p * expanded_height * distributor_area);
}

// Particle mass held by the cells according to the field: rho_p sum eps_s V_cell (the time-averaged inventory).
inline double solid_mass(const CellGrid &g, const CellMeans *m, double rho_p)
{
  double s = 0.0;
  for (long c = 0; c < cell_count(g); ++c) s += m[c].solid_fraction;
  return rho_p * s * cell_volume(g);
}

// ---------------------------------------------------------------------------------------------------------
// Solid mass flow through a cell.

// Mean particle mass flow of a cell along `axis`, eq. 3.5 in every direction: mdot_i = rho_p eps_s A_i v_i
// (kg/s), with eps_s = 1 - eps the cell's solid fraction, A_i the cell face area normal to axis i (in 2D the faces
// normal to x and y span the bed depth) and v_i the cell's average particle velocity. Signed.
inline double cell_mass_flow(const CellGrid &g, double rho_p, const CellMeans &m, int axis)
{
  return rho_p * m.solid_fraction * face_area(g, axis) * component(m.velocity, axis);
}

// The horizontal solid mass flow profile at a height (seed Fig. 3.18-3.19): mdot_x of each column of the layer
// holding that height, summed over z in 3D, so that each value is the flow through a face h_y high and the whole
// bed depth deep, as a 2D cell's is.
inline std::vector<double> horizontal_mass_flow_profile(const CellGrid &g, const CellMeans *m, double rho_p, double height)
{
  std::vector<double> p = horizontal_profile(g, height, [&](long c) { return cell_mass_flow(g, rho_p, m[c], 0); });
  for (double &v : p) v *= g.n[2];
  return p;
}

// Normalised horizontal particle flux, eq. 4.4: eps_s U_s* with U_s* = v_x / U_jet.
inline double normalised_particle_flux(double solid_fraction, double vx, double jet_velocity)
{
  return solid_fraction * vx / jet_velocity;
}

// ---------------------------------------------------------------------------------------------------------
// Solid circulation by the counter-current model, eq. 3.6.
//
// The bed is the set of cells holding particles (solid fraction above the occupied threshold, the cells of the
// expanded-volume height), optionally only those whose centre lies below a height. Weighting each cell by its
// solid volume eps_s V_cell:
//   f_neg        = (solid volume of the bed cells with v_y < 0) / (solid volume of all bed cells),
//   |v_neg,avg|  = solid-volume-weighted mean of |v_y| over the bed cells with v_y < 0,
// so f_neg |v_neg,avg| = sum_{v_y<0} eps_s |v_y| V_cell / sum eps_s V_cell, the downward solid volume flux
// averaged over the bed's solids.

struct DownflowSums {
  double bed_solid_volume        = 0.0; // sum over bed cells of eps_s V_cell, m^3
  double down_solid_volume       = 0.0; // the same over bed cells with v_y < 0
  double down_solid_volume_speed = 0.0; // sum over those of eps_s V_cell |v_y|, m^4/s
};

inline DownflowSums &operator+=(DownflowSums &a, const DownflowSums &b)
{
  a.bed_solid_volume += b.bed_solid_volume;
  a.down_solid_volume += b.down_solid_volume;
  a.down_solid_volume_speed += b.down_solid_volume_speed;
  return a;
}

inline DownflowSums downflow_sums(const CellGrid &g, const CellMeans *m, double threshold = kOccupiedSolidFraction,
                                  double max_height = std::numeric_limits<double>::infinity())
{
  DownflowSums s;
  const double vc = cell_volume(g);
  for (long c = 0; c < cell_count(g); ++c) {
    if (!(m[c].solid_fraction > threshold)) continue;
    if (layer_centre_height(g, cell_ijk(g, c).j) > max_height) continue;
    const double vs = m[c].solid_fraction * vc;
    s.bed_solid_volume += vs;
    if (m[c].velocity.y < 0.0) {
      s.down_solid_volume += vs;
      s.down_solid_volume_speed += vs * -m[c].velocity.y;
    }
  }
  return s;
}

struct CounterCurrentCirculation {
  double fraction_moving_down = 0.0; // f_neg
  double mean_downward_speed  = 0.0; // |v_neg,avg|, m/s
  double mass_flow            = 0.0; // mdot, kg/s
};

// eq. 3.6: mdot = rho_p eps_s,b f_neg |v_neg,avg| A_d.
inline CounterCurrentCirculation counter_current_circulation(const DownflowSums &s, double rho_p, double bulk_solid_fraction,
                                                             double distributor_area)
{
  CounterCurrentCirculation r;
  if (s.bed_solid_volume > 0.0) r.fraction_moving_down = s.down_solid_volume / s.bed_solid_volume;
  if (s.down_solid_volume > 0.0) r.mean_downward_speed = s.down_solid_volume_speed / s.down_solid_volume;
  r.mass_flow = rho_p * bulk_solid_fraction * r.fraction_moving_down * r.mean_downward_speed * distributor_area;
  return r;
}

// ---------------------------------------------------------------------------------------------------------
// Convective and diffusive power (eq. 3.8-3.9), per cell and summed. Only the first dim directions count.

// A cell's convective power, the term of eq. 3.8: sum_i |mdot_i| v_i^2 = sum_i rho_p eps_s A_i |v_i|^3 (W).
inline double cell_convective_power(const CellGrid &g, double rho_p, const CellMeans &m)
{
  double p = 0.0;
  for (int a = 0; a < g.dim; ++a) {
    const double v = component(m.velocity, a);
    p += std::fabs(cell_mass_flow(g, rho_p, m, a)) * v * v;
  }
  return p;
}

// A cell's net particle mass flow rate Mdot of eq. 3.9: the magnitude of the vector of its mass flows,
// |(mdot_x, mdot_y, mdot_z)| = rho_p eps_s sqrt(sum_i (A_i v_i)^2) (kg/s). A choice: the seed names it only.
inline double cell_net_mass_flow(const CellGrid &g, double rho_p, const CellMeans &m)
{
  double s = 0.0;
  for (int a = 0; a < g.dim; ++a) {
    const double f = cell_mass_flow(g, rho_p, m, a);
    s += f * f;
  }
  return std::sqrt(s);
}

// A cell's diffusive power, the term of eq. 3.9: Mdot theta (W), theta the cell's granular temperature.
inline double cell_diffusive_power(const CellGrid &g, double rho_p, const CellMeans &m)
{
  return cell_net_mass_flow(g, rho_p, m) * m.granular_temperature;
}

// P_c, eq. 3.8: the sum over cells of cell_convective_power.
inline double convective_power(const CellGrid &g, double rho_p, const CellMeans *m)
{
  double p = 0.0;
  for (long c = 0; c < cell_count(g); ++c) p += cell_convective_power(g, rho_p, m[c]);
  return p;
}

// P_d, eq. 3.9: the sum over cells of cell_diffusive_power.
inline double diffusive_power(const CellGrid &g, double rho_p, const CellMeans *m)
{
  double p = 0.0;
  for (long c = 0; c < cell_count(g); ++c) p += cell_diffusive_power(g, rho_p, m[c]);
  return p;
}

// ---------------------------------------------------------------------------------------------------------
// Pressure.

// Pressure drop between two heights above the grid bottom, p(low) - p(high), from a cross-section-averaged
// pressure profile (n_y values at the layer centres, e.g. cross_section_profile of the gas pressure), linear
// between layer centres and continued linearly over the outer half layers (interpolate_profile), so that the drop
// from the distributor (height 0) includes the lowest half layer (seed Fig. 3.2: the net drop across the bed).
inline double pressure_drop(const CellGrid &g, const std::vector<double> &pressure_profile, double low, double high)
{
  return interpolate_profile(g, pressure_profile, low) - interpolate_profile(g, pressure_profile, high);
}

// Pressure drop that carries the bed's weight, m_bed g / A (seed chapter 3: what a uniformly fluidized bed shows;
// multiply by 1 - rho_g / rho_p for buoyancy).
inline double bed_weight_pressure_drop(double bed_mass, double gravity, double area)
{
  return bed_mass * gravity / area;
}

} // namespace fluidbed::kernels
