// The outputs of a run, registered in one place (include/fluidbed/outputs.hpp): the guards' report, the run's own
// entries, the monitor.csv columns of the particles, the gas and the coupling (with their summary entries), the tracked
// particles, the final tables, the analyses, the snapshot series, the checkpoints, the scene's entries and
// summary.json; and the view of the run they see.
#include "fluidbed/averaging.hpp"
#include "fluidbed/probes.hpp"
#include "fluidbed/simulation.hpp"

namespace fluidbed {

namespace {

// Global sums over the particles (ComputeParticleTotals); the last row's are kept for the summary, with the DEM's
// time step, counts and speed.
class ParticleColumns final : public Output {
public:
  explicit ParticleColumns(Simulation *sim) : sim_(sim), dem_(sim->dem), last_(&sim->totals) {}
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

  PetscErrorCode AddSummary(const RunView &, JsonWriter *json) override
  {
    const ParticleTotals &t     = *last_;
    const DemParams      &p     = DemGetParams(dem_);
    const double          steps = (double)t.count * (double)sim_->steps_run, wall = sim_->wall_run; // particle-steps
    PetscMPIInt           size;

    PetscFunctionBeginUser;
    PetscCallMPI(MPI_Comm_size(sim_->comm, &size));
    json->Number("dt", p.dt);
    json->Number("t_cr", p.t_cr);
    json->Number("t_cr_wall", p.t_cr_wall);
    json->Integer("particles", (long long)t.count);
    json->Integer("particles_inserted", (long long)sim_->inserted.count);
    json->Integer("particles_outlet", (long long)DemGetStats(dem_)->outlet_removed);
    json->Integer("particles_lost", (long long)DemGetStats(dem_)->lost.count); // through a wall or in migration (the escape guard)
    json->Integer("neighbour_rebuilds", (long long)DemGetStats(dem_)->rebuilds);
    json->Integer("storage_sorts", (long long)DemGetStats(dem_)->storage_sorts);
    json->Number("kinetic_energy", t.ke_trans + t.ke_rot);
    json->Number("contacts_per_particle", t.contacts_per_particle);
    json->Number("particle_steps_per_second", wall > 0 ? steps / wall : 0.0);
    json->Number("particle_steps_per_second_per_rank", wall > 0 ? steps / wall / size : 0.0);
    PetscFunctionReturn(0);
  }

private:
  const Simulation *sim_;
  Dem              *dem_;
  ParticleTotals   *last_;
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

  // "fluid": the steps, solves and flows of the whole run (FluidAddSummary).
  PetscErrorCode AddSummary(const RunView &run, JsonWriter *json) override
  {
    PetscFunctionBeginUser;
    PetscCall(FluidAddSummary(run.fluid, json));
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
  const RunView           run  = SimulationView(sim);
  OutputList             *list = &sim->outputs;
  std::unique_ptr<Output> out;

  PetscFunctionBeginUser;
  // monitor.csv's columns from left to right follow this order, and so do the outputs' summary entries and calls:
  // the guards' report first ("status" leads summary.json), the checkpoints after every output with a Step (a
  // checkpoint holds what they wrote at its step), summary.json last (the entries of all)
  PetscCall(GuardReportCreate(sim, &out));
  PetscCall(OutputListAdd(list, std::move(out)));
  PetscCall(RunEntriesCreate(sim, &out));
  PetscCall(OutputListAdd(list, std::move(out)));
  if (sim->dem) PetscCall(OutputListAdd(list, std::make_unique<ParticleColumns>(sim)));
  if (sim->fluid) PetscCall(OutputListAdd(list, std::make_unique<GasColumns>()));
  if (sim->coupling) PetscCall(OutputListAdd(list, std::make_unique<CouplingColumns>(sim->coupling, sim->domain.dim)));
  PetscCall(OutputListCreate(list, run, ParticleTrackCreate));
  PetscCall(FinalTablesCreate(run, sim->run.write_particles, &out)); // before the analyses' final files, as they were
  PetscCall(OutputListAdd(list, std::move(out)));
  PetscCall(OutputListCreate(list, run, GasProbesCreate));
  PetscCall(OutputListCreate(list, run, BedAveragesCreate, &sim->averages));
  PetscCall(SnapshotSeriesCreate(sim->output.interval, &out));
  PetscCall(OutputListAdd(list, std::move(out)));
  PetscCall(CheckpointsCreate(sim, &out));
  PetscCall(OutputListAdd(list, std::move(out)));
  PetscCall(SceneEntriesCreate(sim, &out));
  PetscCall(OutputListAdd(list, std::move(out)));
  PetscCall(SummaryFileCreate(sim, &out));
  PetscCall(OutputListAdd(list, std::move(out)));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
