// Time averages of the bed during a run: see include/fluidbed/averaging.hpp. Loops over the particles and the
// cells and calls the kernels of include/fluidbed/kernels/bed_statistics.hpp, bed_measures.hpp and jet_height.hpp.
#include "fluidbed/averaging.hpp"
#include "fluidbed/kernels/bed_measures.hpp"
#include "fluidbed/kernels/jet_height.hpp"
#include "fluidbed/fluid.hpp"
#include "fluidbed/hdf5io.hpp"
#include "fluidbed/options.hpp"
#include "fluidbed/probes.hpp"

#include <petscviewerhdf5.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace fluidbed {

static_assert(sizeof(PetscScalar) == sizeof(double) && sizeof(PetscReal) == sizeof(double), "the bed kernels read PetscScalar as double");

namespace {

using kernels::CellAverageSums;
using kernels::CellGrid;
using kernels::CellMeans;
using kernels::CellSums;

// Columns of a time-series row: time, cut-off bed height, pressure drop, then one jet height per jet.
enum SeriesColumn { SERIES_TIME, SERIES_CUTOFF, SERIES_DP, SERIES_JET0 };

// Whole-bed measures of the window, computed on rank 0 from the gathered averages and broadcast.
struct BedMeasures {
  double samples = 0, window_start = 0, window_end = 0;
  double height_cutoff = 0, height_volume = 0, bed_mass = 0, bulk_fraction = 0, bulk_fraction_cutoff = 0;
  double circulation = 0, fraction_down = 0, speed_down = 0;
  double convective_power = 0, diffusive_power = 0;
  double jet_height = 0, jet_height_std = 0, jet_detachments = 0, jets_detaching = 0;
  double pressure_drop = 0;
};
constexpr int kMeasures = sizeof(BedMeasures) / sizeof(double);
static_assert(sizeof(BedMeasures) == kMeasures * sizeof(double), "BedMeasures must be a flat record of doubles");

PetscClassId  avg_classid = 0;
PetscLogEvent ev_sample, ev_write, ev_checkpoint;

} // namespace

// The averages as an output of the run: sampled at its output steps, analysis.h5 at the end, "averages" in
// summary.json and /averages in checkpoints.
struct BedAverages final : Output {
  MPI_Comm comm = MPI_COMM_NULL;
  PetscInt dim  = 3;

  // options
  PetscReal                    start = 0, interval = 1e-3, output_interval = 0;
  std::vector<PetscReal>       heights; // m above the distributor
  PetscInt                     min_count = 2;
  PetscReal                    cutoff = kernels::kBedSurfaceSolidFraction, occupied = kernels::kOccupiedSolidFraction;
  PetscReal                    p_low = 0, p_high = 0;
  PetscReal                    jet_void = kernels::kJetVoidFraction;
  kernels::DetachmentCriterion crit;
  PetscBool                    reset = PETSC_FALSE; // at a restart, drop the checkpoint's averages

  // grids
  CellGrid                              grid;  // the particle grid, whole
  CellGrid                              block; // this rank's ghosted block of it (binning)
  CellGrid                              owned; // this rank's owned block
  PetscInt                              gs[3]{0, 0, 0}, gm[3]{1, 1, 1}, xs[3]{0, 0, 0}, xm[3]{1, 1, 1};
  CellGrid                              fgrid; // the fluid grid (jets, pressure)
  std::vector<std::array<PetscReal, 2>> jets;
  std::vector<std::vector<long>>        jet_cells; // inlet cells of each jet on the fluid grid
  DM                                    da_sums = nullptr, da_acc = nullptr, da_scalar = nullptr, da_vector = nullptr;
  Vec                                   sums_loc = nullptr, sums = nullptr, acc = nullptr;
  Vec                                   eps_nat = nullptr, eps_zero = nullptr; // the gas void fraction in natural order, gathered on rank 0
  VecScatter                            eps_scatter = nullptr;

  // state
  PetscInt64             samples = 0;
  PetscReal              weight = 0, next = 0, next_output = 0;
  std::vector<PetscReal> series; // rows of columns() values
  BedMeasures            measures;
  PetscBool              measured = PETSC_FALSE;
  double                 wall     = 0;

  PetscInt columns() const { return SERIES_JET0 + (PetscInt)jets.size(); }
  PetscInt rows() const { return (PetscInt)(series.size() / (std::size_t)columns()); }

  const char    *Name() const override { return "averages"; }
  PetscErrorCode Step(const RunView &run) override;
  PetscErrorCode Finalize(const RunView &run) override;
  PetscErrorCode AddSummary(const RunView &run, JsonWriter *json) override;
  PetscErrorCode CheckpointWrite(const RunView &run, PetscViewer viewer) override;
  PetscErrorCode CheckpointRead(const RunView &run, PetscViewer viewer) override;
  PetscErrorCode Destroy() override;
  // Writes <output_dir>/analysis.h5 and analysis.xmf and computes the whole-bed measures for the summary.
  PetscErrorCode Write(const RunView &run);
};

namespace {

PetscErrorCode RegisterEvents()
{
  PetscFunctionBeginUser;
  if (avg_classid) PetscFunctionReturn(0);
  PetscCall(PetscClassIdRegister("Bed averages", &avg_classid));
  PetscCall(PetscLogEventRegister("AvgSample", avg_classid, &ev_sample));
  PetscCall(PetscLogEventRegister("AvgWrite", avg_classid, &ev_write));
  PetscCall(PetscLogEventRegister("AvgCheckpoint", avg_classid, &ev_checkpoint));
  PetscFunctionReturn(0);
}

PetscErrorCode SetFromOptions(BedAverages *a, const RunView &run, PetscBool *on)
{
  const Domain &dom   = run.domain;
  PetscReal     h[64] = {0}, ph[2] = {0.0, dom.len[1]};
  PetscInt      nh = 64, nph = 2;
  PetscBool     enable = PETSC_FALSE, set_enable, set_start, set_h, set_drop;
  // two fluid cells, but never more than the box is tall (a pure DEM scene may have a single tall cell)
  PetscReal min_drop = PetscMin(2.0 * run.grids.fluid.h[1], dom.len[1]);

  PetscFunctionBeginUser;
  PetscOptionsBegin(a->comm, "", "Time averages of the bed on the particle grid (analysis.h5, analysis.xmf, summary.json)", "Analysis");
  PetscCall(OptionsBool(PetscOptionsObject, "-average",
                        "Time-average the bed on the particle grid from -average_start (on when -average_start is given)", &enable,
                        &set_enable));
  PetscCall(
    OptionsReal(PetscOptionsObject, "-average_start", "Simulated time of the first sample", "s", NonNegative(1e6), &a->start, &set_start));
  PetscCall(OptionsBool(PetscOptionsObject, "-average_reset",
                        "At a -restart, drop the checkpoint's averages and start afresh at -average_start or the checkpoint's time, "
                        "whichever is later (a window that leaves out a start-up)",
                        &a->reset, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-average_interval",
                        "Simulated time between samples (each sample weighs the same; keep it short against the bubble period for "
                        "the jet height)",
                        "s", Positive(1e6), &a->interval, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-average_output_interval",
                        "Simulated time between intermediate writes of analysis.h5 (0: at the end of the run only)", "s", NonNegative(1e6),
                        &a->output_interval, NULL));
  PetscCall(OptionsRealArray(PetscOptionsObject, "-average_heights",
                             "Heights above the distributor of the horizontal profiles (the particle-grid layer holding each)", "m",
                             Closed(0.0, dom.len[1]), h, &nh, PETSC_FALSE, &set_h));
  PetscCall(OptionsInt(PetscOptionsObject, "-average_temperature_min_count",
                       "Particles a cell needs in a sample for its granular temperature (eq. 3.4) to count", 2, 1000000, &a->min_count,
                       NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-average_cutoff",
                        "Cross-section-averaged solid fraction that marks the bed surface for the cut-off bed height", "",
                        RealRange{0.0, 1.0, true, true}, &a->cutoff, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-average_occupied",
                        "Time-averaged solid fraction above which a cell holds particles (expanded-volume height, circulation)", "",
                        RealRange{0.0, 1.0, false, true}, &a->occupied, NULL));
  PetscCall(OptionsRealArray(PetscOptionsObject, "-average_pressure_heights",
                             "Heights above the distributor low,high between which the pressure drop is taken (default: bottom and top)",
                             "m", Closed(0.0, dom.len[1]), ph, &nph, PETSC_TRUE, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-average_jet_void_fraction",
                        "Void fraction above which a fluid cell belongs to a jet or its bubble (jet penetration height)", "",
                        RealRange{0.0, 1.0, true, true}, &a->jet_void, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-average_jet_min_drop",
                        "Smallest drop of the jet height between samples that counts as a bubble detachment (default: two fluid cells)",
                        "m", NonNegative(dom.len[1]), &min_drop, &set_drop));
  PetscCall(OptionsReal(PetscOptionsObject, "-average_jet_min_relative_drop",
                        "Smallest drop of the jet height between samples, as a fraction of the height before, that counts as a detachment",
                        "", Closed(0.0, 1.0), &a->crit.min_relative_drop, NULL));
  PetscOptionsEnd();
  *on = set_enable ? enable : set_start;
  PetscCheck(ph[0] < ph[1], a->comm, PETSC_ERR_ARG_OUTOFRANGE, "-average_pressure_heights %.6g,%.6g: the first height must be the lower",
             (double)ph[0], (double)ph[1]);
  a->p_low         = ph[0];
  a->p_high        = ph[1];
  a->crit.min_drop = min_drop;
  if (set_h) a->heights.assign(h, h + nh);
  PetscFunctionReturn(0);
}

PetscErrorCode SetUp(BedAverages *a, const RunView &run)
{
  const Domain       &dom = run.domain;
  const ParticleGrid &pg  = run.grids.particle;
  const FluidGrid    &fg  = run.grids.fluid;

  PetscFunctionBeginUser;
  a->dim  = dom.dim;
  a->grid = GridsCellGrid(dom, pg.n);
  PetscCall(DMDACreateCompatibleDMDA(pg.da_cell, kernels::kCellSumsDof, &a->da_sums));
  PetscCall(DMDACreateCompatibleDMDA(pg.da_cell, kernels::kCellAverageSumsDof, &a->da_acc));
  PetscCall(DMDACreateCompatibleDMDA(pg.da_cell, 1, &a->da_scalar));
  PetscCall(DMDACreateCompatibleDMDA(pg.da_cell, dom.dim, &a->da_vector));
  PetscCall(DMCreateLocalVector(a->da_sums, &a->sums_loc));
  PetscCall(DMCreateGlobalVector(a->da_sums, &a->sums));
  PetscCall(DMCreateGlobalVector(a->da_acc, &a->acc));
  PetscCall(PetscObjectSetName((PetscObject)a->acc, "sums"));
  PetscCall(VecZeroEntries(a->acc));
  PetscCall(DMDAGetGhostCorners(a->da_sums, &a->gs[0], &a->gs[1], &a->gs[2], &a->gm[0], &a->gm[1], &a->gm[2]));
  PetscCall(DMDAGetCorners(a->da_sums, &a->xs[0], &a->xs[1], &a->xs[2], &a->xm[0], &a->xm[1], &a->xm[2]));
  if (dom.dim == 2) a->gs[2] = a->xs[2] = 0, a->gm[2] = a->xm[2] = 1;
  a->block = a->owned = a->grid;
  for (int d = 0; d < 3; ++d) {
    a->block.lo[d] = a->grid.lo[d] + a->gs[d] * a->grid.h[d];
    a->block.n[d]  = (int)a->gm[d];
    a->owned.lo[d] = a->grid.lo[d] + a->xs[d] * a->grid.h[d];
    a->owned.n[d]  = (int)a->xm[d];
  }
  if (dom.dim == 2) a->block.lo[2] = a->owned.lo[2] = dom.lo[2];

  if (run.fluid) {
    DM da_eps;
    a->fgrid = GridsCellGrid(dom, fg.n);
    PetscCall(FluidGetJetSlots(run.fluid, &a->jets));
    for (const auto &s : a->jets) a->jet_cells.push_back(kernels::jet_inlet_cells(a->fgrid, s[0], s[1]));
    if (!a->jets.empty()) {
      PetscCall(FluidGetCellDMs(run.fluid, &da_eps, NULL));
      PetscCall(DMDACreateNaturalVector(da_eps, &a->eps_nat));
      PetscCall(VecScatterCreateToZero(a->eps_nat, &a->eps_scatter, &a->eps_zero));
    }
  }
  a->next        = a->start;
  a->next_output = a->start + a->output_interval;
  PetscFunctionReturn(0);
}

// The jet heights of the current gas void fraction (m above the distributor), on every rank.
PetscErrorCode JetHeights(BedAverages *a, const RunView &run, std::vector<PetscReal> *h)
{
  DM                 da;
  Vec                eps;
  const PetscScalar *e;
  PetscMPIInt        rank;

  PetscFunctionBeginUser;
  h->assign(a->jets.size(), 0.0);
  if (a->jets.empty()) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Comm_rank(a->comm, &rank));
  PetscCall(FluidGetCellDMs(run.fluid, &da, NULL));
  PetscCall(FluidGetVoidFraction(run.fluid, &eps));
  PetscCall(DMDAGlobalToNaturalBegin(da, eps, INSERT_VALUES, a->eps_nat));
  PetscCall(DMDAGlobalToNaturalEnd(da, eps, INSERT_VALUES, a->eps_nat));
  PetscCall(VecScatterBegin(a->eps_scatter, a->eps_nat, a->eps_zero, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(a->eps_scatter, a->eps_nat, a->eps_zero, INSERT_VALUES, SCATTER_FORWARD));
  if (!rank) {
    PetscCall(VecGetArrayRead(a->eps_zero, &e));
    for (std::size_t q = 0; q < a->jets.size(); ++q) (*h)[q] = kernels::jet_height(a->fgrid, e, a->jet_cells[q], a->jet_void);
    PetscCall(VecRestoreArrayRead(a->eps_zero, &e));
  }
  PetscCallMPI(MPI_Bcast(h->data(), (int)h->size(), MPIU_REAL, 0, a->comm));
  PetscFunctionReturn(0);
}

// Bins the rank's particles into its ghosted block of the particle grid (a particle may sit up to half a Verlet
// skin outside its rank's cells between neighbour-list rebuilds) and adds the halos to their owners.
PetscErrorCode BinParticles(BedAverages *a, const RunView &run)
{
  PetscScalar *s;

  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(a->sums_loc));
  if (run.swarm) {
    ParticleArrays p;
    PetscInt       outside = 0;
    PetscCall(ParticleArraysGet(run.swarm, &p));
    for (PetscInt q = 0; q < p.n; ++q)
      for (int d = 0; d < a->dim; ++d) {
        const int c = kernels::axis_cell(a->grid, d, p.x[a->dim * q + d]);
        if (c < a->gs[d] || c >= a->gs[d] + a->gm[d]) ++outside;
      }
    kernels::ParticleView view;
    view.n        = (std::size_t)p.n;
    view.x        = p.x;
    view.x_stride = (int)p.dim;
    view.v        = p.v;
    view.v_stride = 3;
    view.d        = p.d;
    PetscCall(VecGetArray(a->sums_loc, &s));
    if (!outside) kernels::add_particles_to_cells(a->block, view, run.props.density, reinterpret_cast<CellSums *>(s));
    PetscCall(VecRestoreArray(a->sums_loc, &s));
    PetscCall(ParticleArraysRestore(run.swarm, &p));
    PetscCheck(!outside, PETSC_COMM_SELF, PETSC_ERR_PLIB, "averages: a particle lies outside its rank's particle-grid halo");
  }
  PetscCall(VecZeroEntries(a->sums));
  PetscCall(DMLocalToGlobal(a->da_sums, a->sums_loc, ADD_VALUES, a->sums));
  PetscFunctionReturn(0);
}

// Adds the current state as one sample.
PetscErrorCode Sample(BedAverages *a, const RunView &run)
{
  const PetscScalar *s;
  PetscScalar       *acc;
  const double       t0 = MPI_Wtime();

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(ev_sample, 0, 0, 0, 0));
  PetscCall(BinParticles(a, run));

  // add the snapshot to the window; the cross-section solid fraction for the cut-off bed height
  const double        vc = kernels::cell_volume(a->grid);
  std::vector<double> layers_loc((std::size_t)a->grid.n[1], 0.0), layers((std::size_t)a->grid.n[1]);
  PetscCall(VecGetArrayRead(a->sums, &s));
  PetscCall(VecGetArray(a->acc, &acc));
  {
    const CellSums  *cs = reinterpret_cast<const CellSums *>(s);
    CellAverageSums *ca = reinterpret_cast<CellAverageSums *>(acc);
    for (long c = 0; c < kernels::cell_count(a->owned); ++c) kernels::add_sample(ca[c], cs[c], vc, (int)a->dim, 1.0, (double)a->min_count);
    const std::vector<double> ls = kernels::layer_sums(a->owned, [&](long c) { return kernels::solid_fraction(cs[c], vc); });
    for (std::size_t j = 0; j < ls.size(); ++j) layers_loc[(std::size_t)a->xs[1] + j] = ls[j];
  }
  PetscCall(VecRestoreArray(a->acc, &acc));
  PetscCall(VecRestoreArrayRead(a->sums, &s));
  PetscCallMPI(MPI_Allreduce(layers_loc.data(), layers.data(), (int)layers.size(), MPI_DOUBLE, MPI_SUM, a->comm));
  for (double &v : layers) v /= (double)kernels::cells_per_layer(a->grid);

  std::vector<PetscReal> row((std::size_t)a->columns(), 0.0);
  row[SERIES_TIME]   = run.time;
  row[SERIES_CUTOFF] = kernels::cutoff_bed_height(a->grid, layers, a->cutoff);
  if (run.fluid && FluidGetStats(run.fluid).steps == 0) {
    // before the first gas step the gas holds its initial fields, not the particles' void fraction: no value
    for (PetscInt c = SERIES_DP; c < a->columns(); ++c) row[(std::size_t)c] = NAN;
  } else if (run.fluid) {
    std::vector<PetscReal> p;
    PetscCall(GasPressureProfile(run.fluid, run.domain, run.grids.fluid, &p));
    row[SERIES_DP] = kernels::pressure_drop(a->fgrid, p, a->p_low, a->p_high);
    std::vector<PetscReal> jh;
    PetscCall(JetHeights(a, run, &jh));
    for (std::size_t q = 0; q < jh.size(); ++q) row[SERIES_JET0 + q] = jh[q];
  }
  a->series.insert(a->series.end(), row.begin(), row.end());
  a->samples += 1;
  a->weight += 1.0;
  a->measured = PETSC_FALSE;
  PetscCall(PetscLogEventEnd(ev_sample, 0, 0, 0, 0));
  a->wall += MPI_Wtime() - t0;
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode BedAverages::Step(const RunView &run)
{
  const PetscReal eps = 0.5 * run.dt;

  PetscFunctionBeginUser;
  if (run.time >= next - eps) {
    PetscCall(Sample(this, run));
    while (next <= run.time + eps) next += interval;
  }
  if (output_interval > 0 && samples > 0 && run.time >= next_output - eps) {
    PetscCall(Write(run));
    while (next_output <= run.time + eps) next_output += output_interval;
  }
  PetscFunctionReturn(0);
}

namespace {

// A rank-0 array as a dataset of n / bs rows of bs values (one dimension when bs is 1, unless `table`), with its
// units and description. Other ranks pass n = 0. Nothing is written for an empty array.
PetscErrorCode WriteArray(PetscViewer viewer, MPI_Comm comm, const char *group, const char *name, PetscInt bs, PetscInt n,
                          const double *data, const char *units, const char *description, PetscBool table = PETSC_FALSE)
{
  Vec      v;
  PetscInt N;

  PetscFunctionBeginUser;
  PetscCall(VecCreateMPIWithArray(comm, bs, n, PETSC_DECIDE, data, &v));
  PetscCall(VecGetSize(v, &N));
  if (N) {
    const std::string path = std::string(group) + "/" + name;
    PetscCall(PetscObjectSetName((PetscObject)v, name));
    PetscCall(PetscViewerHDF5PushGroup(viewer, group));
    PetscCall(PetscViewerHDF5SetBaseDimension2(viewer, table));
    PetscCall(VecView(v, viewer));
    PetscCall(PetscViewerHDF5SetBaseDimension2(viewer, PETSC_FALSE));
    PetscCall(PetscViewerHDF5PopGroup(viewer));
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, path.c_str(), "units", PETSC_STRING, units));
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, path.c_str(), "description", PETSC_STRING, description));
  }
  PetscCall(VecDestroy(&v));
  PetscFunctionReturn(0);
}

// A DMDA field (natural ordering, shape (Nz,) Ny, Nx[, dof]) under /fields.
PetscErrorCode WriteField(PetscViewer viewer, Vec v, const char *name, const char *units, const char *description)
{
  PetscFunctionBeginUser;
  const std::string path = std::string("/fields/") + name;
  PetscCall(PetscObjectSetName((PetscObject)v, name));
  PetscCall(PetscViewerHDF5PushGroup(viewer, "/fields"));
  PetscCall(VecView(v, viewer));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, path.c_str(), "units", PETSC_STRING, units));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, path.c_str(), "description", PETSC_STRING, description));
  PetscFunctionReturn(0);
}

struct FieldSpec {
  const char *name, *units, *description;
  int         components; // 1 or dim
  // the value(s) of a cell from its means
  double (*value)(const CellGrid &, double rho_p, const CellMeans &, int component);
};

const FieldSpec kFields[] = {
  {"solid_fraction", "1", "time-averaged solid volume fraction <eps_s> (eq. 5.2)", 1,
   [](const CellGrid &, double, const CellMeans &m, int) { return m.solid_fraction; }},
  {"void_fraction", "1", "time-averaged void fraction 1 - <eps_s> (eq. 5.3)", 1,
   [](const CellGrid &, double, const CellMeans &m, int) { return 1.0 - m.solid_fraction; }},
  {"velocity", "m/s", "particle velocity over the window, sum v_p / sum N (eq. 4.3); 0 where no particle came", 0,
   [](const CellGrid &, double, const CellMeans &m, int c) { return kernels::component(m.velocity, c); }},
  {"granular_temperature", "m^2/s^2", "mean granular temperature (eq. 3.4) over the samples where it was defined", 1,
   [](const CellGrid &, double, const CellMeans &m, int) { return m.granular_temperature; }},
  {"temperature_coverage", "1", "fraction of the samples in which the granular temperature was defined", 1,
   [](const CellGrid &, double, const CellMeans &m, int) { return m.temperature_coverage; }},
  {"solid_flux", "m/s", "mean solid volume flux <eps_s v>; times the particle density, the solid mass flux", 0,
   [](const CellGrid &, double, const CellMeans &m, int c) { return kernels::component(m.solid_flux, c); }},
  {"convective_power", "W", "cell term of the convective power, sum_i |mdot_i| v_i^2 (eq. 3.8)", 1,
   [](const CellGrid &g, double rho, const CellMeans &m, int) { return kernels::cell_convective_power(g, rho, m); }},
  {"diffusive_power", "W", "cell term of the diffusive power, |mdot| theta (eq. 3.9)", 1,
   [](const CellGrid &g, double rho, const CellMeans &m, int) { return kernels::cell_diffusive_power(g, rho, m); }},
};

// The whole-bed measures, the profiles and the jet statistics from the gathered averages (rank 0).
struct Gathered {
  std::vector<double> heights, layer_heights, x, sf, vy, theta, flux_x, mass_flow; // horizontal profiles, nh x nx
  std::vector<double> cs_height, cs_sf, cs_flux_y, cs_theta;                       // cross-section profiles, ny
  std::vector<double> jet_mean, jet_std, jet_count;                                // per jet
  std::vector<double> measures_row;
};

PetscErrorCode Measure(BedAverages *a, const RunView &run, Gathered *out)
{
  Vec                nat, zero;
  VecScatter         sc;
  const PetscScalar *z;
  PetscMPIInt        rank;
  const double       rho = run.props.density;
  const CellGrid    &g   = a->grid;
  BedMeasures        r;

  Gathered local;

  PetscFunctionBeginUser;
  if (!out) out = &local;
  PetscCallMPI(MPI_Comm_rank(a->comm, &rank));
  PetscCall(DMDACreateNaturalVector(a->da_acc, &nat));
  PetscCall(DMDAGlobalToNaturalBegin(a->da_acc, a->acc, INSERT_VALUES, nat));
  PetscCall(DMDAGlobalToNaturalEnd(a->da_acc, a->acc, INSERT_VALUES, nat));
  PetscCall(VecScatterCreateToZero(nat, &sc, &zero));
  PetscCall(VecScatterBegin(sc, nat, zero, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(sc, nat, zero, INSERT_VALUES, SCATTER_FORWARD));
  if (!rank) {
    PetscCall(VecGetArrayRead(zero, &z));
    const CellAverageSums *acc = reinterpret_cast<const CellAverageSums *>(z);
    std::vector<CellMeans> m((std::size_t)kernels::cell_count(g));
    for (std::size_t c = 0; c < m.size(); ++c) m[c] = kernels::cell_means(acc[c], a->weight);
    PetscCall(VecRestoreArrayRead(zero, &z));
    auto         sf  = [&](long c) { return m[c].solid_fraction; };
    auto         vy  = [&](long c) { return m[c].velocity.y; };
    auto         th  = [&](long c) { return m[c].granular_temperature; };
    auto         fx  = [&](long c) { return m[c].solid_flux.x; };
    auto         fy  = [&](long c) { return m[c].solid_flux.y; };
    const double A_d = kernels::cross_section_area(g);

    out->cs_sf     = kernels::cross_section_profile(g, sf);
    out->cs_flux_y = kernels::cross_section_profile(g, fy);
    out->cs_theta  = kernels::cross_section_profile(g, th);
    for (int j = 0; j < g.n[1]; ++j) out->cs_height.push_back(kernels::layer_centre_height(g, j));
    for (int i = 0; i < g.n[0]; ++i) out->x.push_back(kernels::cell_centre(g, 0, i));
    for (PetscReal h : a->heights) {
      auto append = [](std::vector<double> &to, const std::vector<double> &p) { to.insert(to.end(), p.begin(), p.end()); };
      out->heights.push_back(h);
      out->layer_heights.push_back(kernels::layer_centre_height(g, kernels::layer_of_height(g, h)));
      append(out->sf, kernels::horizontal_profile(g, h, sf));
      append(out->vy, kernels::horizontal_profile(g, h, vy));
      append(out->theta, kernels::horizontal_profile(g, h, th));
      append(out->flux_x, kernels::horizontal_profile(g, h, fx));
      append(out->mass_flow, kernels::horizontal_mass_flow_profile(g, m.data(), rho, h));
    }

    r.samples              = (double)a->samples;
    r.window_start         = a->rows() ? a->series[SERIES_TIME] : 0.0;
    r.window_end           = a->rows() ? a->series[(std::size_t)(a->rows() - 1) * a->columns() + SERIES_TIME] : 0.0;
    r.height_cutoff        = kernels::cutoff_bed_height(g, out->cs_sf, a->cutoff);
    r.height_volume        = kernels::expanded_volume_bed_height(g, m.data(), a->occupied);
    r.bed_mass             = kernels::solid_mass(g, m.data(), rho);
    r.bulk_fraction        = r.height_volume > 0 ? kernels::bulk_solid_fraction(r.bed_mass, rho, r.height_volume, A_d) : 0.0;
    r.bulk_fraction_cutoff = r.height_cutoff > 0 ? kernels::bulk_solid_fraction(r.bed_mass, rho, r.height_cutoff, A_d) : 0.0;
    const kernels::CounterCurrentCirculation cc =
      kernels::counter_current_circulation(kernels::downflow_sums(g, m.data(), a->occupied), rho, r.bulk_fraction, A_d);
    r.circulation      = cc.mass_flow;
    r.fraction_down    = cc.fraction_moving_down;
    r.speed_down       = cc.mean_downward_speed;
    r.convective_power = kernels::convective_power(g, rho, m.data());
    r.diffusive_power  = kernels::diffusive_power(g, rho, m.data());

    // jets: the mean of the per-jet means over the jets that shed bubbles (seed ch. 4 averages its jets)
    double sum_mean = 0, sum_std = 0;
    for (std::size_t q = 0; q < a->jets.size(); ++q) {
      std::vector<double> hs; // the samples with a value, in time order
      for (PetscInt k = 0; k < a->rows(); ++k) {
        const double h = a->series[(std::size_t)(k * a->columns() + SERIES_JET0) + q];
        if (std::isfinite(h)) hs.push_back(h);
      }
      const kernels::JetHeightSeries js = kernels::jet_height_series(hs, a->crit);
      out->jet_mean.push_back(js.mean_height);
      out->jet_std.push_back(js.std_dev);
      out->jet_count.push_back((double)js.detachments.size());
      r.jet_detachments += (double)js.detachments.size();
      if (!js.detachments.empty()) {
        r.jets_detaching += 1;
        sum_mean += js.mean_height;
        sum_std += js.std_dev;
      }
    }
    if (r.jets_detaching > 0) {
      r.jet_height     = sum_mean / r.jets_detaching;
      r.jet_height_std = sum_std / r.jets_detaching;
    }
    if (run.fluid) {
      double s = 0, n = 0;
      for (PetscInt k = 0; k < a->rows(); ++k) {
        const double dp = a->series[(std::size_t)(k * a->columns() + SERIES_DP)];
        if (std::isfinite(dp)) s += dp, n += 1;
      }
      r.pressure_drop = n > 0 ? s / n : 0.0;
    }
  }
  PetscCall(VecScatterDestroy(&sc));
  PetscCall(VecDestroy(&zero));
  PetscCall(VecDestroy(&nat));
  PetscCallMPI(MPI_Bcast(&r, kMeasures, MPI_DOUBLE, 0, a->comm));
  a->measures = r;
  a->measured = PETSC_TRUE;
  PetscFunctionReturn(0);
}

// The per-cell fields of the owned block into a DMDA vector (dof 1 or dim) from the window's sums.
PetscErrorCode FillField(BedAverages *a, const RunView &run, const FieldSpec &f, Vec v)
{
  const PetscScalar *acc;
  PetscScalar       *out;
  const int          comps = f.components ? f.components : (int)a->dim;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(a->acc, &acc));
  PetscCall(VecGetArray(v, &out));
  const CellAverageSums *ca = reinterpret_cast<const CellAverageSums *>(acc);
  for (long c = 0; c < kernels::cell_count(a->owned); ++c) {
    const CellMeans m = kernels::cell_means(ca[c], a->weight);
    for (int k = 0; k < comps; ++k) out[comps * c + k] = f.value(a->grid, run.props.density, m, k);
  }
  PetscCall(VecRestoreArray(v, &out));
  PetscCall(VecRestoreArrayRead(a->acc, &acc));
  PetscFunctionReturn(0);
}

// The contents of analysis.h5; out: the fields for analysis.xmf.
PetscErrorCode WriteAnalysis(BedAverages *a, const RunView &run, const Gathered &g, PetscViewer viewer, std::vector<XdmfCellField> *out)
{
  Vec         scalar, vector;
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(a->comm, &rank));
  std::vector<XdmfCellField> &xdmf = *out;

  // time-averaged fields on the particle grid
  PetscCall(DMGetGlobalVector(a->da_scalar, &scalar));
  PetscCall(DMGetGlobalVector(a->da_vector, &vector));
  for (const FieldSpec &f : kFields) {
    Vec v = f.components == 1 ? scalar : vector;
    PetscCall(FillField(a, run, f, v));
    PetscCall(WriteField(viewer, v, f.name, f.units, f.description));
    xdmf.push_back({f.name, std::string("/fields/") + f.name, f.components == 1 ? 1 : (int)a->dim});
  }
  PetscCall(PetscObjectSetName((PetscObject)scalar, ""));
  PetscCall(PetscObjectSetName((PetscObject)vector, ""));
  PetscCall(DMRestoreGlobalVector(a->da_vector, &vector));
  PetscCall(DMRestoreGlobalVector(a->da_scalar, &scalar));

  // the grid
  const PetscInt n0 = rank ? 0 : 1;
  {
    const ParticleGrid &pg        = run.grids.particle;
    const double        origin[3] = {a->grid.lo[0], a->grid.lo[1], a->grid.lo[2]}, spacing[3] = {a->grid.h[0], a->grid.h[1], a->grid.h[2]};
    const double        cells[3] = {(double)pg.n[0], (double)pg.n[1], (double)(a->dim == 3 ? pg.n[2] : 1)};
    PetscCall(WriteArray(viewer, a->comm, "/grid", "origin", 1, 3 * n0, origin, "m", "lower corner of the particle grid x,y,z"));
    PetscCall(WriteArray(viewer, a->comm, "/grid", "spacing", 1, 3 * n0, spacing, "m",
                         "cell size x,y,z of the particle grid (in 2D z is the bed depth)"));
    PetscCall(WriteArray(viewer, a->comm, "/grid", "cells", 1, 3 * n0, cells, "1", "cells along x,y,z (in 2D one layer along z)"));
  }

  // profiles
  const PetscInt nx = a->grid.n[0], ny = a->grid.n[1], nh = (PetscInt)a->heights.size();
  PetscCall(
    WriteArray(viewer, a->comm, "/profiles", "heights", 1, n0 * nh, g.heights.data(), "m", "requested heights above the distributor"));
  PetscCall(WriteArray(viewer, a->comm, "/profiles", "layer_heights", 1, n0 * nh, g.layer_heights.data(), "m",
                       "centre height of the particle-grid layer holding each requested height (the profile's layer)"));
  if (nh) PetscCall(WriteArray(viewer, a->comm, "/profiles", "x", 1, n0 * nx, g.x.data(), "m", "x of the cell centres"));
  PetscCall(WriteArray(viewer, a->comm, "/profiles", "solid_fraction", nx, n0 * nh * nx, g.sf.data(), "1",
                       "time-averaged solid fraction per height (rows) and column (mean over z)", PETSC_TRUE));
  PetscCall(WriteArray(viewer, a->comm, "/profiles", "velocity_y", nx, n0 * nh * nx, g.vy.data(), "m/s",
                       "vertical particle velocity (eq. 4.3 over the window) per height and column (mean over z)", PETSC_TRUE));
  PetscCall(WriteArray(viewer, a->comm, "/profiles", "granular_temperature", nx, n0 * nh * nx, g.theta.data(), "m^2/s^2",
                       "granular temperature (eq. 3.4) per height and column (mean over z)", PETSC_TRUE));
  PetscCall(WriteArray(viewer, a->comm, "/profiles", "solid_flux_x", nx, n0 * nh * nx, g.flux_x.data(), "m/s",
                       "horizontal solid volume flux <eps_s v_x> per height and column (mean over z)", PETSC_TRUE));
  PetscCall(WriteArray(viewer, a->comm, "/profiles", "mass_flow_x", nx, n0 * nh * nx, g.mass_flow.data(), "kg/s",
                       "horizontal solid mass flow rho_p eps_s A_x v_x (eq. 3.5) per height and column, summed over the depth",
                       PETSC_TRUE));
  PetscCall(WriteArray(viewer, a->comm, "/cross_section", "height", 1, n0 * ny, g.cs_height.data(), "m",
                       "centre height of each particle-grid layer above the distributor"));
  PetscCall(WriteArray(viewer, a->comm, "/cross_section", "solid_fraction", 1, n0 * ny, g.cs_sf.data(), "1",
                       "cross-section-averaged time-averaged solid fraction per layer"));
  PetscCall(WriteArray(viewer, a->comm, "/cross_section", "solid_flux_y", 1, n0 * ny, g.cs_flux_y.data(), "m/s",
                       "cross-section-averaged vertical solid volume flux <eps_s v_y> per layer"));
  PetscCall(WriteArray(viewer, a->comm, "/cross_section", "granular_temperature", 1, n0 * ny, g.cs_theta.data(), "m^2/s^2",
                       "cross-section-averaged granular temperature per layer"));

  // time series
  {
    const PetscInt      ns = rank ? 0 : a->rows(), nc = a->columns(), nj = (PetscInt)a->jets.size();
    std::vector<double> col[3], jets((std::size_t)(ns * nj)), slots;
    for (PetscInt k = 0; k < ns; ++k) {
      for (int c = 0; c < 3; ++c) col[c].push_back(a->series[(std::size_t)(k * nc + c)]);
      for (PetscInt q = 0; q < nj; ++q) jets[(std::size_t)(k * nj + q)] = a->series[(std::size_t)(k * nc + SERIES_JET0 + q)];
    }
    for (const auto &s : a->jets) slots.insert(slots.end(), {s[0], s[1]});
    PetscCall(WriteArray(viewer, a->comm, "/series", "time", 1, ns, col[SERIES_TIME].data(), "s", "simulated time of each sample"));
    PetscCall(WriteArray(viewer, a->comm, "/series", "cutoff_bed_height", 1, ns, col[SERIES_CUTOFF].data(), "m",
                         "instantaneous expanded bed height by the solid-fraction cut-off (-average_cutoff)"));
    if (run.fluid)
      PetscCall(WriteArray(viewer, a->comm, "/series", "pressure_drop", 1, ns, col[SERIES_DP].data(), "Pa",
                           "gas pressure drop between -average_pressure_heights (cross-section averages); NaN before the first gas step"));
    if (nj) {
      PetscCall(WriteArray(
        viewer, a->comm, "/series", "jet_height", nj, ns * nj, jets.data(), "m",
        "height of each jet's high-voidage region connected to its inlet (rows: samples, columns: jets); NaN before the first gas step",
        PETSC_TRUE));
      PetscCall(WriteArray(viewer, a->comm, "/jets", "slots", 2, rank ? 0 : 2 * nj, slots.data(), "m", "x range of each inlet slit"));
      PetscCall(WriteArray(viewer, a->comm, "/jets", "penetration_height", 1, rank ? 0 : nj, g.jet_mean.data(), "m",
                           "mean height before bubble detachment per jet (0: none detached)"));
      PetscCall(WriteArray(viewer, a->comm, "/jets", "penetration_height_std", 1, rank ? 0 : nj, g.jet_std.data(), "m",
                           "standard deviation of the heights before detachment per jet"));
      PetscCall(WriteArray(viewer, a->comm, "/jets", "detachments", 1, rank ? 0 : nj, g.jet_count.data(), "1",
                           "bubble detachments counted per jet"));
    }
  }

  // whole-bed measures
  {
    const BedMeasures &r = a->measures;
    struct Scalar {
      const char *name;
      double      value;
      const char *units, *description;
      bool        write;
    } scalars[] = {
      {"samples", r.samples, "1", "samples in the window", true},
      {"window_start", r.window_start, "s", "time of the first sample", true},
      {"window_end", r.window_end, "s", "time of the last sample", true},
      {"expanded_bed_height_cutoff", r.height_cutoff, "m", "expanded bed height by the cut-off of the cross-section solid fraction", true},
      {"expanded_bed_height_volume", r.height_volume, "m", "expanded bed height: volume of the cells holding particles / cross-section",
       true},
      {"bed_mass", r.bed_mass, "kg", "time-averaged particle mass rho_p sum <eps_s> V_cell", true},
      {"bulk_solid_fraction", r.bulk_fraction, "1", "bulk solid fraction of the expanded bed (eq. 3.7) with the expanded-volume height",
       true},
      {"bulk_solid_fraction_cutoff", r.bulk_fraction_cutoff, "1", "bulk solid fraction (eq. 3.7) with the cut-off height", true},
      {"solid_circulation", r.circulation, "kg/s", "solid circulation rate by the counter-current model (eq. 3.6)", true},
      {"fraction_moving_down", r.fraction_down, "1", "f_neg of eq. 3.6: solid-volume fraction of the bed moving down", true},
      {"mean_downward_speed", r.speed_down, "m/s", "|v_neg,avg| of eq. 3.6", true},
      {"convective_power", r.convective_power, "W", "convective power P_c (eq. 3.8)", true},
      {"diffusive_power", r.diffusive_power, "W", "diffusive power P_d (eq. 3.9)", true},
      {"pressure_drop", r.pressure_drop, "Pa", "mean of the sampled pressure drop", run.fluid != nullptr},
      {"jet_penetration_height", r.jet_height, "m",
       "jet penetration height: mean over the jets that shed bubbles of their mean heights "
       "before detachment",
       !a->jets.empty()},
      {"jet_penetration_height_std", r.jet_height_std, "m", "mean over those jets of the standard deviation of the heights",
       !a->jets.empty()},
      {"jet_detachments", r.jet_detachments, "1", "bubble detachments counted over all jets", !a->jets.empty()},
    };
    for (const Scalar &s : scalars)
      if (s.write) PetscCall(WriteArray(viewer, a->comm, "/measures", s.name, 1, n0, &s.value, s.units, s.description));
  }
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "time", PETSC_REAL, &run.time));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode BedAverages::Write(const RunView &run)
{
  Gathered                   g;
  std::vector<XdmfCellField> xdmf;
  const double               t0 = MPI_Wtime();

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(ev_write, 0, 0, 0, 0));
  PetscCall(Measure(this, run, &g));
  const std::string dir = run.output_dir;
  PetscInt          n;
  PetscCall(VecGetSize(acc, &n)); // the sums the averaged fields are made of: about as much data
  PetscCall(WriteHDF5File(comm, dir + "/" + run_files::averages, (PetscInt64)n * (PetscInt64)sizeof(PetscScalar),
                          [&](PetscViewer viewer) { return WriteAnalysis(this, run, g, viewer, &xdmf); }));
  PetscCall(XdmfWriteFile(
    comm, dir + "/" + run_files::averages_xdmf,
    XdmfDocument(XdmfCellGrid("averages", dim, run.grids.particle.n, run.domain.lo, grid.h, run_files::averages, xdmf, nullptr), nullptr)));
  PetscCall(PetscLogEventEnd(ev_write, 0, 0, 0, 0));
  wall += MPI_Wtime() - t0;
  PetscFunctionReturn(0);
}

PetscErrorCode BedAverages::Finalize(const RunView &run)
{
  PetscFunctionBeginUser;
  PetscCall(Write(run));
  PetscFunctionReturn(0);
}

PetscErrorCode BedAveragesSchedule(const Output *averages, PetscReal *start, PetscReal *interval)
{
  const BedAverages *a = dynamic_cast<const BedAverages *>(averages);

  PetscFunctionBeginUser;
  PetscCheck(a || !averages, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "BedAveragesSchedule: output %s is not the averages", averages->Name());
  *start    = a ? a->start : 0;
  *interval = a ? a->interval : 0;
  PetscFunctionReturn(0);
}

PetscErrorCode BedAverages::AddSummary(const RunView &run, JsonWriter *json)
{
  JsonWriter in;

  PetscFunctionBeginUser;
  if (!measured) PetscCall(Measure(this, run, nullptr));
  const BedMeasures &r = measures;
  in.Integer("samples", (long long)samples);
  in.Number("window_start_s", r.window_start);
  in.Number("window_end_s", r.window_end);
  in.Number("interval_s", interval);
  in.Number("expanded_bed_height_cutoff_m", r.height_cutoff);
  in.Number("expanded_bed_height_volume_m", r.height_volume);
  in.Number("bed_mass_kg", r.bed_mass);
  in.Number("bulk_solid_fraction", r.bulk_fraction);
  in.Number("bulk_solid_fraction_cutoff", r.bulk_fraction_cutoff);
  in.Number("solid_circulation_kg_per_s", r.circulation);
  in.Number("fraction_moving_down", r.fraction_down);
  in.Number("mean_downward_speed_m_per_s", r.speed_down);
  in.Number("convective_power_W", r.convective_power);
  in.Number("diffusive_power_W", r.diffusive_power);
  if (run.fluid) in.Number("pressure_drop_mean_Pa", r.pressure_drop);
  if (!jets.empty()) {
    in.Number("jet_penetration_height_m", r.jet_height);
    in.Number("jet_penetration_height_std_m", r.jet_height_std);
    in.Integer("jet_detachments", (long long)r.jet_detachments);
  }
  in.Number("wall_time_s", wall);
  json->Object("averages", in);
  PetscFunctionReturn(0);
}

PetscErrorCode BedAverages::CheckpointWrite(const RunView &, PetscViewer viewer)
{
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(ev_checkpoint, 0, 0, 0, 0));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscViewerHDF5PushGroup(viewer, "/averages"));
  PetscCall(VecView(acc, viewer));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  const PetscReal count = (PetscReal)samples;
  const PetscInt  ncols = columns(), nrows = rows();
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/averages", "samples", PETSC_REAL, &count));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/averages", "weight", PETSC_REAL, &weight));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/averages", "next_sample", PETSC_REAL, &next));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/averages", "next_output", PETSC_REAL, &next_output));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/averages", "series_columns", PETSC_INT, &ncols));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/averages", "series_rows", PETSC_INT, &nrows));
  if (nrows) {
    Vec v;
    PetscCall(VecCreateMPIWithArray(comm, ncols, rank ? 0 : nrows * ncols, PETSC_DECIDE, series.data(), &v));
    PetscCall(PetscObjectSetName((PetscObject)v, "series"));
    PetscCall(PetscViewerHDF5PushGroup(viewer, "/averages"));
    PetscCall(VecView(v, viewer));
    PetscCall(PetscViewerHDF5PopGroup(viewer));
    PetscCall(VecDestroy(&v));
  }
  PetscCall(PetscLogEventEnd(ev_checkpoint, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

// A checkpoint without /averages starts the averages afresh.
PetscErrorCode BedAverages::CheckpointRead(const RunView &run, PetscViewer viewer)
{
  PetscBool   has;
  PetscMPIInt rank;
  PetscInt    ncols, nrows;
  PetscReal   count;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscViewerHDF5HasGroup(viewer, "/averages", &has));
  if (!has || reset) {
    // the checkpoint was written before averaging was on, or -average_reset: start now, after the checkpoint's time
    const PetscReal eps = 0.5 * run.dt;
    while (next <= run.time + eps) next += interval;
    next_output = next + output_interval;
    PetscCall(PetscPrintf(comm, "Averages: %s; the first sample is at t = %.6g s\n",
                          has ? "the checkpoint's are dropped (-average_reset)" : "the checkpoint holds none", (double)next));
    PetscFunctionReturn(0);
  }
  PetscCall(PetscLogEventBegin(ev_checkpoint, 0, 0, 0, 0));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/averages", "series_columns", PETSC_INT, NULL, &ncols));
  PetscCheck(ncols == columns(), comm, PETSC_ERR_USER_INPUT,
             "-restart %s: the checkpoint's averages follow %d jets, the options give %d (-inlet_jets must match)", run.restart,
             (int)(ncols - SERIES_JET0), (int)(columns() - SERIES_JET0));
  PetscCall(PetscViewerHDF5PushGroup(viewer, "/averages"));
  PetscCall(VecLoad(acc, viewer));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/averages", "samples", PETSC_REAL, NULL, &count));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/averages", "weight", PETSC_REAL, NULL, &weight));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/averages", "next_sample", PETSC_REAL, NULL, &next));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/averages", "next_output", PETSC_REAL, NULL, &next_output));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/averages", "series_rows", PETSC_INT, NULL, &nrows));
  samples = (PetscInt64)count;
  series.assign((std::size_t)(nrows * ncols), 0.0);
  if (nrows) {
    Vec                v;
    const PetscScalar *s;
    PetscCall(VecCreateMPI(comm, rank ? 0 : nrows * ncols, PETSC_DETERMINE, &v));
    PetscCall(VecSetBlockSize(v, ncols));
    PetscCall(PetscObjectSetName((PetscObject)v, "series"));
    PetscCall(PetscViewerHDF5PushGroup(viewer, "/averages"));
    PetscCall(VecLoad(v, viewer));
    PetscCall(PetscViewerHDF5PopGroup(viewer));
    if (!rank) {
      PetscCall(VecGetArrayRead(v, &s));
      for (std::size_t k = 0; k < series.size(); ++k) series[k] = s[k];
      PetscCall(VecRestoreArrayRead(v, &s));
    }
    PetscCall(VecDestroy(&v));
    PetscCallMPI(MPI_Bcast(series.data(), (int)series.size(), MPIU_REAL, 0, comm));
  }
  measured = PETSC_FALSE;
  PetscCall(PetscLogEventEnd(ev_checkpoint, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode BedAverages::Destroy()
{
  PetscFunctionBeginUser;
  PetscCall(VecScatterDestroy(&eps_scatter));
  for (Vec *v : {&eps_zero, &eps_nat, &acc, &sums, &sums_loc}) PetscCall(VecDestroy(v));
  for (DM *dm : {&da_vector, &da_scalar, &da_acc, &da_sums}) PetscCall(DMDestroy(dm));
  PetscFunctionReturn(0);
}

PetscErrorCode BedAveragesCreate(const RunView &run, std::unique_ptr<Output> *out)
{
  PetscBool on;

  PetscFunctionBeginUser;
  PetscCall(RegisterEvents());
  out->reset();
  std::unique_ptr<BedAverages> a = std::make_unique<BedAverages>();
  a->comm                        = run.comm;
  PetscCall(SetFromOptions(a.get(), run, &on));
  if (!on) PetscFunctionReturn(0);
  PetscCall(SetUp(a.get(), run));
  std::string hs;
  for (PetscReal h : a->heights) {
    char buf[32];
    PetscCall(PetscSNPrintf(buf, sizeof(buf), "%s%.4g", hs.empty() ? "" : ", ", 1e3 * (double)h));
    hs += buf;
  }
  PetscCall(PetscPrintf(a->comm,
                        "Averages: every %.6g s from t = %.6g s on the %d x %d x %d particle grid%s%s%s; %d jet(s)%s -> %s/analysis.h5\n",
                        (double)a->interval, (double)a->start, a->grid.n[0], a->grid.n[1], a->grid.n[2], hs.empty() ? "" : ", profiles at ",
                        hs.c_str(), hs.empty() ? "" : " mm", (int)a->jets.size(), run.fluid ? ", pressure drop" : "", run.output_dir));
  *out = std::move(a);
  PetscFunctionReturn(0);
}

} // namespace fluidbed
