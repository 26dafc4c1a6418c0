// Pressure measurements in the gas: cross-section-averaged pressure at given heights (the bed's pressure drop,
// seed ch. 2-3) and point probes (seed fig. 2.11, Tsuji's probe 200 mm above the distributor), as monitor columns.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "fluidbed/domain.hpp"
#include "fluidbed/fluid.hpp"
#include "fluidbed/grids.hpp"

namespace fluidbed {

struct GasProbes {
  std::vector<PetscReal>                heights; // -probe_heights, m above the distributor
  std::vector<std::array<PetscReal, 3>> points;  // -probe_points
  std::vector<PetscReal>                values;  // last measurement: heights first, then points (Pa)
};

PetscErrorCode GasProbesSetFromOptions(MPI_Comm comm, const Domain &domain, GasProbes *probes);
// Column names for monitor.csv: p_y<height in mm, '_' for the decimal point>mm_avg, then p_probe<n>.
void           GasProbesColumns(const GasProbes &probes, std::vector<std::string> *names);
PetscErrorCode GasProbesMeasure(GasProbes *probes, Fluid *fluid, const Domain &domain, const FluidGrid &grid);
// The gas pressure averaged over each horizontal layer of the fluid grid (n_y values at the layer centres, Pa), on
// every rank.
PetscErrorCode GasPressureProfile(Fluid *fluid, const Domain &domain, const FluidGrid &grid, std::vector<PetscReal> *profile);

} // namespace fluidbed
