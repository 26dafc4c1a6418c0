#include "fluidbed/simulation.hpp"
#include "fluidbed/options.hpp"

#include <string>

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
  PetscCall(PetscOptionsString("-output_dir", "Directory for monitor.csv, track.csv, particles.csv and summary.json", "", r->output_dir,
                               r->output_dir, sizeof(r->output_dir), NULL));
  PetscCall(PetscOptionsBool("-output_particles", "Write particles.csv (sorted by id) at the end", "", r->write_particles,
                             &r->write_particles, NULL));
  PetscOptionsEnd();
  PetscFunctionReturn(0);
}

std::string Duration(double s)
{
  char buf[64];
  if (s < 120) snprintf(buf, sizeof(buf), "%.0f s", s);
  else if (s < 7200) snprintf(buf, sizeof(buf), "%.0f min %02.0f s", std::floor(s / 60), std::fmod(s, 60.0));
  else snprintf(buf, sizeof(buf), "%.0f h %02.0f min", std::floor(s / 3600), std::fmod(s / 60, 60.0));
  return buf;
}

PetscErrorCode WriteSummary(Simulation *sim, const ParticleTotals &tot)
{
  PetscMPIInt size;
  double      phase_max[PHASE_COUNT];
  JsonWriter  json, phases;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(sim->comm, &size));
  PetscCallMPI(MPI_Allreduce(sim->log.seconds, phase_max, PHASE_COUNT, MPI_DOUBLE, MPI_MAX, sim->comm));
  const double psteps = (double)tot.count * (double)sim->step;
  json.Integer("steps", (long long)sim->step);
  json.Number("time", sim->time);
  json.Number("dt", sim->dem->par.dt);
  json.Number("t_cr", sim->dem->par.t_cr);
  json.Number("t_cr_wall", sim->dem->par.t_cr_wall);
  json.Integer("particles", (long long)tot.count);
  json.Integer("particles_inserted", (long long)sim->inserted.count);
  json.Integer("particles_outlet", (long long)sim->dem->stats.outlet_removed);
  json.Integer("ranks", size);
  json.Integer("neighbour_rebuilds", (long long)sim->dem->stats.rebuilds);
  json.Number("kinetic_energy", tot.ke_trans + tot.ke_rot);
  json.Number("contacts_per_particle", tot.contacts_per_particle);
  json.Number("wall_time_setup", sim->wall_setup);
  json.Number("wall_time_run", sim->wall_run);
  for (int p = 0; p < PHASE_COUNT; ++p) phases.Number(PhaseKeys[p], phase_max[p]);
  json.Object("wall_time_phase_max_over_ranks", phases);
  json.Number("particle_steps_per_second", sim->wall_run > 0 ? psteps / sim->wall_run : 0.0);
  json.Number("particle_steps_per_second_per_rank", sim->wall_run > 0 ? psteps / sim->wall_run / size : 0.0);
  PetscCall(JsonWrite(sim->comm, (std::string(sim->run.output_dir) + "/summary.json").c_str(), json));
  PetscFunctionReturn(0);
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
  PetscCall(DomainSetFromOptions(sim->comm, &sim->domain));
  PetscCall(ParticlePropsSetFromOptions(sim->comm, sim->domain, &sim->props));
  PetscCall(GridsCreate(sim->comm, sim->domain, sim->props.d_max, &sim->grids));
  PetscCall(DemCreate(sim->comm, sim->domain, sim->grids.particle, sim->props, &sim->log, &sim->dem));
  PetscCall(DemCreateSwarm(sim->dem, &sim->swarm));
  PetscCall(MakeDirectory(sim->comm, sim->run.output_dir));
  PetscCall(MonitorCreate(sim->comm, sim->run.output_dir, sim->run.t_final, restart, &sim->monitor));
  if (restart) PetscCall(SimulationReadCheckpoint(sim));
  else PetscCall(ParticlesInsert(sim->comm, sim->domain, sim->grids.particle, sim->props, sim->swarm, &sim->inserted));

  PetscCall(DomainView(sim->domain, viewer));
  PetscCall(GridsView(sim->grids, sim->domain, viewer));
  PetscCall(PetscViewerASCIIPrintf(
    viewer, "Particles: %lld inserted, d = %.6g..%.6g mm, rho = %.6g kg/m^3, solid fraction of the insertion region %.3f\n",
    (long long)sim->inserted.count, 1e3 * sim->props.d_min, 1e3 * sim->props.d_max, (double)sim->props.density,
    (double)sim->inserted.solid_fraction_region));
  PetscCall(DemParamsView(sim->dem->par, viewer));
  if (restart)
    PetscCall(PetscViewerASCIIPrintf(viewer, "Restart from %s at t = %.6g s, step %lld\n", sim->output.restart, (double)sim->time,
                                     (long long)sim->step));

  PetscCall(DemSetUp(sim->dem, sim->swarm, restart));
  sim->wall_setup = MPI_Wtime() - t0;
  PetscFunctionReturn(0);
}

PetscErrorCode SimulationRun(Simulation *sim)
{
  Dem            *dem = sim->dem;
  const PetscReal dt  = dem->par.dt;
  // Steps count from the start of the simulated time (t = step dt), so that a restarted run reproduces the times
  // of the uninterrupted one; -max_steps limits the steps of this run.
  const PetscInt64 step_final = (PetscInt64)PetscCeilReal(sim->run.t_final / dt - 1e-9);
  const PetscInt64 nsteps =
    PetscMax(0, sim->run.max_steps >= 0 ? PetscMin(step_final - sim->step, (PetscInt64)sim->run.max_steps) : step_final - sim->step);
  const PetscBool restarted = sim->output.restart[0] ? PETSC_TRUE : PETSC_FALSE;
  ParticleTotals  tot;
  const double    t0            = MPI_Wtime();
  double          last_progress = t0;

  PetscFunctionBeginUser;
  PetscCall(PetscPrintf(sim->comm, "Running %lld steps to t = %.6g s\n", (long long)nsteps, (double)((sim->step + nsteps) * dt)));
  PetscCall(PhaseBegin(&sim->log, PHASE_OUTPUT));
  PetscCall(ComputeParticleTotals(dem, &tot));
  if (!restarted) { // a restart continues the files at the checkpoint's row
    PetscCall(MonitorWrite(sim->comm, &sim->monitor, dem, sim->step, sim->time, tot));
    PetscCall(MonitorTrack(sim->comm, &sim->monitor, dem, sim->step, sim->time));
    sim->monitor.next = sim->time + sim->monitor.interval;
    PetscCall(SimulationOutputStep(sim, PETSC_FALSE));
  }
  PetscCall(PhaseEnd(&sim->log, PHASE_OUTPUT));

  const PetscInt64 step0 = sim->step;
  while (sim->step - step0 < nsteps) {
    PetscCall(DemStep(dem));
    sim->step++;
    sim->time = (PetscReal)sim->step * dt;

    PetscCall(PhaseBegin(&sim->log, PHASE_OUTPUT));
    PetscCall(MonitorTrack(sim->comm, &sim->monitor, dem, sim->step, sim->time));
    PetscCall(SimulationOutputStep(sim, sim->step - step0 == nsteps ? PETSC_TRUE : PETSC_FALSE));
    if (sim->time >= sim->monitor.next - 0.5 * dt || sim->step - step0 == nsteps) {
      PetscCall(ComputeParticleTotals(dem, &tot));
      PetscCall(MonitorWrite(sim->comm, &sim->monitor, dem, sim->step, sim->time, tot));
      while (sim->monitor.next <= sim->time + 0.5 * dt) sim->monitor.next += PetscMax(sim->monitor.interval, dt);
    }
    PetscCall(PhaseEnd(&sim->log, PHASE_OUTPUT));

    // Progress: rank 0 decides every 64 steps, so that all ranks take the same branch.
    if (sim->run.progress_interval > 0 && (sim->step - step0) % 64 == 0) {
      double now = MPI_Wtime();
      PetscCallMPI(MPI_Bcast(&now, 1, MPI_DOUBLE, 0, sim->comm));
      if (now - last_progress >= sim->run.progress_interval) {
        const double elapsed = now - t0, done = (double)(sim->step - step0) / (double)nsteps;
        PetscCall(PetscPrintf(sim->comm, "  t = %.5g s (%4.1f%%), step %lld, %.3g steps/s, %s elapsed, about %s left\n", (double)sim->time,
                              100.0 * done, (long long)sim->step, (double)(sim->step - step0) / elapsed, Duration(elapsed).c_str(),
                              Duration(elapsed * (1.0 - done) / PetscMax(done, 1e-12)).c_str()));
        last_progress = now;
      }
    }
  }
  sim->wall_run = MPI_Wtime() - t0;

  PetscCall(PhaseBegin(&sim->log, PHASE_OUTPUT));
  if (sim->run.write_particles) PetscCall(WriteParticlesCSV(sim->swarm, (std::string(sim->run.output_dir) + "/particles.csv").c_str()));
  PetscCall(PhaseEnd(&sim->log, PHASE_OUTPUT));
  PetscCall(WriteSummary(sim, tot));
  PetscMPIInt size;
  PetscCallMPI(MPI_Comm_size(sim->comm, &size));
  PetscCall(PetscPrintf(
    sim->comm, "Done: %lld steps, t = %.6g s, %lld particles (%lld left through the outlet), %.3f s wall, %.3g particle-steps/s per rank\n",
    (long long)sim->step, (double)sim->time, (long long)tot.count, (long long)dem->stats.outlet_removed, sim->wall_run,
    sim->wall_run > 0 ? (double)tot.count * (double)(sim->step - step0) / sim->wall_run / size : 0.0));
  PetscFunctionReturn(0);
}

PetscErrorCode SimulationDestroy(Simulation **sim)
{
  PetscFunctionBeginUser;
  if (!*sim) PetscFunctionReturn(0);
  PetscCall(MonitorDestroy(&(*sim)->monitor));
  PetscCall(DMDestroy(&(*sim)->swarm));
  PetscCall(DemDestroy(&(*sim)->dem));
  PetscCall(GridsDestroy(&(*sim)->grids));
  delete *sim;
  *sim = nullptr;
  PetscFunctionReturn(0);
}

} // namespace fluidbed
