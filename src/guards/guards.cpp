// Run-time guards: see include/fluidbed/guards.hpp. Gathers the figures the step already computed, reduces them
// once per check, applies the rules of kernels/guard_rules.hpp, and on a trip finds where it happened and says
// what to change.
#include "fluidbed/guards.hpp"
#include "fluidbed/io.hpp"
#include "fluidbed/options.hpp"
#include "fluidbed/status.hpp"

#include <petscksp.h>

#include <cmath>
#include <cstdarg>
#include <string>

namespace fluidbed {

const char *const GuardNames[GUARD_COUNT] = {"nan", "escape", "pressure", "overlap", "displacement", "energy", "void_fraction", "courant"};
static const char *const GuardActionTypes[] = {"stop", "warn", "GuardAction", "GUARD_ACTION_", NULL};

namespace {

std::string Format(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
std::string Format(const char *fmt, ...)
{
  char    buf[1024];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, sizeof(buf), fmt, ap);
  va_end(ap);
  return buf;
}

std::string PositionMm(const PetscReal x[3], PetscInt dim)
{
  return dim == 3 ? Format("(%.4g, %.4g, %.4g) mm", 1e3 * x[0], 1e3 * x[1], 1e3 * x[2]) : Format("(%.4g, %.4g) mm", 1e3 * x[0], 1e3 * x[1]);
}

std::string Partner(PetscInt64 partner)
{
  if (partner >= 0) return Format("particle %lld", (long long)partner);
  if (partner <= -2) return Format("the %s wall", FaceNames[-2 - partner]);
  return "nothing";
}

std::string CellText(PetscInt64 natural, const PetscInt n[3], PetscInt dim)
{
  const PetscInt i = (PetscInt)(natural % n[0]), j = (PetscInt)((natural / n[0]) % n[1]),
                 k = (PetscInt)(natural / ((PetscInt64)n[0] * n[1]));
  return dim == 3 ? Format("(%d, %d, %d)", (int)i, (int)j, (int)k) : Format("(%d, %d)", (int)i, (int)j);
}

// The fluid grid's size (FluidGrid of the fluid module is not at hand here: read it off the pressure DM).
PetscErrorCode FluidGridSize(Fluid *fluid, PetscInt n[3])
{
  DM scalar;
  PetscFunctionBeginUser;
  PetscCall(FluidGetCellDMs(fluid, &scalar, NULL));
  n[0] = n[1] = n[2] = 1;
  PetscCall(DMDAGetInfo(scalar, NULL, &n[0], &n[1], &n[2], NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL));
  PetscFunctionReturn(0);
}

// Prints a trip and records it. Under -guard_action stop (and always for a NaN, after which nothing is
// meaningful) the first trip stops the run; under warn each guard is reported once and counted after that.
PetscErrorCode Report(Guards *g, GuardTrip &&trip)
{
  const unsigned bit   = 1u << trip.kind;
  const bool     stops = g->opt.action == GUARD_ACTION_STOP || trip.kind == GUARD_NAN;

  PetscFunctionBeginUser;
  if (stops) {
    if (!g->stop) {
      PetscCall(PetscFPrintf(g->comm, PETSC_STDERR,
                             "fluidbed: guard '%s' stopped the run at step %lld, t = %.6g s: %s%s%s\n  likely remedy: %s\n",
                             GuardNames[trip.kind], (long long)trip.step, (double)trip.time, trip.what.c_str(),
                             trip.where.empty() ? "" : ", ", trip.where.c_str(), trip.remedy.c_str()));
      g->stop = PETSC_TRUE;
    } else {
      PetscCall(PetscFPrintf(g->comm, PETSC_STDERR, "  also tripped at that check: guard '%s': %s%s%s\n", GuardNames[trip.kind],
                             trip.what.c_str(), trip.where.empty() ? "" : ", ", trip.where.c_str()));
    }
    g->trips.push_back(std::move(trip));
  } else if (!(g->warned & bit)) {
    PetscCall(
      PetscPrintf(g->comm,
                  "WARNING: guard '%s' tripped at step %lld, t = %.6g s: %s%s%s\n  likely remedy: %s\n  (-guard_action warn: the run "
                  "continues; this guard is not reported again)\n",
                  GuardNames[trip.kind], (long long)trip.step, (double)trip.time, trip.what.c_str(), trip.where.empty() ? "" : ", ",
                  trip.where.c_str(), trip.remedy.c_str()));
    g->warned |= bit;
    g->trips.push_back(std::move(trip));
  }
  PetscFunctionReturn(0);
}

GuardTrip NewTrip(GuardKind kind, PetscInt64 step, PetscReal time, PetscReal value, PetscReal limit)
{
  GuardTrip t;
  t.kind  = kind;
  t.step  = step;
  t.time  = time;
  t.value = value;
  t.limit = limit;
  return t;
}

std::string DtRemedy(const Dem *dem)
{
  return Format("a shorter DEM step, -dem_dt_factor below %.3g (dt = %.4g s = %.3g t_cr)", (double)DemGetParams(dem).dt_factor,
                (double)DemGetParams(dem).dt, (double)(DemGetParams(dem).dt / DemGetParams(dem).t_cr));
}

PetscErrorCode TripNonFinite(Guards *g, PetscInt64 step, PetscReal time, const ParticleSite &site, const std::vector<PetscInt64> &ids)
{
  ParticleSite overlap;
  GuardTrip    t = NewTrip(GUARD_NAN, step, time, (PetscReal)site.count, 0);

  PetscFunctionBeginUser;
  PetscCall(DemLocateMaxOverlap(g->dem, &overlap));
  t.what  = Format("%lld particle(s) hold NaN or inf in their position, velocity, spin, force or torque", (long long)site.count);
  t.where = Format("the first particle %lld at %s on rank %d", (long long)site.id, PositionMm(site.x, g->dom->dim).c_str(), (int)site.rank);
  if (overlap.value >= 0.99)
    t.remedy = Format("particle %lld and %s are at the same point (overlap %.3g d): fix the insertion (-insert_positions, -insert_file)",
                      (long long)overlap.id, Partner(overlap.partner).c_str(), (double)overlap.value);
  else t.remedy = DtRemedy(g->dem) + "; see the overlap, displacement and energy figures in summary.json";
  // every rank's non-finite ids, so that the snapshot marks them all
  {
    PetscMPIInt size, n = (PetscMPIInt)ids.size();
    PetscCallMPI(MPI_Comm_size(g->comm, &size));
    std::vector<PetscMPIInt> counts((std::size_t)size), displs((std::size_t)size, 0);
    PetscCallMPI(MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, g->comm));
    for (PetscMPIInt r = 1; r < size; ++r) displs[(std::size_t)r] = displs[(std::size_t)r - 1] + counts[(std::size_t)r - 1];
    t.particles.resize((std::size_t)(displs.back() + counts.back()));
    PetscCallMPI(MPI_Allgatherv(ids.data(), n, MPIU_INT64, t.particles.data(), counts.data(), displs.data(), MPIU_INT64, g->comm));
  }
  PetscCall(Report(g, std::move(t)));
  PetscFunctionReturn(0);
}

PetscErrorCode TripEscape(Guards *g, PetscInt64 step, PetscReal time)
{
  const ParticleLoss &lost = DemGetStats(g->dem)->lost;
  GuardTrip           t    = NewTrip(GUARD_ESCAPE, step, time, (PetscReal)lost.count, 0);

  PetscFunctionBeginUser;
  if (lost.first_id >= 0) {
    t.what   = Format("%lld particle(s) left the domain through a wall and were removed", (long long)lost.count);
    t.where  = Format("the first particle %lld at %s", (long long)lost.first_id, PositionMm(lost.first_x, g->dom->dim).c_str());
    t.remedy = Format("the contact with the wall was not resolved: %s, or stiffer walls, -wall_kn above %.4g N/m", DtRemedy(g->dem).c_str(),
                      (double)DemGetParams(g->dem).pw.kn);
    t.particles.push_back(lost.first_id);
  } else {
    t.what   = Format("%lld particle(s) were lost in migration (a particle moved further than a neighbouring rank between rebuilds)",
                      (long long)lost.count);
    t.remedy = DtRemedy(g->dem) + ", or fewer ranks along the direction of the fastest particles (-pgrid_processors)";
  }
  PetscCall(Report(g, std::move(t)));
  PetscFunctionReturn(0);
}

PetscErrorCode TripOverlap(Guards *g, PetscInt64 step, PetscReal time, PetscReal value)
{
  ParticleSite s;
  GuardTrip    t = NewTrip(GUARD_OVERLAP, step, time, value, g->opt.overlap);

  PetscFunctionBeginUser;
  PetscCall(DemLocateMaxOverlap(g->dem, &s));
  t.what =
    Format("the largest overlap reached %.3g of the particle diameter (limit -guard_overlap %.3g)", (double)value, (double)g->opt.overlap);
  t.where = Format("now %.3g d between particle %lld and %s at %s on rank %d", (double)s.value, (long long)s.id, Partner(s.partner).c_str(),
                   PositionMm(s.x, g->dom->dim).c_str(), (int)s.rank);
  t.remedy = Format("stiffer contacts, -dem_kn above %.4g N/m (the overlap of an impact at speed v is about v sqrt(m_eff / k_n)), or if "
                    "it grew within a few steps %s",
                    (double)DemGetParams(g->dem).pp.kn, DtRemedy(g->dem).c_str());
  if (s.id >= 0) t.particles.push_back(s.id);
  if (s.partner >= 0) t.particles.push_back(s.partner);
  PetscCall(Report(g, std::move(t)));
  PetscFunctionReturn(0);
}

PetscErrorCode TripDisplacement(Guards *g, PetscInt64 step, PetscReal time, PetscReal value)
{
  ParticleSite s;
  GuardTrip    t = NewTrip(GUARD_DISPLACEMENT, step, time, value, g->opt.displacement);

  PetscFunctionBeginUser;
  PetscCall(ParticlesLocateFastest(DemGetParticles(g->dem), &s));
  t.what   = Format("a particle moved %.3g of its diameter in one step (limit -guard_displacement %.3g)", (double)value,
                    (double)g->opt.displacement);
  t.where  = Format("now particle %lld moves %.3g d per step at %s on rank %d", (long long)s.id, (double)s.value,
                    PositionMm(s.x, g->dom->dim).c_str(), (int)s.rank);
  t.remedy = DtRemedy(g->dem) + (g->fluid ? "; if the gas launched it, see the gas Courant number (monitor.csv gas_courant)" : "");
  if (s.id >= 0) t.particles.push_back(s.id);
  PetscCall(Report(g, std::move(t)));
  PetscFunctionReturn(0);
}

PetscErrorCode TripEnergy(Guards *g, PetscInt64 step, PetscReal time, PetscReal growth, PetscReal e)
{
  ParticleSite s;
  GuardTrip    t = NewTrip(GUARD_ENERGY, step, time, growth, g->opt.energy_growth);

  PetscFunctionBeginUser;
  PetscCall(ParticlesLocateFastest(DemGetParticles(g->dem), &s));
  t.what   = Format("the mechanical energy of a scene without energy input grew by %.3g of its least value (%.6g J -> %.6g J; limit "
                      "-guard_energy_growth %.3g)",
                    (double)growth, (double)g->energy.least, (double)e, (double)g->opt.energy_growth);
  t.where  = Format("the fastest particle %lld moves %.3g d per step at %s on rank %d", (long long)s.id, (double)s.value,
                    PositionMm(s.x, g->dom->dim).c_str(), (int)s.rank);
  t.remedy = "the step does not resolve the contacts: " + DtRemedy(g->dem);
  if (s.id >= 0) t.particles.push_back(s.id);
  PetscCall(Report(g, std::move(t)));
  PetscFunctionReturn(0);
}

PetscErrorCode TripPressure(Guards *g, PetscInt64 step, PetscReal time)
{
  const FluidStats &fs = FluidGetStats(g->fluid);
  const char       *kt, *pt;
  PetscInt          max_it;
  GuardTrip         t = NewTrip(GUARD_PRESSURE, step, time, (PetscReal)fs.ksp_its, 0);

  PetscFunctionBeginUser;
  PetscCall(FluidPressureSolverInfo(g->fluid, &kt, &pt, &max_it));
  t.what  = Format("the pressure solve of gas step %lld did not converge: %s after %d iterations, residual norm %.3g", (long long)fs.steps,
                   KSPConvergedReasons[fs.ksp_reason], (int)fs.ksp_its, (double)fs.ksp_rnorm);
  t.where = Format("-fluid_p_ksp_type %s -fluid_p_pc_type %s -fluid_p_ksp_max_it %d", kt, pt, (int)max_it);
  t.remedy =
    "another solver or preconditioner (-fluid_p_ksp_type, -fluid_p_pc_type: docs/fluid.md), a larger -fluid_p_ksp_max_it or a looser "
    "-fluid_p_ksp_rtol; when the gas Courant number is high (monitor.csv gas_courant) the gas step diverged first";
  PetscCall(Report(g, std::move(t)));
  PetscFunctionReturn(0);
}

// What brings the gas step within its explicit limit dt_max: fewer substeps when there are some to drop, else a shorter
// DEM step, a coarser grid or a slower jet (never -couple_substeps at one substep).
std::string CourantRemedy(const Guards *g, PetscReal dt_max)
{
  if (!g->dem) {
    const FluidStats &fs = FluidGetStats(g->fluid);
    return Format("a shorter gas step: -fluid_dt at most %.4g s (now %.4g s), or leave -fluid_dt unset", (double)dt_max, (double)fs.dt);
  }
  const PetscReal dt       = DemGetParams(g->dem).dt;
  const PetscInt  k        = (PetscInt)(dt_max / dt);
  const PetscInt  substeps = g->coupling ? CouplingSubsteps(g->coupling) : 1;
  const PetscInt  gas_sub  = g->coupling ? CouplingGasSubsteps(g->coupling) : 1;
  if (substeps > 1 && k >= 1) return Format("fewer DEM steps per gas step: -couple_substeps at most %d (now %d)", (int)k, (int)substeps);
  // the gas steps of one DEM step that bring the gas step within the limit
  const PetscInt need = (PetscInt)PetscCeilReal(dt / dt_max * (1.0 - 1e-12));
  return Format("the DEM step %.4g s alone exceeds the gas limit %.4g s, so -couple_substeps (now %d) cannot help: more gas steps per DEM "
                "step, -couple_gas_substeps at least %d (now %d), -dem_dt_factor at most %.3g (now %.3g), a coarser gas grid "
                "(-grid_nx/-grid_ny/-grid_nz) or a slower jet; if the void fraction is held at the floor (-couple_eps_min) the gas "
                "speeds up through those cells: fix the grid first",
                (double)dt, (double)dt_max, (int)substeps, (int)PetscMax(need, gas_sub + 1), (int)gas_sub,
                (double)(DemGetParams(g->dem).dt_factor * dt_max / dt), (double)DemGetParams(g->dem).dt_factor);
}

} // namespace

std::string GuardsCourantRemedy(const Guards *g, PetscReal dt_max)
{
  return CourantRemedy(g, dt_max);
}

namespace {

PetscErrorCode TripCourant(Guards *g, PetscInt64 step, PetscReal time)
{
  const FluidStats &fs = FluidGetStats(g->fluid);
  PetscInt64        cell;
  PetscReal         speed, dt_max;
  PetscInt          n[3];
  GuardTrip         t = NewTrip(GUARD_COURANT, step, time, fs.courant, g->opt.courant);

  PetscFunctionBeginUser;
  PetscCall(FluidLocateMaxSpeed(g->fluid, &cell, &speed));
  PetscCall(FluidGridSize(g->fluid, n));
  PetscCall(FluidMaxTimeStep(g->fluid, &dt_max));
  t.what =
    Format("the gas Courant number stayed above -guard_courant %.3g for %ld gas steps (now %.3g: gas step %.4g s against its explicit "
           "limit %.4g s)",
           (double)g->opt.courant, g->courant_run.run, (double)fs.courant, (double)fs.dt, (double)(fs.dt / PetscMax(fs.courant, 1e-300)));
  t.where  = Format("the largest gas speed %.4g m/s on a face of cell %s", (double)speed, CellText(cell, n, g->dom->dim).c_str());
  t.remedy = CourantRemedy(g, dt_max);
  t.fluid_cells.push_back(cell); // marked by the rank that owns it (DiagnosticSnapshot keeps owned cells only)
  PetscCall(Report(g, std::move(t)));
  PetscFunctionReturn(0);
}

PetscErrorCode TripVoidFraction(Guards *g, PetscInt64 step, PetscReal time, const kernels::VoidFractionVerdict &v)
{
  const CouplingStats &cs = CouplingGetStats(g->coupling);
  PetscInt             first[3];
  PetscReal            h[3];
  PetscInt             ratio[3];
  GuardTrip            t = NewTrip(GUARD_VOID_FRACTION, step, time, v.outside ? cs.eps_raw_min : v.share_at_floor, g->opt.floor_share);

  PetscFunctionBeginUser;
  PetscCall(CouplingFloorCells(g->coupling, &t.fluid_cells, first));
  PetscCall(CouplingCellSize(g->coupling, h, ratio));
  if (v.outside)
    t.what = Format("the void fraction left (0, 1]: least %.4g before the floor, largest %.4g (%lld of %lld cells held at the floor)",
                    (double)cs.eps_raw_min, (double)cs.eps_max, (long long)cs.clamped, (long long)cs.cells);
  else
    t.what = Format("the void fraction is held at the floor in %lld of %lld cells (%.3g%%, limit -guard_floor_share %.3g)",
                    (long long)cs.clamped, (long long)cs.cells, 100.0 * v.share_at_floor, (double)g->opt.floor_share);
  if (first[0] >= 0)
    t.where = g->dom->dim == 3 ? Format("first at coupling cell (%d, %d, %d)", (int)first[0], (int)first[1], (int)first[2])
                               : Format("first at coupling cell (%d, %d)", (int)first[0], (int)first[1]);
  const PetscReal d = DemGetProps(g->dem).d_max;
  t.remedy =
    Format("the coupling cells are %.3g x %.3g%s particle diameters and hold too few particles for a smooth void fraction: "
           "cells of about 3 d or more, on two grids (-couple_grid two with -pgrid_ratio or -pgrid_cell_diameters) or a coarser gas grid",
           (double)(h[0] / d), (double)(h[1] / d), g->dom->dim == 3 ? Format(" x %.3g", (double)(h[2] / d)).c_str() : "");
  PetscCall(Report(g, std::move(t)));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode GuardsCreate(MPI_Comm comm, const Domain &domain, Dem *dem, Fluid *fluid, Coupling *coupling, PhaseLog *log, Guards **out)
{
  Guards   *g      = new Guards;
  PetscEnum action = (PetscEnum)g->opt.action;

  PetscFunctionBeginUser;
  g->comm     = comm;
  g->dom      = &domain;
  g->dem      = dem;
  g->fluid    = fluid;
  g->coupling = coupling;
  g->log      = log;
  // Pure DEM, walls at rest, nothing flows in: the energy cannot grow. Not with gravity along a periodic direction,
  // where particles fall without end (the gravitational energy jumps at each wrap).
  g->closed = (PetscBool)(dem && !fluid);
  for (int a = 0; a < domain.dim; ++a)
    if (domain.periodic[a] && domain.gravity[a] != 0) g->closed = PETSC_FALSE;
  GuardOptions &o = g->opt;
  PetscOptionsBegin(comm, "guard_", "Run-time guards: stop a run whose state went wrong (docs/reliability.md)", "Guards");
  PetscCall(PetscOptionsBool("-enable", "Check the guards below during the run", "", o.enable, &o.enable, NULL));
  PetscCall(OptionsEnum(PetscOptionsObject, "-action", "What a tripped guard does: stop (exit status per guard) or warn once and go on",
                        GuardActionTypes, &action, NULL));
  PetscCall(OptionsInt(PetscOptionsObject, "-interval", "DEM steps between checks of the particle guards (gas guards: every gas step)", 1,
                       PETSC_MAX_INT, &o.interval, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-overlap",
                        "Largest overlap allowed, as a fraction of the smaller diameter of the pair (0: off)", "", Closed(0.0, 1.0),
                        &o.overlap, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-displacement", "Largest distance a particle may move in one step, in diameters (0: off)", "",
                        NonNegative(100.0), &o.displacement, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-energy_growth",
                        "Largest growth of the mechanical energy over its least value in a scene without energy input (pure DEM; 0: off)",
                        "", NonNegative(1e6), &o.energy_growth, NULL));
  PetscCall(
    OptionsInt(PetscOptionsObject, "-energy_interval", "DEM steps between energy checks", 1, PETSC_MAX_INT, &o.energy_interval, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-floor_share",
                        "Largest share of coupling cells held at the void-fraction floor -couple_eps_min (0: off)", "", Closed(0.0, 1.0),
                        &o.floor_share, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-courant", "Gas Courant number (gas step / explicit limit) that may not persist (0: off)", "",
                        NonNegative(1e6), &o.courant, NULL));
  PetscCall(OptionsInt(PetscOptionsObject, "-courant_steps", "Consecutive gas steps above -guard_courant that stop the run", 1,
                       PETSC_MAX_INT, &o.courant_steps, NULL));
  PetscOptionsEnd();
  o.action = (GuardAction)action;
  *out     = g;
  PetscFunctionReturn(0);
}

PetscErrorCode GuardsView(const Guards *g, PetscViewer viewer)
{
  const GuardOptions &o = g->opt;

  PetscFunctionBeginUser;
  if (!o.enable) {
    PetscCall(PetscViewerASCIIPrintf(viewer, "Guards: off (-guard_enable 0)\n"));
    PetscFunctionReturn(0);
  }
  std::string s = Format("Guards (%s, every %d steps): NaN", o.action == GUARD_ACTION_STOP ? "stop" : "warn", (int)o.interval);
  if (g->dem) {
    s += ", escape";
    if (o.overlap > 0) s += Format(", overlap < %.3g d", (double)o.overlap);
    if (o.displacement > 0) s += Format(", step < %.3g d", (double)o.displacement);
    if (g->closed && o.energy_growth > 0)
      s += Format(", energy growth < %.3g (every %d steps)", (double)o.energy_growth, (int)o.energy_interval);
  }
  if (g->fluid) {
    s += ", pressure solve";
    if (o.courant > 0) s += Format(", gas Courant < %.3g (%d gas steps)", (double)o.courant, (int)o.courant_steps);
  }
  if (g->coupling && o.floor_share > 0) s += Format(", void fraction in (0, 1] with < %.3g of cells at the floor", (double)o.floor_share);
  PetscCall(PetscViewerASCIIPrintf(viewer, "%s\n", s.c_str()));
  PetscFunctionReturn(0);
}

PetscErrorCode GuardsCheckParticles(Guards *g, PetscInt64 step, PetscReal time, PetscBool force)
{
  Dem *dem = g->dem;

  PetscFunctionBeginUser;
  if (!g->opt.enable || !dem || g->stop) PetscFunctionReturn(0);
  if (!force && !DemGetStats(dem)->halted && step % g->opt.interval) PetscFunctionReturn(0);
  PetscCall(PhaseBegin(g->log, PHASE_GUARDS));
  PetscReal loc[3] = {DemGetStats(dem)->guard_overlap_rel, DemGetStats(dem)->guard_step_rel,
                      (DemGetStats(dem)->nonfinite || DemGetStats(dem)->halted) ? 1.0 : 0.0},
            glob[3];
  PetscCallMPI(MPI_Allreduce(loc, glob, 3, MPIU_REAL, MPI_MAX, g->comm));
  DemGetStats(dem)->guard_overlap_rel = 0;
  DemGetStats(dem)->guard_step_rel    = 0;
  g->fig.overlap                      = PetscMax(g->fig.overlap, glob[0]);
  g->fig.displacement                 = PetscMax(g->fig.displacement, glob[1]);
  g->fig.checks++;

  // a NaN shows in the velocities the step integrated; the initial state (step 0) is scanned whole, forces included
  bool nan = false;
  if (glob[2] > 0 || step == 0) {
    ParticleSite            site;
    std::vector<PetscInt64> ids;
    PetscCall(ParticlesLocateNonFinite(DemGetParticles(dem), &site, &ids));
    nan = site.count > 0;
    if (nan) PetscCall(TripNonFinite(g, step, time, site, ids));
  }
  if (DemGetStats(dem)->lost.count > g->lost_seen) {
    PetscCall(TripEscape(g, step, time));
    g->lost_seen = DemGetStats(dem)->lost.count;
  }
  if (!DemGetStats(dem)->halted) {
    if (g->opt.overlap > 0 && glob[0] > g->opt.overlap) PetscCall(TripOverlap(g, step, time, glob[0]));
    if (g->opt.displacement > 0 && glob[1] > g->opt.displacement) PetscCall(TripDisplacement(g, step, time, glob[1]));
    if (!nan && g->closed && g->opt.energy_growth > 0 && (force || step % g->opt.energy_interval == 0)) {
      PetscReal e;
      PetscCall(DemMechanicalEnergy(dem, &e));
      const PetscReal growth = g->energy.add(e);
      g->fig.energy_checks++;
      g->fig.energy_growth = PetscMax(g->fig.energy_growth, growth);
      if (!(growth <= g->opt.energy_growth)) PetscCall(TripEnergy(g, step, time, growth, e));
    }
  }
  PetscCall(PhaseEnd(g->log, PHASE_GUARDS));
  PetscFunctionReturn(0);
}

PetscErrorCode GuardsCheckGas(Guards *g, PetscInt64 step, PetscReal time)
{
  PetscFunctionBeginUser;
  if (!g->opt.enable || !g->fluid || g->stop) PetscFunctionReturn(0);
  PetscCall(PhaseBegin(g->log, PHASE_GUARDS));
  const FluidStats &fs = FluidGetStats(g->fluid);
  g->fig.gas_checks++;
  if (fs.ksp_failures > g->ksp_failures_seen) {
    PetscCall(TripPressure(g, step, time));
    g->ksp_failures_seen = fs.ksp_failures;
  }
  if (g->opt.courant > 0) {
    const bool over    = g->courant_run.add(fs.courant, g->opt.courant, g->opt.courant_steps);
    g->fig.courant     = PetscMax(g->fig.courant, fs.courant);
    g->fig.courant_run = g->courant_run.longest;
    if (!(fs.courant <= g->opt.courant) && !g->courant_warned) {
      // the first excursion: said once, since a jet entering a packed bed causes a few without harm
      PetscInt64 cell;
      PetscReal  speed;
      PetscInt   n[3];
      PetscCall(FluidLocateMaxSpeed(g->fluid, &cell, &speed));
      PetscCall(FluidGridSize(g->fluid, n));
      PetscCall(PetscPrintf(
        g->comm,
        "WARNING: gas Courant number %.3g above -guard_courant %.3g at step %lld, t = %.6g s (largest gas speed %.4g m/s at cell "
        "%s); the guard stops the run if it stays above for %d gas steps\n",
        (double)fs.courant, (double)g->opt.courant, (long long)step, (double)time, (double)speed, CellText(cell, n, g->dom->dim).c_str(),
        (int)g->opt.courant_steps));
      g->courant_warned = PETSC_TRUE;
    }
    if (over) PetscCall(TripCourant(g, step, time));
  }
  if (g->coupling) {
    const CouplingStats               &cs = CouplingGetStats(g->coupling);
    const kernels::VoidFractionVerdict v  = kernels::void_fraction_verdict(cs.eps_raw_min, cs.eps_max, cs.clamped, cs.cells);
    g->fig.floor_share                    = PetscMax(g->fig.floor_share, v.share_at_floor);
    g->fig.eps_raw_min                    = PetscMin(g->fig.eps_raw_min, cs.eps_raw_min);
    if (v.outside || (g->opt.floor_share > 0 && v.share_at_floor > g->opt.floor_share)) PetscCall(TripVoidFraction(g, step, time, v));
  }
  if (fs.steps % g->opt.interval == 0) {
    PetscBool   finite;
    PetscInt64  cell;
    const char *field;
    PetscCall(FluidCheckFinite(g->fluid, &finite, &cell, &field));
    if (!finite) {
      PetscInt  n[3];
      GuardTrip t = NewTrip(GUARD_NAN, step, time, 0, 0);
      PetscCall(FluidGridSize(g->fluid, n));
      t.what   = Format("the gas %s holds NaN or inf", field);
      t.where  = Format("first at cell %s", CellText(cell, n, g->dom->dim).c_str());
      t.remedy = "the gas step diverged: see the gas Courant number (monitor.csv gas_courant, -guard_courant) and the pressure solve";
      t.fluid_cells.push_back(cell);
      PetscCall(Report(g, std::move(t)));
    }
  }
  PetscCall(PhaseEnd(g->log, PHASE_GUARDS));
  PetscFunctionReturn(0);
}

PetscBool GuardsStopped(const Guards *g)
{
  return g && g->stop ? PETSC_TRUE : PETSC_FALSE;
}

const GuardTrip *GuardsStopTrip(const Guards *g)
{
  return GuardsStopped(g) ? &g->trips.front() : nullptr;
}

void GuardsNoteInterrupt(Guards *g, int signal)
{
  g->interrupt_signal = signal;
}

int GuardsExitStatus(const Guards *g)
{
  const GuardTrip *t = GuardsStopTrip(g);
  return t ? EXIT_GUARD_NAN + (int)t->kind : (g->interrupt_signal ? EXIT_INTERRUPTED : EXIT_OK);
}

PetscErrorCode GuardsAddSummary(const Guards *g, JsonWriter *json)
{
  JsonWriter       limits, seen, trips;
  const GuardTrip *t = GuardsStopTrip(g);

  PetscFunctionBeginUser;
  json->String("status", t ? "stopped" : (g->interrupt_signal ? "interrupted" : (g->trips.empty() ? "ok" : "warned")));
  json->Integer("exit_code", GuardsExitStatus(g));
  if (!t && g->interrupt_signal) json->Integer("interrupt_signal", g->interrupt_signal);
  if (t) {
    json->String("guard", GuardNames[t->kind]);
    json->Integer("guard_step", (long long)t->step);
    json->Number("guard_time", t->time);
    json->Number("guard_value", t->value);
    json->Number("guard_limit", t->limit);
    json->String("guard_message", t->what);
    json->String("guard_where", t->where);
    json->String("guard_remedy", t->remedy);
  }
  for (const GuardTrip &x : g->trips) trips.Integer(GuardNames[x.kind], (long long)x.step);
  json->Object("guard_trips", trips); // each guard that tripped and the step it first did
  const GuardOptions &o = g->opt;
  limits.Integer("enable", o.enable ? 1 : 0);
  limits.String("action", GuardActionTypes[o.action]);
  limits.Integer("interval", o.interval);
  limits.Number("overlap", o.overlap);
  limits.Number("displacement", o.displacement);
  limits.Number("energy_growth", g->closed ? o.energy_growth : 0.0);
  limits.Number("floor_share", o.floor_share);
  limits.Number("courant", o.courant);
  limits.Integer("courant_steps", o.courant_steps);
  json->Object("guard_limits", limits);
  seen.Number("overlap_max", g->fig.overlap);
  seen.Number("displacement_max", g->fig.displacement);
  seen.Number("energy_growth_max", g->fig.energy_growth);
  seen.Number("floor_share_max", g->fig.floor_share);
  seen.Number("eps_raw_min", g->fig.eps_raw_min);
  seen.Number("courant_max", g->fig.courant);
  seen.Integer("courant_longest_run", (long long)g->fig.courant_run);
  seen.Integer("particles_lost", g->dem ? (long long)DemGetStats(g->dem)->lost.count : 0);
  seen.Integer("pressure_failures", g->fluid ? (long long)FluidGetStats(g->fluid).ksp_failures : 0);
  seen.Integer("checks", (long long)g->fig.checks);
  seen.Integer("energy_checks", (long long)g->fig.energy_checks);
  seen.Integer("gas_checks", (long long)g->fig.gas_checks);
  json->Object("guard_figures", seen); // the largest figures of the run, tripped or not
  PetscFunctionReturn(0);
}

PetscErrorCode GuardsDestroy(Guards **g)
{
  PetscFunctionBeginUser;
  delete *g;
  *g = nullptr;
  PetscFunctionReturn(0);
}

} // namespace fluidbed
