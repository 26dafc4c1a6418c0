#include "fluidbed/simulation.hpp"
#include "fluidbed/checkpoint_check.hpp"
#include "fluidbed/options.hpp"

#include <cmath>
#include <string>

#include <csignal>

#include <sys/resource.h>

namespace fluidbed {

namespace {

PetscErrorCode RunControlSetFromOptions(MPI_Comm comm, RunControl *r)
{
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, "", "Run control", "Run");
  PetscCall(OptionsReal(PetscOptionsObject, "-t_final", "Simulated time to run", "s", NonNegative(1e6), &r->t_final, NULL));
  PetscCall(
    OptionsInt(PetscOptionsObject, "-max_steps", "Stop after this many steps (-1: no limit)", -1, PETSC_MAX_INT, &r->max_steps, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-progress_interval", "Wall-clock time between progress lines (0: none)", "s", NonNegative(),
                        &r->progress_interval, NULL));
  PetscCall(OptionsString(PetscOptionsObject, "-output_dir",
                          "Directory for the run's files (created if missing; a fresh run first removes a previous run's files from it)",
                          "a directory", r->output_dir, sizeof(r->output_dir), NULL));
  PetscCall(
    OptionsBool(PetscOptionsObject, "-output_particles", "Write particles.csv (sorted by id) at the end", &r->write_particles, NULL));
  PetscCall(OptionsBool(PetscOptionsObject, "-fluid", "Turn the gas phase on (-fluid_*, -fluid_bc_*, -inlet_*, -fluid_p_* options)",
                        &r->fluid, NULL));
  PetscCall(OptionsBool(PetscOptionsObject, "-particles", "Turn the particles (DEM) on", &r->particles, NULL));
  PetscOptionsEnd();
  PetscCheck(r->fluid || r->particles, comm, PETSC_ERR_USER_INPUT, "-particles 0 needs -fluid: there is nothing to simulate");
  PetscFunctionReturn(0);
}

std::string Duration(double s)
{
  // rounded to the unit shown first, so that 359.6 s reads 6 min 00 s, not 5 min 60 s
  char buf[64];
  if (s < 120) snprintf(buf, sizeof(buf), "%.0f s", s);
  else if (s < 7200) {
    const double r = std::round(s);
    snprintf(buf, sizeof(buf), "%.0f min %02.0f s", std::floor(r / 60), std::fmod(r, 60.0));
  } else {
    const double m = std::round(s / 60);
    snprintf(buf, sizeof(buf), "%.0f h %02.0f min", std::floor(m / 60), std::fmod(m, 60.0));
  }
  return buf;
}

} // namespace

PetscErrorCode SimulationCreate(MPI_Comm comm, Simulation **sim)
{
  PetscFunctionBeginUser;
  *sim         = new Simulation;
  (*sim)->comm = comm;
  PetscFunctionReturn(0);
}

PetscErrorCode SimulationSetUp(Simulation *sim)
{
  const double t0     = MPI_Wtime();
  PetscViewer  viewer = PETSC_VIEWER_STDOUT_(sim->comm);

  PetscFunctionBeginUser;
  PetscCall(PhaseLogRegister(&sim->log));
  PetscCall(RunControlSetFromOptions(sim->comm, &sim->run));
  PetscCall(OutputScheduleSetFromOptions(sim));
  const PetscBool restart = sim->output.restart[0] ? PETSC_TRUE : PETSC_FALSE;
  if (restart) PetscCall(CheckpointValidate(sim->comm, sim->output.restart)); // before the set-up, not after it
  PetscCall(DomainSetFromOptions(sim->comm, &sim->domain));
  if (sim->run.particles) PetscCall(ParticlePropsSetFromOptions(sim->comm, sim->domain, &sim->props));
  {
    // -pgrid_layout particles shares the initial particles among the ranks: known before insertion from a file
    const InitialPoints points = [&](std::vector<PetscReal> *xyz, PetscBool *known) -> PetscErrorCode {
      PetscFunctionBeginUser;
      *known = PETSC_FALSE;
      if (sim->run.particles && !restart) PetscCall(ParticlesInitialPositions(sim->comm, xyz, known));
      PetscFunctionReturn(0);
    };
    PetscCall(GridsCreate(sim->comm, sim->domain, sim->run.particles ? sim->props.d_max : 0.0, &sim->grids, points, sim->run.fluid));
  }
  if (sim->run.particles) {
    PetscCall(DemCreate(sim->comm, sim->domain, sim->grids.particle, sim->props, &sim->log, &sim->dem));
    PetscCall(DemCreateSwarm(sim->dem, &sim->swarm));
  }
  if (sim->run.fluid) {
    PetscCall(FluidCreate(sim->comm, sim->domain, sim->grids.fluid, &sim->log, &sim->fluid));
    PetscCall(FluidSetOutputDirectory(sim->fluid, sim->run.output_dir));
    PetscCall(FluidSetUp(sim->fluid));
  }
  if (sim->dem && sim->fluid)
    PetscCall(CouplingCreate(sim->comm, sim->domain, sim->grids, DemGetParticles(sim->dem), sim->fluid, &sim->log, &sim->coupling));
  PetscCall(GuardsCreate(sim->comm, sim->domain, sim->dem, sim->fluid, sim->coupling, &sim->log, &sim->guards));
  PetscCall(MakeDirectory(sim->comm, sim->run.output_dir));
  if (sim->output.checkpoint_interval > 0) PetscCall(CheckFileLocation(sim->comm, sim->output.checkpoint_file, "-checkpoint_file"));
  PetscCall(SimulationAddOutputs(sim));
  if (restart) PetscCall(OutputListRestart(sim->outputs, SimulationView(sim))); // the checkpoints output reads it
  else if (sim->dem) PetscCall(ParticlesInsert(sim->comm, sim->domain, sim->grids.particle, sim->props, sim->swarm, &sim->inserted));
  // Inputs read, nothing written yet: the output directory is cleared of what would mix with this run's files.
  PetscCall(SimulationRemoveStaleOutput(sim));
  OutputListColumns(sim->outputs, &sim->monitor.columns);
  PetscCall(MonitorCreate(sim->comm, sim->run.output_dir, sim->run.t_final, restart, sim->step, &sim->monitor));
  PetscCall(OutputListStart(sim->outputs, SimulationView(sim)));

  PetscCall(DomainView(sim->domain, viewer));
  PetscCall(GridsView(sim->grids, sim->domain, viewer));
  if (sim->dem) {
    PetscCall(PetscViewerASCIIPrintf(
      viewer, "Particles: %lld inserted, d = %.6g..%.6g mm, rho = %.6g kg/m^3, solid fraction of the insertion region %.3f\n",
      (long long)sim->inserted.count, 1e3 * sim->props.d_min, 1e3 * sim->props.d_max, (double)sim->props.density,
      (double)sim->inserted.solid_fraction_region));
    PetscCall(DemParamsView(DemGetParams(sim->dem), viewer));
  }
  if (sim->coupling) {
    PetscCall(CouplingView(sim->coupling, viewer));
    PetscCall(CouplingSetUp(sim->coupling)); // the gas velocity the first drag sees
  }
  if (sim->dem) PetscCall(DemSetUp(sim->dem, sim->swarm, restart));
  PetscCall(GuardsView(sim->guards, viewer));
  if (restart)
    PetscCall(PetscViewerASCIIPrintf(viewer, "Restart from %s at t = %.6g s, step %lld\n", sim->output.restart, (double)sim->time,
                                     (long long)sim->step));
  if (sim->fluid) {
    PetscCall(FluidView(sim->fluid, viewer));
    if (sim->coupling) {
      // coupled: the gas step is a whole number of DEM steps and must respect the gas limits
      const PetscInt substeps = CouplingSubsteps(sim->coupling), gas_substeps = CouplingGasSubsteps(sim->coupling);
      PetscReal      dt_gas, dt_max;
      PetscCall(CouplingGasStep(sim->coupling, &dt_gas, &dt_max));
      // Said on the initial state: the gas step may exceed its explicit limit for a while (a jet entering a packed bed)
      // without harm, so the run goes on and the Courant guard stops it when the excess persists.
      if (!restart && dt_gas > dt_max)
        PetscCall(
          PetscPrintf(sim->comm,
                      "WARNING: the gas step %.6g s (DEM step %.6g s x -couple_substeps %d / -couple_gas_substeps %d) exceeds the gas "
                      "limit %.6g s at the start (Courant number %.3g); the Courant guard stops the run if it stays above "
                      "-guard_courant. To fit: %s\n",
                      (double)dt_gas, (double)DemGetParams(sim->dem).dt, (int)substeps, (int)gas_substeps, (double)dt_max,
                      (double)(dt_gas / dt_max * FluidCfl(sim->fluid)), GuardsCourantRemedy(sim->guards, dt_max).c_str()));
      if (gas_substeps > 1)
        PetscCall(PetscViewerASCIIPrintf(viewer, "Gas step = DEM step / %d = %.4g s\n", (int)gas_substeps, (double)dt_gas));
      else PetscCall(PetscViewerASCIIPrintf(viewer, "Gas step = DEM step x %d = %.4g s\n", (int)substeps, (double)dt_gas));
    }
  }
  // Every module exists and has read its options: what the scene models, and where it asks for more or less than it can use.
  PetscCall(SceneModelBuild(sim, &sim->model));
  PetscCall(SceneModelView(sim->model, viewer));
  sim->wall_setup = MPI_Wtime() - t0;
  PetscFunctionReturn(0);
}

namespace {

// This process's processor time so far (user + system), s. Beside the wall time it tells whether a run had its core
// to itself: on a shared machine a run that waited for the processor shows less processor than wall time.
double ProcessCpuSeconds()
{
  struct rusage u;
  if (getrusage(RUSAGE_SELF, &u) != 0) return 0.0;
  return (double)u.ru_utime.tv_sec + 1e-6 * (double)u.ru_utime.tv_usec + (double)u.ru_stime.tv_sec + 1e-6 * (double)u.ru_stime.tv_usec;
}

// The signal that asked the run to end early (SIGTERM, SIGINT, SIGUSR1), 0 until one arrives. The handler only sets
// it; the time loop reads it and the ranks agree on the step to end at (InterruptAgreed).
volatile std::sig_atomic_t interrupt_signal = 0;

extern "C" void NoteInterrupt(int sig)
{
  interrupt_signal = sig;
}

// Installs NoteInterrupt for the run's steps, in place of PETSc's handlers (which end the process at once), and puts
// the previous handlers back when it goes out of scope.
class InterruptHandlers {
public:
  InterruptHandlers()
  {
    interrupt_signal = 0;
    for (int i = 0; i < 3; ++i) previous_[i] = std::signal(kSignals[i], NoteInterrupt);
  }
  ~InterruptHandlers()
  {
    for (int i = 0; i < 3; ++i) std::signal(kSignals[i], previous_[i]);
  }

private:
  static constexpr int kSignals[3] = {SIGTERM, SIGINT, SIGUSR1};
  void (*previous_[3])(int);
};

// Every 32 steps the ranks agree whether any has received an interrupt signal (the largest signal number, 0 for
// none), so that all end at the same step.
PetscErrorCode InterruptAgreed(MPI_Comm comm, PetscInt64 steps_done, int *sig)
{
  PetscFunctionBeginUser;
  if (steps_done % 32) PetscFunctionReturn(0);
  int mine = (int)interrupt_signal;
  PetscCallMPI(MPI_Allreduce(&mine, sig, 1, MPI_INT, MPI_MAX, comm));
  PetscFunctionReturn(0);
}

// Length of the next gas step when the gas runs alone: -fluid_dt or its limits. The last step is not shortened to
// end on t_final (the run ends with the first step that reaches it), so that a run restarted from a checkpoint takes
// the same steps as the uninterrupted one.
PetscErrorCode GasOnlyStep(Simulation *sim, PetscReal *dt)
{
  PetscFunctionBeginUser;
  *dt = FluidFixedTimeStep(sim->fluid);
  if (*dt == 0) PetscCall(FluidMaxTimeStep(sim->fluid, dt));
  PetscFunctionReturn(0);
}

PetscErrorCode WriteMonitorRow(Simulation *sim)
{
  std::vector<PetscReal> values;

  PetscFunctionBeginUser;
  PetscCall(OutputListValues(sim->outputs, SimulationView(sim), &values));
  PetscCall(MonitorWrite(sim->comm, &sim->monitor, sim->step, sim->time, values));
  PetscFunctionReturn(0);
}

// What is due at the current time: every output's Step in order, the checkpoint last (it checks the guards first, so
// that every checkpoint holds a state that passed them); `last` forces a final checkpoint.
PetscErrorCode OutputStep(Simulation *sim, PetscBool last)
{
  RunView run = SimulationView(sim);

  PetscFunctionBeginUser;
  run.last = last;
  PetscCall(OutputListStep(sim->outputs, run));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode SimulationRun(Simulation *sim)
{
  Dem            *dem    = sim->dem;
  const PetscInt  sub    = sim->coupling ? CouplingSubsteps(sim->coupling) : 1;    // DEM steps per gas step
  const PetscInt  nsub   = sim->coupling ? CouplingGasSubsteps(sim->coupling) : 1; // gas steps per DEM step
  const PetscReal dt_dem = dem ? DemGetParams(dem).dt : 0.0;
  // With particles, steps count from the start of the simulated time (t = step dt), so that a restarted run
  // reproduces the times of the uninterrupted one. -max_steps limits the steps of this run.
  const PetscInt64 step_final    = dem ? StepAtTime(sim, sim->run.t_final) : PETSC_MAX_INT;
  const PetscInt64 step0         = sim->step;
  const PetscInt64 step_stop     = sim->run.max_steps >= 0 ? PetscMin(step_final, step0 + sim->run.max_steps) : step_final;
  const PetscReal  time0         = sim->time;
  const PetscBool  restarted     = sim->output.restart[0] ? PETSC_TRUE : PETSC_FALSE;
  const double     t0            = MPI_Wtime();
  const double     cpu0          = ProcessCpuSeconds();
  double           last_progress = t0;

  InterruptHandlers handlers;
  int               interrupted = 0; // the signal the ranks agreed to end on (InterruptAgreed)
  auto              finished    = [&]() {
    if (interrupted) return true;
    if (dem) return sim->step >= step_stop;
    return sim->time >= sim->run.t_final * (1 - 1e-12) || (sim->run.max_steps >= 0 && sim->step - step0 >= sim->run.max_steps);
  };

  PetscFunctionBeginUser;
  if (dem)
    PetscCall(PetscPrintf(sim->comm, "Running %lld steps to t = %.6g s\n", (long long)PetscMax(0, step_stop - step0),
                          (double)(sim->time_origin + (PetscReal)(step_stop - sim->step_origin) * dt_dem)));
  else
    PetscCall(PetscPrintf(sim->comm, "Running the gas to t = %.6g s%s\n", (double)sim->run.t_final,
                          sim->run.max_steps >= 0 ? " (or -max_steps)" : ""));
  // the initial state, before anything is written from it
  PetscCall(GuardsCheckParticles(sim->guards, sim->step, sim->time, PETSC_TRUE));
  PetscCall(PhaseBegin(&sim->log, PHASE_OUTPUT));
  if (!restarted) { // a restart continues the files after the checkpoint's row
    PetscCall(WriteMonitorRow(sim));
    sim->monitor.next = sim->time + sim->monitor.interval;
    if (!GuardsStopped(sim->guards)) PetscCall(OutputStep(sim, PETSC_FALSE));
  }
  PetscCall(PhaseEnd(&sim->log, PHASE_OUTPUT));

  while (!finished() && !GuardsStopped(sim->guards)) {
    PetscReal dt = dt_dem;
    if (sim->fluid && (!sim->coupling || CouplingGasStepDue(sim->coupling))) {
      PetscReal dt_gas = sub * dt_dem / nsub;
      if (!dem) PetscCall(GasOnlyStep(sim, &dt_gas));
      // seed chapter 5: the gas advances first, with the void fraction and exchange terms of the particles' last step
      // (held over the -couple_gas_substeps gas steps of one DEM step)
      if (sim->coupling) PetscCall(CouplingBeforeFluidStep(sim->coupling));
      for (PetscInt k = 0; k < nsub && !GuardsStopped(sim->guards); ++k) {
        PetscCall(FluidStep(sim->fluid, dt_gas));
        if (sim->coupling) PetscCall(CouplingAfterFluidStep(sim->coupling, k, nsub));
        PetscCall(GuardsCheckGas(sim->guards, sim->step, sim->time + (k + 1) * dt_gas));
      }
      if (!dem) dt = dt_gas;
    }
    if (GuardsStopped(sim->guards)) break;
    if (dem) {
      PetscCall(DemStep(dem));
      sim->step++;
      sim->time = sim->time_origin + (PetscReal)(sim->step - sim->step_origin) * dt;
      PetscCall(InterruptAgreed(sim->comm, sim->step - step0, &interrupted));
      PetscCall(GuardsCheckParticles(sim->guards, sim->step, sim->time, finished() ? PETSC_TRUE : PETSC_FALSE));
      if (GuardsStopped(sim->guards)) break;
    } else {
      sim->step++;
      sim->time += dt;
      PetscCall(InterruptAgreed(sim->comm, sim->step - step0, &interrupted));
    }

    PetscCall(PhaseBegin(&sim->log, PHASE_OUTPUT));
    const PetscBool last = finished() ? PETSC_TRUE : PETSC_FALSE;
    if (sim->monitor.interval == 0 || sim->time >= sim->monitor.next - 0.5 * dt || last) {
      PetscCall(WriteMonitorRow(sim));
      while (sim->monitor.next <= sim->time + 0.5 * dt) sim->monitor.next += PetscMax(sim->monitor.interval, dt);
    }
    PetscCall(OutputStep(sim, last));
    PetscCall(PhaseEnd(&sim->log, PHASE_OUTPUT));

    // Progress: rank 0 decides every 64 steps, so that all ranks take the same branch.
    if (sim->run.progress_interval > 0 && (sim->step - step0) % 64 == 0) {
      double now = MPI_Wtime();
      PetscCallMPI(MPI_Bcast(&now, 1, MPI_DOUBLE, 0, sim->comm));
      if (now - last_progress >= sim->run.progress_interval) {
        const double elapsed = now - t0;
        const double done    = dem ? (double)(sim->step - step0) / (double)PetscMax(1, step_stop - step0)
                                   : (double)((sim->time - time0) / PetscMax(sim->run.t_final - time0, 1e-300));
        PetscCall(PetscPrintf(sim->comm, "  t = %.5g s (%4.1f%%), step %lld, %.3g steps/s, %s elapsed, about %s left\n", (double)sim->time,
                              100.0 * done, (long long)sim->step, (double)(sim->step - step0) / elapsed, Duration(elapsed).c_str(),
                              Duration(elapsed * (1.0 - done) / PetscMax(done, 1e-12)).c_str()));
        last_progress = now;
      }
    }
  }
  sim->wall_run  = MPI_Wtime() - t0;
  sim->cpu_run   = ProcessCpuSeconds() - cpu0;
  sim->steps_run = sim->step - step0;
  if (interrupted) GuardsNoteInterrupt(sim->guards, interrupted);
  sim->exit_status = GuardsExitStatus(sim->guards);

  PetscCall(UnusedOptionsCollect(sim, &sim->unused_options)); // every option has been read by now
  PetscMPIInt size;
  PetscCallMPI(MPI_Comm_size(sim->comm, &size));
  PetscCall(PhaseBegin(&sim->log, PHASE_OUTPUT));
  if (GuardsStopped(sim->guards)) {
    // The state that failed, for ParaView, and its monitor row; the run's final files are not written from it (the
    // last checkpoint, written before the failure, is the one to continue from).
    if (sim->monitor.last_row_step != sim->step) PetscCall(WriteMonitorRow(sim));
    PetscCall(OutputListStopped(sim->outputs, SimulationView(sim))); // the diagnostic
    PetscCall(PhaseEnd(&sim->log, PHASE_OUTPUT));
    PetscCall(OutputListEnd(sim->outputs, SimulationView(sim))); // summary.json
    PetscCall(
      PetscPrintf(sim->comm, "Stopped by guard '%s' at step %lld, t = %.6g s (exit status %d): %s/guard_failure.xmf marks where%s\n",
                  GuardNames[GuardsStopTrip(sim->guards)->kind], (long long)sim->step, (double)sim->time, sim->exit_status,
                  sim->run.output_dir, sim->output.checkpoint_interval > 0 ? "; continue from the last checkpoint with -restart" : ""));
    PetscCall(UnusedOptionsPrint(sim->comm, sim->unused_options));
    PetscFunctionReturn(0);
  }
  PetscCall(OutputListFinalize(sim->outputs, SimulationView(sim))); // particles.csv, fluid_cells.csv, the analyses' files
  PetscCall(MonitorClose(sim->comm, &sim->monitor));
  PetscCall(PhaseEnd(&sim->log, PHASE_OUTPUT));
  PetscCall(OutputListEnd(sim->outputs, SimulationView(sim))); // summary.json, after the final files and their phase
  if (dem)
    PetscCall(PetscPrintf(
      sim->comm,
      "Done: %lld steps, t = %.6g s, %lld particles (%lld left through the outlet), %.3f s wall, %.3g particle-steps/s per rank\n",
      (long long)sim->step, (double)sim->time, (long long)sim->totals.count, (long long)DemGetStats(dem)->outlet_removed, sim->wall_run,
      sim->wall_run > 0 ? (double)sim->totals.count * (double)sim->steps_run / sim->wall_run / size : 0.0));
  if (sim->fluid) {
    const FluidStats &fs = FluidGetStats(sim->fluid);
    PetscCall(PetscPrintf(
      sim->comm,
      "Gas: %lld steps, t = %.6g s, %.3f s wall; pressure: %.1f iterations and %.3g ms per solve; max |div(eps u)| %.3g 1/s; in %.6g, out "
      "%.6g m^3/s\n",
      (long long)fs.steps, (double)sim->time, sim->wall_run, fs.solves ? (double)fs.ksp_its_total / (double)fs.solves : 0.0,
      fs.solves ? 1e3 * fs.ksp_time_total / (double)fs.solves : 0.0, (double)fs.max_div, (double)fs.inflow, (double)fs.outflow));
  }
  if (!sim->guards->trips.empty()) {
    // each guard is reported once while the run goes on: name them again at the end, with what the gas could not do
    std::string list;
    for (const GuardTrip &t : sim->guards->trips) {
      char one[160];
      PetscCall(PetscSNPrintf(one, sizeof(one), "%s%s (first at step %lld, t = %.6g s)", list.empty() ? "" : ", ", GuardNames[t.kind],
                              (long long)t.step, (double)t.time));
      list += one;
    }
    if (sim->fluid && FluidGetStats(sim->fluid).ksp_failures > 0) {
      char more[96];
      PetscCall(
        PetscSNPrintf(more, sizeof(more), "; %lld pressure solves did not converge", (long long)FluidGetStats(sim->fluid).ksp_failures));
      list += more;
    }
    PetscCall(PetscPrintf(
      sim->comm, "WARNING: guards tripped and the run went on (-guard_action warn): %s (summary.json \"guard_trips\")\n", list.c_str()));
  }
  if (interrupted)
    PetscCall(PetscPrintf(sim->comm, "Interrupted by signal %d at step %lld, t = %.6g s, before -t_final %.6g s (exit status %d): %s\n",
                          interrupted, (long long)sim->step, (double)sim->time, (double)sim->run.t_final, sim->exit_status,
                          sim->output.checkpoint_interval > 0
                            ? "the state reached is the checkpoint; continue from it with -restart"
                            : "no checkpoint (-checkpoint_interval 0): the final files hold the state reached"));
  PetscCall(UnusedOptionsPrint(sim->comm, sim->unused_options));
  PetscFunctionReturn(0);
}

PetscErrorCode SimulationDestroy(Simulation **sim)
{
  PetscFunctionBeginUser;
  if (!*sim) PetscFunctionReturn(0);
  PetscCall(MonitorDestroy(&(*sim)->monitor));
  PetscCall(GuardsDestroy(&(*sim)->guards));
  PetscCall(OutputListDestroy(&(*sim)->outputs));
  PetscCall(CouplingDestroy(&(*sim)->coupling));
  PetscCall(FluidDestroy(&(*sim)->fluid));
  PetscCall(DMDestroy(&(*sim)->swarm));
  PetscCall(DemDestroy(&(*sim)->dem));
  PetscCall(GridsDestroy(&(*sim)->grids));
  delete *sim;
  *sim = nullptr;
  PetscFunctionReturn(0);
}

} // namespace fluidbed
