// What a scene models, and why; and where it asks for more than it can use or less than it needs. The thresholds and
// their reasons are in docs/stability.md ("What a scene models").
#include "fluidbed/scene_model.hpp"
#include "fluidbed/averaging.hpp"
#include "fluidbed/simulation.hpp"
#include "fluidbed/kernels/grid_ratio.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <map>
#include <sstream>

namespace fluidbed {

namespace {

constexpr double kPacking             = 0.6;  // solid fraction of a settled bed: the particles a coupling cell holds there
constexpr double kMinParticlesPerCell = 10.0; // fewer: one particle more or less moves the cell's void fraction by > 0.06
constexpr double kSingleGridCell      = 3.0;  // d: the smallest single-grid cell with a smooth void fraction (seed chapter 5)
// "About 3 d": single-grid cells of 2.7 d and more count. The seed's own single grids of the 550 um beds have cells of
// 2.93 d (a cell per slit), examples/coupling/small_bed 2.78 d; the particle count per cell is checked on its own.
constexpr double  kAbout        = 0.9;
constexpr double  kOneDeep      = 2.0;  // d: a box less deep than two particles holds one layer
constexpr double  kDtFactorSeed = 0.1;  // dt = t_cr / 10 resolves a contact in about 10 steps (the seed's choice)
constexpr double  kDtFactorLow  = 0.02; // below: a step far finer than any contact needs
constexpr long    kJetCells     = 5;    // gas cells across a slit that resolve its jet (the seed's two-grid beds use 5)
constexpr double  kTol          = 1e-9; // relative: a cell of 0.033 m / 33 is not below 1 mm
const char *const kAxes         = "xyz";

std::string Format(const char *fmt, ...) PETSC_ATTRIBUTE_FORMAT(1, 2);
std::string Format(const char *fmt, ...)
{
  char    buf[1024]; // vsnprintf: PetscVSNPrintf writes 0 as "0."
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, sizeof(buf), fmt, ap);
  va_end(ap);
  return buf;
}

// The options as given: name (with its dash) -> value ("" for none). Read from PetscOptionsGetAll, which marks no
// option as used, so that an option the scene never reads is still reported as unused at the end of the run.
class GivenOptions {
public:
  PetscErrorCode Load()
  {
    char *all = NULL;

    PetscFunctionBeginUser;
    PetscCall(PetscOptionsGetAll(NULL, &all));
    std::istringstream in(all ? all : "");
    std::string        word, name;
    while (in >> word) {
      // "-0.5" is a value; "-fluid" a name
      if (word.size() > 1 && word[0] == '-' && !std::isdigit((unsigned char)word[1]) && word[1] != '.') {
        name         = word;
        values[name] = "";
      } else if (!name.empty()) {
        std::string &v = values[name];
        v += (v.empty() ? "" : " ") + word;
      }
    }
    PetscCall(PetscFree(all));
    PetscFunctionReturn(0);
  }
  bool        Has(const std::string &name) const { return values.count(name) > 0; }
  std::string Value(const std::string &name) const { return Has(name) ? values.at(name) : ""; }
  // "-name value" as given, a long value cut short (a list of positions).
  std::string Shown(const std::string &name) const
  {
    const std::string v = Value(name);
    if (v.empty()) return name;
    return name + " " + (v.size() > 24 ? v.substr(0, 20) + "..." : v);
  }
  // The options among names that were given, as given, or the fallback.
  std::string Why(std::initializer_list<const char *> names, const char *fallback = "default") const
  {
    std::string s;
    for (const char *n : names)
      if (n && Has(n)) s += (s.empty() ? "" : " ") + Shown(n);
    return s.empty() ? fallback : s;
  }
  // The given options whose names start with prefix.
  std::vector<std::string> WithPrefix(const std::string &prefix) const
  {
    std::vector<std::string> names;
    for (const auto &kv : values)
      if (!kv.first.compare(0, prefix.size(), prefix)) names.push_back(kv.first);
    return names;
  }

private:
  std::map<std::string, std::string> values;
};

// The mean particle volume: diameters uniform by number in [d_min, d_max] (-particle_diameter_min/max).
double MeanParticleVolume(const ParticleProps &p)
{
  const double a = p.d_min, b = p.d_max;
  const double d3 = b - a > 1e-12 * b ? (b * b * b * b - a * a * a * a) / (4.0 * (b - a)) : b * b * b;
  return PETSC_PI / 6.0 * d3;
}

// The smallest divisor r of n with r h >= target (n when none): the ratio that makes particle cells that large.
PetscInt DivisorAtLeast(PetscInt n, PetscReal h, PetscReal target)
{
  for (long r : kernels::divisors(n))
    if (r * h >= target * (1 - kTol)) return (PetscInt)r;
  return n;
}

// "1 inlet slit", "2 inlet slits"
std::string Count(long long n, const char *what)
{
  return std::to_string(n) + " " + what + (n == 1 ? "" : "s");
}

// "3 x 2" (2D) or "3 x 2 x 5" (3D): the first n entries, each written with fmt ("%.3g").
std::string Cross(int n, const double *v, const char *fmt)
{
  std::string s;
  for (int a = 0; a < n; ++a) s += (a ? " x " : "") + Format(fmt, v[a]);
  return s;
}
std::string Cross(int n, const PetscInt v[3])
{
  std::string s;
  for (int a = 0; a < n; ++a) s += (a ? " x " : "") + std::to_string((long long)v[a]);
  return s;
}
// "3,2" as -pgrid_ratio takes it.
std::string Comma(int n, const PetscInt v[3])
{
  std::string s;
  for (int a = 0; a < n; ++a) s += (a ? "," : "") + std::to_string((long long)v[a]);
  return s;
}

} // namespace

PetscErrorCode SceneModelBuild(Simulation *sim, SceneModel *m)
{
  GivenOptions                          given;
  const Domain                         &dom   = sim->domain;
  const int                             dim   = (int)dom.dim;
  const FluidGrid                      &fg    = sim->grids.fluid;
  const ParticleGrid                   &pg    = sim->grids.particle;
  Dem                                  *dem   = sim->dem;
  Fluid                                *gas   = sim->fluid;
  Coupling                             *cpl   = sim->coupling;
  const PetscReal                       d     = dem ? sim->props.d_max : 0; // cell sizes in largest diameters, as -pgrid_cell_diameters
  JsonWriter                           &json  = m->json;
  PetscInt64                            count = 0;
  PetscReal                             ch[3] = {0, 0, 0}; // the coupling cells (particle cells on two grids, fluid cells on a single grid)
  PetscInt                              cr[3] = {1, 1, 1}; // fluid cells per coupling cell
  std::vector<std::array<PetscReal, 2>> slots;

  auto row  = [&](const char *feature, const std::string &state, const std::string &why) { m->rows.push_back({feature, state, why}); };
  auto warn = [&](const std::string &text) { m->warnings.push_back(text + "; the run goes on"); };
  auto in_d = [&](const PetscReal h[3]) {
    std::vector<double> v;
    for (int a = 0; a < 3; ++a) v.push_back(h[a] / d);
    return v;
  };

  PetscFunctionBeginUser;
  *m = SceneModel();
  PetscCall(given.Load());
  if (sim->swarm) PetscCall(ParticlesGlobalCount(sim->swarm, &count));
  if (cpl) PetscCall(CouplingCellSize(cpl, ch, cr));
  if (gas) PetscCall(FluidGetJetSlots(gas, &slots));
  const bool planar = dim == 2 || (dem && DemGetParams(dem).pseudo2d);

  // ---- The table ----
  if (dem) {
    const std::string size =
      sim->props.d_min < sim->props.d_max ? Format("d %g..%g mm", 1e3 * sim->props.d_min, 1e3 * d) : Format("d %g mm", 1e3 * d);
    row("particles", Format("%lld, %s", (long long)count, size.c_str()),
        sim->output.restart[0] ? given.Shown("-restart")
                               : given.Why({"-insert_count", "-insert_bed_height", "-insert_positions", "-insert_file"}));
  } else row("particles", "off", given.Why({"-particles"}));
  json.Integer("particles", (long long)count);

  if (gas)
    row("gas", Format("on%s, %s", dem ? "" : ", alone", slots.empty() ? "no inlet slit" : Count(slots.size(), "inlet slit").c_str()),
        given.Why({"-fluid"}));
  else row("gas", "off", given.Why({"-fluid"}));
  json.Bool("gas", gas != nullptr);

  row("dimension",
      dim == 2 ? Format("2D (x-y), depth %g mm in cell volumes", 1e3 * dom.len[2])
      : planar ? "3D, motion in the x-y plane"
               : "3D",
      given.Why({"-domain_dim", dim == 2 ? "-domain_lz" : "-dem_pseudo2d"}));
  json.Integer("dim", dim);
  json.Bool("planar", planar);

  if (dem) {
    const DemParams &p = DemGetParams(dem);
    // a tangential force is what turns a particle: friction and a tangential spring, between particles or at a wall
    const bool torque = (p.mu > 0 && p.kt > 0) || (p.wall_mu > 0 && p.wall_kt > 0);
    row("rotation",
        !torque  ? "off in effect: no tangential force"
        : planar ? "spin about z"
                 : "spin about x, y, z",
        given.Why({"-dem_mu", "-wall_mu", "-dem_kt", "-wall_kt"}));
    json.Bool("rotation", torque);

    std::string law = Format("linear spring-dashpot, k_n %g N/m%s, e %g, mu %g", (double)p.kn,
                             p.kt != p.kn ? Format(", k_t %g N/m", (double)p.kt).c_str() : "", (double)p.e, (double)p.mu);
    if (p.wall_kn != p.kn || p.wall_e != p.e || p.wall_mu != p.mu)
      law += Format("; walls k_n %g N/m, e %g, mu %g", (double)p.wall_kn, (double)p.wall_e, (double)p.wall_mu);
    row("contact", law + Format("; dt %g t_cr", (double)p.dt_factor),
        given.Why({"-dem_kn", "-dem_kt", "-dem_e", "-dem_mu", "-wall_kn", "-wall_kt", "-wall_e", "-wall_mu", "-dem_dt_factor"}));
    json.String("contact", "linear spring-dashpot");
    json.Number("k_n", p.kn);
    json.Number("e", p.e);
    json.Number("mu", p.mu);
    json.Number("dt_factor", p.dt_factor);
  } else {
    row("rotation", "off (no particles)", given.Why({"-particles"}));
    row("contact", "none (no particles)", given.Why({"-particles"}));
    json.Bool("rotation", false);
    json.String("contact", "none");
  }

  if (cpl) row("drag", Format("%s, buoyancy (Model B)", CouplingDragName(cpl)), given.Why({"-drag_model"}));
  else row("drag", dem ? "none (no gas)" : "none (no particles)", given.Why({dem ? "-fluid" : "-particles"}));
  json.String("drag_model", cpl ? CouplingDragName(cpl) : "none");

  const bool single = cpl && cr[0] * cr[1] * cr[2] == 1; // the coupling cell is the fluid cell
  if (cpl) {
    const std::string cells = Cross(dim, in_d(ch).data(), "%.3g") + " d";
    std::string       state;
    if (!CouplingOnParticleGrid(cpl)) state = "single (-couple_grid single): coupling on fluid cells of " + cells;
    else if (single) state = "single (ratio 1): particle cell = fluid cell of " + cells;
    else state = "two: " + Cross(dim, cr) + " fluid cells per particle cell of " + cells;
    row("grids", state,
        given.Why({"-couple_grid", "-grid_nx", "-grid_ny", dim == 3 ? "-grid_nz" : nullptr, "-pgrid_ratio", "-pgrid_cell_diameters"}));
    json.String("grid", single ? "single" : "two");
    json.String("couple_grid", CouplingOnParticleGrid(cpl) ? "two" : "single");
    json.IntegerArray("fluid_cells_per_particle_cell", {(long long)cr[0], (long long)cr[1], (long long)cr[2]});
    json.NumberArray("particle_cell_diameters", in_d(ch));
  } else if (dem) {
    row("grids", "particle grid only (no gas): cells of " + Cross(dim, in_d(pg.h).data(), "%.3g") + " d bin the particles",
        given.Why({"-pgrid_cell_diameters", "-pgrid_ratio"}));
    json.String("grid", "particles only");
    json.NumberArray("particle_cell_diameters", in_d(pg.h));
  } else {
    const PetscReal mm[3] = {1e3 * fg.h[0], 1e3 * fg.h[1], 1e3 * fg.h[2]};
    row("grids", "gas grid only: " + Cross(dim, fg.n) + " cells of " + Cross(dim, mm, "%.4g") + " mm",
        given.Why({"-grid_nx", "-grid_ny", dim == 3 ? "-grid_nz" : nullptr}));
    json.String("grid", "gas only");
  }

  if (cpl) {
    const PetscInt substeps = CouplingSubsteps(cpl), gas_substeps = CouplingGasSubsteps(cpl);
    if (gas_substeps > 1)
      row("gas step", Format("1 DEM step / %d = %.4g s", (int)gas_substeps, (double)(DemGetParams(dem).dt / gas_substeps)),
          given.Why({"-couple_gas_substeps"}));
    else
      row("gas step", Count(substeps, "DEM step") + Format(" = %.4g s", (double)(substeps * DemGetParams(dem).dt)),
          given.Why({"-couple_substeps"}));
    json.Integer("substeps", (long long)substeps);
    json.Integer("gas_substeps", (long long)gas_substeps);
  } else if (gas) {
    const PetscReal fixed = FluidFixedTimeStep(gas);
    row("gas step", fixed > 0 ? Format("fixed, %.4g s", (double)fixed) : "follows the gas limits", given.Why({"-fluid_dt", "-fluid_cfl"}));
  } else row("gas step", "none (no gas)", given.Why({"-fluid"}));

  if (gas) {
    const char *ksp, *pc;
    PetscInt    max_it;
    PetscCall(FluidPressureSolverInfo(gas, &ksp, &pc, &max_it));
    row("pressure", Format("%s + %s", ksp, pc), given.Why({"-fluid_p_ksp_type", "-fluid_p_pc_type"}));
    json.String("pressure_ksp", ksp);
    json.String("pressure_pc", pc);
  } else row("pressure", "none (no gas)", given.Why({"-fluid"}));

  {
    const GuardOptions &o      = sim->guards->opt;
    const char         *action = !o.enable ? "off" : o.action == GUARD_ACTION_STOP ? "stop" : "warn";
    row("guards",
        !o.enable ? "off"
                  : Format("on, %s at a trip, checked every %s", action, o.interval == 1 ? "step" : Count(o.interval, "step").c_str()),
        given.Why({"-guard_enable", "-guard_action", "-guard_interval"}));
    json.String("guards", action);
  }

  PetscReal avg_start, avg_interval;
  PetscCall(BedAveragesSchedule(sim->averages, &avg_start, &avg_interval));
  if (sim->averages)
    row("averaging", Format("from t = %g s, every %g s", (double)avg_start, (double)avg_interval),
        given.Why({"-average", "-average_start", "-average_interval"}));
  else row("averaging", "off", given.Why({"-average", "-average_start"}));
  json.Bool("averaging", sim->averages != nullptr);
  if (sim->averages) json.Number("averaging_start", avg_start);

  {
    const OutputSchedule &o     = sim->output;
    std::string           state = o.interval > 0 ? Format("snapshots every %g s", (double)o.interval) : "no snapshots";
    state += o.checkpoint_interval > 0 ? Format(", checkpoints every %g s", (double)o.checkpoint_interval) : ", no checkpoints";
    state += sim->monitor.interval > 0 ? Format(", monitor every %g s", (double)sim->monitor.interval) : ", monitor every step";
    row("output", state, given.Why({"-output_interval", "-checkpoint_interval", "-monitor_dt"}));
    json.Number("snapshot_interval", o.interval);
    json.Number("checkpoint_interval", o.checkpoint_interval);
  }

  // What is off.
  row("heat", "off: not modelled by fluidbed (no energy equation)", "no option turns it on");
  json.Bool("heat", false);

  {
    std::string       per;
    std::vector<bool> flags;
    for (int a = 0; a < 3; ++a) {
      flags.push_back(a < dim && dom.periodic[a]);
      if (flags.back()) per += std::string(per.empty() ? "" : ", ") + kAxes[a];
    }
    row("periodic", per.empty() ? "off" : per,
        given.Why({"-domain_periodic_x", "-domain_periodic_y", dim == 3 ? "-domain_periodic_z" : nullptr}));
    json.BoolArray("periodic", flags);
  }

  {
    const bool        particles_out = dem && dom.top_outlet;
    const std::string top           = gas ? FluidBoundaryType(gas, FACE_YHI) : "none";
    const bool        gas_out       = top == "outlet" || top == "pressure";
    std::string       state;
    if (dom.periodic[1]) state = "off: y is periodic";
    else if (!particles_out && !gas_out) state = "off: closed top";
    else {
      state = "top: ";
      if (dem) state += particles_out ? "particles leave (removed)" : "particles stay";
      if (gas) state += std::string(dem ? ", " : "") + (gas_out ? "gas leaves (" + top + ")" : "gas wall");
    }
    row("outlet", state, given.Why({"-domain_top_outlet", gas ? "-fluid_bc_yhi" : nullptr}));
    json.Bool("outlet", particles_out || gas_out);
    json.Bool("particle_outlet", particles_out);
    json.String("gas_outlet", gas_out ? top : "none");
  }

  // ---- More than the scene can use, or less than it needs ----
  // A gas grid several cells deep on a bed one particle deep: the gas cannot vary across a depth that holds one
  // particle, and every layer costs a whole gas grid.
  bool deep_warned = false;
  if (cpl && dim == 3 && fg.n[2] > 1 && dom.len[2] < kOneDeep * sim->props.d_min * (1 - kTol)) {
    deep_warned = true;
    warn(Format("the gas grid is %d cells deep (-grid_nz %d) on a bed one particle deep (-domain_lz %g mm = %.3g d, below %g d): the gas "
                "cannot vary across a depth that holds one particle, and each layer costs a whole gas grid; use -grid_nz 1%s, or the 2D "
                "model (-domain_dim 2 -domain_lz %g)",
                (int)fg.n[2], (int)fg.n[2], 1e3 * dom.len[2], (double)(dom.len[2] / sim->props.d_min), kOneDeep,
                pg.ratio[2] > 1 ? " with 1 as the z entry of -pgrid_ratio" : "", (double)dom.len[2]));
  }

  if (cpl && single) {
    // Fluid cells below about 3 d as coupling cells: the particle-centre void fraction of so small a cell jumps as
    // particles cross it (seed chapter 5). Directions with one cell across the box cannot be coarser.
    std::string axes, coarser;
    PetscInt    ratio[3] = {1, 1, 1};
    for (int a = 0; a < dim; ++a) {
      if (fg.n[a] > 1 && ch[a] < kAbout * kSingleGridCell * d * (1 - kTol)) {
        axes += std::string(axes.empty() ? "" : ", ") + kAxes[a];
        coarser += Format("%s-grid_n%c at most %d", coarser.empty() ? "" : ", ", kAxes[a],
                          (int)PetscMax(1, (PetscInt)std::floor(dom.len[a] / (kSingleGridCell * d) + kTol)));
      }
      if (fg.n[a] > 1) ratio[a] = DivisorAtLeast(fg.n[a], fg.h[a], kSingleGridCell * d);
    }
    if (!axes.empty()) {
      PetscReal two[3] = {fg.h[0] * ratio[0], fg.h[1] * ratio[1], fg.h[2] * ratio[2]};
      warn(Format("single grid: the coupling cells are %s d, below about %g d along %s: cells that small hold too few particles for a "
                  "smooth void fraction (seed chapter 5); use fluid cells of %g d or more (%s), or two grids that keep this gas grid "
                  "(%s-pgrid_ratio %s: particle cells of %s d)",
                  Cross(dim, in_d(ch).data(), "%.3g").c_str(), kSingleGridCell, axes.c_str(), kSingleGridCell, coarser.c_str(),
                  CouplingOnParticleGrid(cpl) ? "" : "-couple_grid two ", Comma(dim, ratio).c_str(),
                  Cross(dim, in_d(two).data(), "%.3g").c_str()));
    }
  }

  if (cpl) {
    // The particles a coupling cell holds at the bed's packing (in 2D the cell is -domain_lz deep): with few, one
    // particle more or less moves the void fraction by V_p / V_cell.
    const double vp = MeanParticleVolume(sim->props), vcell = ch[0] * ch[1] * ch[2], held = kPacking * vcell / vp;
    if (held < kMinParticlesPerCell) {
      // particle cells at least X on a side in the directions with more than one fluid cell, the others as they are
      double fixed     = 1;
      int    free_axes = 0;
      for (int a = 0; a < 3; ++a) {
        if (a < dim && fg.n[a] > 1) ++free_axes;
        else fixed *= ch[a];
      }
      const double need     = kMinParticlesPerCell * vp / kPacking;
      const double side     = free_axes ? std::pow(need / fixed, 1.0 / free_axes) : 0;
      PetscInt     ratio[3] = {1, 1, 1};
      PetscReal    cell[3]  = {ch[0], ch[1], ch[2]};
      for (int a = 0; a < dim; ++a)
        if (fg.n[a] > 1) {
          ratio[a] = DivisorAtLeast(fg.n[a], fg.h[a], PetscMax(side, ch[a]));
          cell[a]  = ratio[a] * fg.h[a];
        }
      const PetscReal mm[3] = {1e3 * ch[0], 1e3 * ch[1], 1e3 * ch[2]}, mm_new[3] = {1e3 * cell[0], 1e3 * cell[1], 1e3 * cell[2]};
      warn(
        Format("a coupling cell of %s mm holds about %.3g particles at the bed's packing (solid fraction %g), fewer than %g: one particle "
               "more or less moves its void fraction by %.2f; use larger particle cells, %s-pgrid_ratio %s (%s mm, about %.3g "
               "particles)%s",
               Cross(3, mm, "%.4g").c_str(), held, kPacking, kMinParticlesPerCell, vp / vcell,
               CouplingOnParticleGrid(cpl) ? "" : "-couple_grid two ", Comma(dim, ratio).c_str(), Cross(3, mm_new, "%.4g").c_str(),
               kPacking * cell[0] * cell[1] * cell[2] / vp,
               dim == 2 ? Format(", or a deeper 2D bed (-domain_lz, now %g mm)", 1e3 * dom.len[2]).c_str() : ""));
    }
  }

  // A DEM step far below what the contacts need: t_cr / 10 resolves a contact; each halving doubles the steps.
  if (dem && DemGetParams(dem).dt_factor < kDtFactorLow)
    warn(Format("-dem_dt_factor %g is far below what the contacts need (t_cr / 10, -dem_dt_factor %g, resolves a contact in about 10 "
                "steps, the seed's choice): the run takes %.3g times the steps of -dem_dt_factor %g for the same time; use "
                "-dem_dt_factor %g unless the finer step is the point of the run",
                (double)DemGetParams(dem).dt_factor, kDtFactorSeed, kDtFactorSeed / DemGetParams(dem).dt_factor, kDtFactorSeed,
                kDtFactorSeed));

  // A gas grid finer than its slits need: the narrowest slit over the cell width is the cells that resolve it.
  if (gas && !slots.empty()) {
    double w = PETSC_MAX_REAL;
    for (const auto &s : slots) w = PetscMin(w, s[1] - s[0]);
    const long cells = std::lround(w / fg.h[0]);
    if (cells > kJetCells)
      warn(Format("the narrowest inlet slit (-inlet_jets, %g mm wide) spans %ld gas cells along x, more than the %ld that resolve a jet "
                  "(the seed's two-grid beds use %ld): the whole gas grid is finer than its slits need; use gas cells of at least %g mm "
                  "along x (-grid_nx at most %d, with the slits' edges on cell faces)",
                  1e3 * w, cells, kJetCells, kJetCells, 1e3 * w / kJetCells,
                  (int)PetscMax(1, (PetscInt)std::floor(dom.len[0] * kJetCells / w + kTol))));
  }
  // Gas cells below a particle where no slit needs them: along x without slits, along z in 3D (slits run through
  // the depth). The void fraction and drag are particle averages: they show nothing finer than a particle.
  if (cpl) {
    std::string axes, coarser, cells;
    for (int a = 0; a < dim; ++a) {
      const bool needed = a == 1 || (a == 0 && !slots.empty()) || (a == 2 && deep_warned);
      if (needed || fg.n[a] <= 1 || fg.h[a] >= d * (1 - kTol)) continue;
      axes += std::string(axes.empty() ? "" : ", ") + kAxes[a];
      cells += Format("%s%.3g d along %c", cells.empty() ? "" : ", ", (double)(fg.h[a] / d), kAxes[a]);
      coarser += Format("%s-grid_n%c at most %d", coarser.empty() ? "" : ", ", kAxes[a],
                        (int)PetscMax(1, (PetscInt)std::floor(dom.len[a] / d + kTol)));
    }
    if (!axes.empty())
      warn(Format("the gas cells are %s, smaller than a particle where no slit needs them (%s): the void fraction and drag show nothing "
                  "finer than a particle; use gas cells of at least d (%s)",
                  cells.c_str(), slots.empty() ? "the scene has no -inlet_jets" : "slits run through the depth", coarser.c_str()));
  }

  // Averaging that never samples: it starts at or after the end of the run, or is off while -average_* options ask
  // for it. These options have no effect, and go to summary.json's "unused_options" too (option_report.hpp).
  if (sim->averages && avg_start >= sim->run.t_final) {
    const std::string name   = given.Has("-average_start") ? "-average_start" : "-average";
    const std::string value  = given.Value(name);
    const std::string reason = Format("is at or after -t_final %g s: the run ends before averaging starts", (double)sim->run.t_final);
    m->without_effect.push_back({name, value, reason, true});
    warn(Format("option -average_start %s %s, and analysis.h5 will hold no sample; an -average_start below %g s, or a -t_final after %g "
                "s, averages",
                given.Has("-average_start") ? value.c_str() : "(default 0)", reason.c_str(), (double)sim->run.t_final, (double)avg_start));
  } else if (!sim->averages) {
    const char *off = given.Has("-average") ? "averaging is off (-average 0)" : "averaging is off (no -average or -average_start)";
    for (const std::string &name : given.WithPrefix("-average_")) {
      const std::string reason = Format("has no effect: %s", off);
      m->without_effect.push_back({name, given.Value(name), reason, true});
      warn(Format("option %s %s; add -average (from t = 0) or -average_start S to average", given.Shown(name).c_str(), reason.c_str()));
    }
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SceneModelView(const SceneModel &m, PetscViewer viewer)
{
  int wf = (int)strlen("feature"), ws = (int)strlen("state");

  PetscFunctionBeginUser;
  for (const SceneModelRow &r : m.rows) {
    wf = std::max(wf, (int)r.feature.size());
    ws = std::max(ws, (int)r.state.size());
  }
  PetscCall(PetscViewerASCIIPrintf(viewer, "Model: what this scene simulates, and the options that set it\n"));
  PetscCall(PetscViewerASCIIPrintf(viewer, "  %-*s  %-*s  %s\n", wf, "feature", ws, "state", "why"));
  for (const SceneModelRow &r : m.rows)
    PetscCall(PetscViewerASCIIPrintf(viewer, "  %-*s  %-*s  %s\n", wf, r.feature.c_str(), ws, r.state.c_str(), r.why.c_str()));
  for (const std::string &w : m.warnings) PetscCall(PetscViewerASCIIPrintf(viewer, "WARNING: %s\n", w.c_str()));
  PetscFunctionReturn(0);
}

void SceneModelAddSummary(const SceneModel &m, JsonWriter *json)
{
  json->Object("model", m.json);
  json->StringArray("model_warnings", m.warnings);
}

} // namespace fluidbed
