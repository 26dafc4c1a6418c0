// The checkpoints as an output of the run (include/fluidbed/outputs.hpp): the schedule, each checkpoint written
// atomically with the run's state and every output's part of it, and the restart from one; with the output schedule's
// options and the clean-up of the output directory.
#include "fluidbed/checkpoint_check.hpp"
#include "fluidbed/options.hpp"
#include "fluidbed/simulation.hpp"

#include <cstdio>
#include <string>
#include <vector>

namespace fluidbed {

namespace {
// 64-bit counters as HDF5 attributes: PETSc 3.18 writes no 64-bit integer attributes, doubles are exact below 2^53.
PetscErrorCode WriteCount(PetscViewer viewer, const char *name, PetscInt64 value)
{
  const PetscReal v = (PetscReal)value;
  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", name, PETSC_REAL, &v));
  PetscFunctionReturn(0);
}
PetscErrorCode ReadCount(PetscViewer viewer, const char *name, PetscInt64 *value)
{
  PetscReal v;
  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", name, PETSC_REAL, NULL, &v));
  *value = (PetscInt64)v;
  PetscFunctionReturn(0);
}
PetscErrorCode HasAttribute(PetscViewer viewer, const char *name, PetscBool *has)
{
  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5HasAttribute(viewer, "/", name, has));
  PetscFunctionReturn(0);
}

// What a checkpoint's state was made with and a restart may not change: the physics (domain, particles, contacts,
// gas, drag) and the layout of the saved fields (grids). Written as attributes scene_<key>; a rescue restart may
// change everything else (the time step, substeps, solvers, tolerances, guards, outputs).
struct SceneValue {
  std::string key, option; // attribute key, and the option a user changes
  PetscReal   value = 0;
  std::string text; // for named choices (is_text)
  bool        is_text = false;
};

std::vector<SceneValue> SceneValues(const Simulation *sim)
{
  std::vector<SceneValue> v;
  auto                    num     = [&](const char *key, const char *option, PetscReal x) { v.push_back({key, option, x, "", false}); };
  const Domain           &d       = sim->domain;
  const char             *axes[3] = {"x", "y", "z"};
  num("domain_lx", "-domain_lx", d.len[0]);
  num("domain_ly", "-domain_ly", d.len[1]);
  num("domain_lz", "-domain_lz", d.len[2]);
  for (int a = 0; a < 3; ++a) {
    num((std::string("domain_periodic_") + axes[a]).c_str(), (std::string("-domain_periodic_") + axes[a]).c_str(), d.periodic[a] ? 1 : 0);
    num((std::string("gravity_") + axes[a]).c_str(), "-gravity", d.gravity[a]);
    num((std::string("grid_n") + axes[a]).c_str(), (std::string("-grid_n") + axes[a]).c_str(), (PetscReal)sim->grids.fluid.n[a]);
    num((std::string("pgrid_ratio_") + axes[a]).c_str(), "-pgrid_ratio", (PetscReal)sim->grids.particle.ratio[a]);
  }
  num("domain_top_outlet", "-domain_top_outlet", d.top_outlet ? 1 : 0);
  if (sim->dem) {
    const DemParams &p = DemGetParams(sim->dem);
    num("particle_diameter_min", "-particle_diameter_min", sim->props.d_min);
    num("particle_diameter_max", "-particle_diameter_max", sim->props.d_max);
    num("particle_density", "-particle_density", sim->props.density);
    num("dem_kn", "-dem_kn", p.pp.kn);
    num("dem_kt", "-dem_kt", p.pp.kt);
    num("dem_e", "-dem_e", p.e);
    num("dem_mu", "-dem_mu", p.pp.mu);
    num("wall_kn", "-wall_kn", p.pw.kn);
    num("wall_kt", "-wall_kt", p.pw.kt);
    num("wall_e", "-wall_e", p.wall_e);
    num("wall_mu", "-wall_mu", p.pw.mu);
    num("dem_pseudo2d", "-dem_pseudo2d", p.pseudo2d ? 1 : 0);
  }
  // The inflow is not part of it: a bed packed or settled at one flow is continued at another (the boundary
  // conditions of the next stage of a study, as tests/coupling/test_small_bed.py does).
  if (sim->fluid) {
    PetscReal rho, mu;
    FluidGetGasProperties(sim->fluid, &rho, &mu);
    num("fluid_rho", "-fluid_rho", rho);
    num("fluid_mu", "-fluid_mu", mu);
    num("fluid_model_b", "-fluid_model", FluidIsModelB(sim->fluid) ? 1 : 0);
  }
  if (sim->coupling) {
    num("couple_grid_two", "-couple_grid", CouplingOnParticleGrid(sim->coupling) ? 1 : 0);
    v.push_back({"drag_model", "-drag_model", 0, CouplingDragName(sim->coupling), true});
  }
  return v;
}

PetscErrorCode WriteScene(const Simulation *sim, PetscViewer viewer)
{
  PetscFunctionBeginUser;
  for (const SceneValue &x : SceneValues(sim)) {
    const std::string name = "scene_" + x.key;
    if (x.is_text) PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", name.c_str(), PETSC_STRING, x.text.c_str()));
    else PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", name.c_str(), PETSC_REAL, &x.value));
  }
  PetscFunctionReturn(0);
}

std::string Show(PetscReal x)
{
  char buf[64];
  snprintf(buf, sizeof(buf), "%.10g", (double)x);
  return buf;
}

// Compares the options' scene with the checkpoint's; sets *has to whether the checkpoint records one (older
// checkpoints do not).
PetscErrorCode CheckScene(const Simulation *sim, PetscViewer viewer, const char *file, PetscBool *has)
{
  PetscFunctionBeginUser;
  PetscCall(HasAttribute(viewer, "scene_domain_lx", has));
  if (!*has) PetscFunctionReturn(0);
  for (const SceneValue &x : SceneValues(sim)) {
    const std::string name = "scene_" + x.key;
    PetscBool         present;
    std::string       saved, now;
    PetscCall(HasAttribute(viewer, name.c_str(), &present));
    if (!present) {
      saved = "(none)";
      now   = x.is_text ? x.text : Show(x.value);
    } else if (x.is_text) {
      char *t = NULL;
      PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", name.c_str(), PETSC_STRING, NULL, &t));
      saved = t;
      now   = x.text;
      PetscCall(PetscFree(t));
      if (saved == now) continue;
    } else {
      PetscReal y;
      PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", name.c_str(), PETSC_REAL, NULL, &y));
      if (PetscAbsReal(y - x.value) <= 1e-12 * PetscMax(PetscAbsReal(y), PetscAbsReal(x.value))) continue;
      saved = Show(y);
      now   = Show(x.value);
    }
    SETERRQ(sim->comm, PETSC_ERR_USER_INPUT,
            "-restart %s was written with %s %s, the options give %s: it sets the physics or the layout of the saved state and cannot "
            "change on a restart (a rescue may change -dem_dt_factor, -couple_substeps, the -fluid_p_ solver options, -fluid_cfl, "
            "-guard_* and the outputs)",
            file, x.option.c_str(), saved.c_str(), now.c_str());
  }
  PetscFunctionReturn(0);
}

// Every -checkpoint_interval of simulated time and at the last step (when it is set), after every other output's Step
// of the step (registered after them): the guards are checked first, so that every checkpoint holds a state that
// passed them, since it is what a rescue continues from. Restart reads -restart back.
class Checkpoints final : public Output {
public:
  explicit Checkpoints(Simulation *sim) : sim_(sim), next_(sim->output.checkpoint_interval) {}
  const char *Name() const override { return "checkpoints"; }

  PetscErrorCode Step(const RunView &run) override
  {
    const PetscReal interval = sim_->output.checkpoint_interval, eps = 0.5 * run.dt;

    PetscFunctionBeginUser;
    if (interval <= 0) PetscFunctionReturn(0);
    const PetscBool due = (PetscBool)(sim_->dem ? run.step >= StepAtTime(sim_, next_) : run.time >= next_ - eps);
    if (!due && !run.last) PetscFunctionReturn(0);
    PetscCall(GuardsCheckParticles(sim_->guards, run.step, run.time, PETSC_TRUE));
    if (GuardsStopped(sim_->guards)) PetscFunctionReturn(0);
    while (next_ <= run.time + eps) next_ += interval;
    PetscCall(Write());
    PetscFunctionReturn(0);
  }

  // The schedule: the time of the next checkpoint.
  PetscErrorCode CheckpointWrite(const RunView &, PetscViewer viewer) override
  {
    PetscFunctionBeginUser;
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "checkpoint_next", PETSC_REAL, &next_));
    PetscFunctionReturn(0);
  }

  PetscErrorCode CheckpointRead(const RunView &, PetscViewer viewer) override
  {
    PetscFunctionBeginUser;
    PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", "checkpoint_next", PETSC_REAL, NULL, &next_));
    PetscFunctionReturn(0);
  }

  PetscErrorCode Restart(const RunView &) override
  {
    PetscFunctionBeginUser;
    PetscCall(Read());
    PetscFunctionReturn(0);
  }

private:
  // The checkpoint file: the run's own state, then every output's part.
  PetscErrorCode Write()
  {
    Simulation *sim = sim_;
    PetscMPIInt size;

    PetscFunctionBeginUser;
    PetscCallMPI(MPI_Comm_size(sim->comm, &size));
    // Migration, contact-history sync and neighbour lists now, as a restart does when it loads the checkpoint: both
    // runs then continue from the same ownership of particles by ranks (the coupling's cell sums depend on it).
    if (sim->dem) PetscCall(DemRebuild(sim->dem));
    const RunView run = SimulationView(sim);
    PetscInt64    bytes;
    PetscCall(StateHDF5Bytes(sim->swarm, sim->fluid, PETSC_TRUE, &bytes));
    PetscCall(WriteHDF5File(sim->comm, sim->output.checkpoint_file, bytes, [&](PetscViewer viewer) {
      PetscFunctionBeginUser;
      PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", kCheckpointMarker, PETSC_INT, &kCheckpointFormat)); // snapshots have none
      PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "time", PETSC_REAL, &sim->time));
      PetscCall(WriteCount(viewer, "step", sim->step));
      if (sim->dem) PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "dt", PETSC_REAL, &DemGetParams(sim->dem).dt));
      PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "dim", PETSC_INT, &sim->domain.dim));
      PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "ranks", PETSC_INT, &size));
      if (sim->dem) {
        PetscCall(WriteCount(viewer, "particles_outlet", DemGetStats(sim->dem)->outlet_removed));
        PetscCall(WriteCount(viewer, "particles_inserted", sim->inserted.count));
        PetscCall(WriteCount(viewer, "particles_lost", DemGetStats(sim->dem)->lost.count));
        PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "dem_dt_factor", PETSC_REAL, &DemGetParams(sim->dem).dt_factor));
      }
      PetscCall(WriteCount(viewer, "step_origin", sim->step_origin));
      PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "time_origin", PETSC_REAL, &sim->time_origin));
      const PetscInt substeps = sim->coupling ? CouplingSubsteps(sim->coupling) : 1;
      PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "couple_substeps", PETSC_INT, &substeps));
      PetscCall(WriteScene(sim, viewer));
      PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "monitor_next", PETSC_REAL, &sim->monitor.next));
      if (sim->swarm) PetscCall(ParticlesWriteHDF5(sim->swarm, viewer, PETSC_TRUE));
      if (sim->fluid) PetscCall(FluidWriteHDF5(sim->fluid, viewer, PETSC_TRUE));
      if (sim->coupling) PetscCall(CouplingWriteHDF5(sim->coupling, viewer));
      PetscCall(OutputListCheckpointWrite(sim->outputs, run, viewer)); // the schedule, the snapshot series, the averages, ...
      PetscFunctionReturn(0);
    }));
    PetscFunctionReturn(0);
  }

  // -restart: the run's own state first, then every output's part (which sees the run at the checkpoint).
  PetscErrorCode Read()
  {
    Simulation     *sim = sim_;
    OutputSchedule &o   = sim->output;
    PetscViewer     viewer;
    PetscInt        dim;
    PetscReal       dt;

    PetscFunctionBeginUser;
    PetscCall(CheckpointValidate(sim->comm, o.restart)); // a wrong file gives one line, not HDF5's error stack
    PetscCall(PetscViewerHDF5Open(sim->comm, o.restart, FILE_MODE_READ, &viewer));
    PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", "dim", PETSC_INT, NULL, &dim));
    PetscCheck(dim == sim->domain.dim, sim->comm, PETSC_ERR_USER_INPUT, "-restart %s holds a %dD run; -domain_dim is %d", o.restart,
               (int)dim, (int)sim->domain.dim);
    PetscBool has_scene, has, new_dt = PETSC_FALSE;
    // what the checkpoint simulates first, then the scene of what it holds
    PetscCall(HasAttribute(viewer, "dt", &has));
    PetscCheck(!sim->dem || has, sim->comm, PETSC_ERR_USER_INPUT, "-restart %s holds no particles; the options turn them on", o.restart);
    PetscCall(PetscViewerHDF5HasGroup(viewer, "/fluid", &has));
    PetscCheck(!sim->fluid || has, sim->comm, PETSC_ERR_USER_INPUT, "-restart %s holds no gas state; the options turn the gas on",
               o.restart);
    PetscCall(CheckScene(sim, viewer, o.restart, &has_scene));
    PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", "time", PETSC_REAL, NULL, &sim->time));
    PetscCall(ReadCount(viewer, "step", &sim->step));
    PetscCall(HasAttribute(viewer, "step_origin", &has));
    if (has) {
      PetscCall(ReadCount(viewer, "step_origin", &sim->step_origin));
      PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", "time_origin", PETSC_REAL, NULL, &sim->time_origin));
    }
    if (sim->dem) {
      PetscBool has_dt;
      PetscCall(HasAttribute(viewer, "dt", &has_dt));
      PetscCheck(has_dt, sim->comm, PETSC_ERR_USER_INPUT, "-restart %s holds no particles; the options turn them on", o.restart);
      PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", "dt", PETSC_REAL, NULL, &dt));
      new_dt = (PetscBool)(PetscAbsReal(dt - DemGetParams(sim->dem).dt) > 1e-12 * dt);
      // a checkpoint that does not record its scene cannot tell a new time step from new physics
      PetscCheck(!new_dt || has_scene, sim->comm, PETSC_ERR_USER_INPUT,
                 "-restart %s was run with dt = %.10g s, the options give %.10g s: restart with the same particle and contact options",
                 o.restart, (double)dt, (double)DemGetParams(sim->dem).dt);
      if (new_dt) {
        // a rescue with another -dem_dt_factor: the steps count on from the checkpoint with the new length
        PetscReal factor = 0;
        PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", "dem_dt_factor", PETSC_REAL, NULL, &factor));
        sim->step_origin = sim->step;
        sim->time_origin = sim->time;
        PetscCall(PetscPrintf(sim->comm, "Restart with a new time step: dt %.6g s -> %.6g s (-dem_dt_factor %.6g -> %.6g)\n", (double)dt,
                              (double)DemGetParams(sim->dem).dt, (double)factor, (double)DemGetParams(sim->dem).dt_factor));
      }
      PetscCall(ReadCount(viewer, "particles_outlet", &DemGetStats(sim->dem)->outlet_removed));
      PetscCall(HasAttribute(viewer, "particles_lost", &has));
      if (has) PetscCall(ReadCount(viewer, "particles_lost", &DemGetStats(sim->dem)->lost.count));
    }
    PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", "monitor_next", PETSC_REAL, NULL, &sim->monitor.next));
    if (sim->swarm) {
      PetscCall(ParticlesReadHDF5(sim->swarm, viewer, sim->domain, sim->grids.particle));
      // inserted = present + left through the outlet + lost, across restarts
      PetscCall(HasAttribute(viewer, "particles_inserted", &has));
      if (has) PetscCall(ReadCount(viewer, "particles_inserted", &sim->inserted.count));
      else {
        PetscCall(ParticlesGlobalCount(sim->swarm, &sim->inserted.count));
        sim->inserted.count += DemGetStats(sim->dem)->outlet_removed;
      }
    }
    if (sim->fluid) {
      PetscBool has;
      PetscCall(PetscViewerHDF5HasGroup(viewer, "/fluid", &has));
      PetscCheck(has, sim->comm, PETSC_ERR_USER_INPUT, "-restart %s holds no gas state; the options turn the gas on", o.restart);
      PetscCall(FluidReadHDF5(sim->fluid, viewer));
    }
    if (sim->coupling) PetscCall(CouplingReadHDF5(sim->coupling, viewer));
    PetscCall(OutputListCheckpointRead(sim->outputs, SimulationView(sim), viewer)); // once the run's own state is read
    PetscCall(PetscViewerDestroy(&viewer));
    PetscFunctionReturn(0);
  }

  Simulation *sim_;
  PetscReal   next_; // simulated time of the next checkpoint (s)
};
} // namespace

PetscErrorCode OutputScheduleSetFromOptions(Simulation *sim)
{
  OutputSchedule &o       = sim->output;
  PetscBool       reserve = PETSC_TRUE;

  PetscFunctionBeginUser;
  PetscOptionsBegin(sim->comm, "", "HDF5 output, checkpoints and restart", "Output");
  PetscCall(OptionsReal(PetscOptionsObject, "-output_interval",
                        "Simulated time between HDF5 snapshots (snapshot_NNNNN.h5 + particles.xmf for ParaView; 0: none)", "s",
                        NonNegative(), &o.interval, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-checkpoint_interval",
                        "Simulated time between checkpoints (0: none); the last step is always checkpointed when set", "s", NonNegative(),
                        &o.checkpoint_interval, NULL));
  PetscCall(OptionsString(PetscOptionsObject, "-checkpoint_file",
                          "Checkpoint path (default <output_dir>/checkpoint.h5; its directory must exist); written to .tmp, then renamed",
                          "a file path", o.checkpoint_file, sizeof(o.checkpoint_file), NULL));
  PetscCall(OptionsString(PetscOptionsObject, "-restart",
                          "Continue from this checkpoint (any number of ranks); the scene's options must match it",
                          "a checkpoint file (checkpoint.h5)", o.restart, sizeof(o.restart), NULL));
  PetscCall(OptionsBool(PetscOptionsObject, "-output_reserve",
                        "Reserve each HDF5 file's space before writing it, so that a full disk or a file-size limit stops the run cleanly "
                        "on every rank (off: a failure inside parallel HDF5 aborts the job, still with exit status 3)",
                        &reserve, NULL));
  PetscOptionsEnd();
  OutputSetReserve(reserve);
  if (!o.checkpoint_file[0])
    PetscCall(PetscSNPrintf(o.checkpoint_file, sizeof(o.checkpoint_file), "%s/%s", sim->run.output_dir, run_files::checkpoint));
  PetscFunctionReturn(0);
}

PetscErrorCode SimulationRemoveStaleOutput(Simulation *sim)
{
  const OutputSchedule &o   = sim->output;
  const std::string     dir = sim->run.output_dir;

  PetscFunctionBeginUser;
  if (!o.restart[0]) {
    std::vector<std::string> also; // this run's checkpoint, wherever -checkpoint_file keeps it
    if (o.checkpoint_interval > 0) also.push_back(o.checkpoint_file);
    PetscCall(RemovePreviousRun(sim->comm, dir, also, {sim->inserted.file}));
  } else PetscCall(OutputListRemoveStale(sim->outputs, SimulationView(sim)));
  PetscFunctionReturn(0);
}

PetscErrorCode CheckpointsCreate(Simulation *sim, std::unique_ptr<Output> *out)
{
  PetscFunctionBeginUser;
  *out = std::make_unique<Checkpoints>(sim);
  PetscFunctionReturn(0);
}

} // namespace fluidbed
