// Pressure measurements in the gas: cross-section-averaged pressure at given heights (the bed's pressure drop,
// seed ch. 2-3) and point probes (seed fig. 2.11, Tsuji's probe 200 mm above the distributor), as monitor columns.
#pragma once

#include <memory>
#include <vector>

#include "fluidbed/domain.hpp"
#include "fluidbed/fluid.hpp"
#include "fluidbed/grids.hpp"
#include "fluidbed/outputs.hpp"

namespace fluidbed {

// Reads -probe_heights and -probe_points and, with the gas on and a probe given, creates the probes as an output
// of the run (*out NULL otherwise): monitor.csv columns p_y<height in mm, '_' for the decimal point>mm_avg, then
// p_probe<n>, measured for every row (Pa).
PetscErrorCode GasProbesCreate(const RunView &run, std::unique_ptr<Output> *out);
// The gas pressure averaged over each horizontal layer of the fluid grid (n_y values at the layer centres, Pa), on
// every rank.
PetscErrorCode GasPressureProfile(Fluid *fluid, const Domain &domain, const FluidGrid &grid, std::vector<PetscReal> *profile);

} // namespace fluidbed
