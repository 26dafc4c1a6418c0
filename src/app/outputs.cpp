// The outputs of a run, registered in one place (include/fluidbed/outputs.hpp): the run's own monitor.csv columns
// (the particles, the gas, the coupling), the analyses and the snapshot series; and the view of the run they see.
#include "fluidbed/averaging.hpp"
#include "fluidbed/probes.hpp"
#include "fluidbed/simulation.hpp"

namespace fluidbed {

namespace {

// Global sums over the particles (ComputeParticleTotals); the last row's are kept for the summary.
class ParticleColumns final : public Output {
public:
  ParticleColumns(Dem *dem, ParticleTotals *last) : dem_(dem), last_(last) {}
  const char *Name() const override { return "particles"; }

  void Columns(std::vector<MonitorColumn> *columns) const override
  {
    columns->insert(columns->end(), {{"particles", nullptr},
                                     {"contacts_per_particle", "%.6g"},
                                     {"ke_trans", "%.10e"},
                                     {"ke_rot", "%.10e"},
                                     {"pe_grav", "%.10e"},
                                     {"momentum_x", "%.10e"},
                                     {"momentum_y", "%.10e"},
                                     {"momentum_z", "%.10e"},
                                     {"max_speed", "%.6e"},
                                     {"max_overlap_rel", "%.6e"},
                                     {"outlet_removed", nullptr},
                                     {"rebuilds", nullptr}});
  }

  PetscErrorCode Values(const RunView &, std::vector<PetscReal> *values) override
  {
    const ParticleTotals &t = *last_;

    PetscFunctionBeginUser;
    PetscCall(ComputeParticleTotals(dem_, last_));
    values->insert(values->end(), {(PetscReal)t.count, t.contacts_per_particle, t.ke_trans, t.ke_rot, t.pe_grav, t.momentum[0],
                                   t.momentum[1], t.momentum[2], t.max_speed, t.max_overlap_rel,
                                   (PetscReal)DemGetStats(dem_)->outlet_removed, (PetscReal)DemGetStats(dem_)->rebuilds});
    PetscFunctionReturn(0);
  }

private:
  Dem            *dem_;
  ParticleTotals *last_;
};

// The gas's last step and pressure solve (FluidGetStats).
class GasColumns final : public Output {
public:
  const char *Name() const override { return "gas"; }

  void Columns(std::vector<MonitorColumn> *columns) const override
  {
    columns->insert(columns->end(), {{"fluid_dt", "%.6e"},
                                     {"gas_max_speed", "%.6e"},
                                     {"gas_courant", "%.4f"},
                                     {"ksp_its", nullptr},
                                     {"ksp_rnorm", "%.6e"},
                                     {"ksp_time", "%.6e"},
                                     {"max_div", "%.6e"},
                                     {"div_scale", "%.6e"},
                                     {"inflow", "%.15e"},
                                     {"outflow", "%.15e"}});
  }

  PetscErrorCode Values(const RunView &run, std::vector<PetscReal> *values) override
  {
    const FluidStats &s = FluidGetStats(run.fluid);

    PetscFunctionBeginUser;
    values->insert(values->end(), {s.dt, s.max_speed, s.courant, (PetscReal)s.ksp_its, s.ksp_rnorm, s.ksp_time, s.max_div, s.rhs_scale,
                                   s.inflow, s.outflow});
    PetscFunctionReturn(0);
  }
};

// The drag between the phases (action and reaction) and the void fraction of the coupling cells (CouplingGetStats).
class CouplingColumns final : public Output {
public:
  CouplingColumns(const Coupling *coupling, PetscInt dim) : coupling_(coupling), dim_(dim) {}
  const char *Name() const override { return "coupling"; }

  void Columns(std::vector<MonitorColumn> *columns) const override
  {
    const char *axes[3] = {"x", "y", "z"};
    for (const char *what : {"drag_particles_", "drag_gas_"})
      for (PetscInt a = 0; a < dim_; ++a) columns->push_back({std::string(what) + axes[a]});
    for (const char *name : {"eps_min", "eps_max", "eps_clamped_cells"}) columns->push_back({name});
  }

  PetscErrorCode Values(const RunView &, std::vector<PetscReal> *values) override
  {
    const CouplingStats &cs = CouplingGetStats(coupling_);

    PetscFunctionBeginUser;
    values->insert(values->end(), cs.drag_particles, cs.drag_particles + dim_);
    values->insert(values->end(), cs.drag_gas, cs.drag_gas + dim_);
    values->insert(values->end(), {cs.eps_min, cs.eps_max, (PetscReal)cs.clamped});
    PetscFunctionReturn(0);
  }

private:
  const Coupling *coupling_;
  PetscInt        dim_; // the drag's components
};

} // namespace

RunView SimulationView(const Simulation *sim)
{
  const PetscReal dt = sim->dem ? DemGetParams(sim->dem).dt : sim->fluid ? FluidGetStats(sim->fluid).dt : 0.0;
  return {sim->comm,           sim->domain,         sim->grids, sim->props, sim->swarm, sim->fluid,
          sim->run.output_dir, sim->output.restart, sim->step,  sim->time,  dt};
}

PetscErrorCode SimulationAddOutputs(Simulation *sim)
{
  const RunView run  = SimulationView(sim);
  OutputList   *list = &sim->outputs;

  PetscFunctionBeginUser;
  // monitor.csv's columns from left to right follow this order, and so do the outputs' summary entries and calls
  if (sim->dem) PetscCall(OutputListAdd(list, std::make_unique<ParticleColumns>(sim->dem, &sim->totals)));
  if (sim->fluid) PetscCall(OutputListAdd(list, std::make_unique<GasColumns>()));
  if (sim->coupling) PetscCall(OutputListAdd(list, std::make_unique<CouplingColumns>(sim->coupling, sim->domain.dim)));
  PetscCall(OutputListCreate(list, run, GasProbesCreate));
  PetscCall(OutputListCreate(list, run, BedAveragesCreate, &sim->averages));
  {
    std::unique_ptr<Output> snapshots;
    PetscCall(SnapshotSeriesCreate(sim->output.interval, &snapshots));
    PetscCall(OutputListAdd(list, std::move(snapshots)));
  }
  PetscFunctionReturn(0);
}

} // namespace fluidbed
