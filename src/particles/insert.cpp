// Initial particles from options: every rank builds the same global list and keeps the particles of its own
// particle cells, so ids and positions do not depend on the number of ranks.
#include "fluidbed/particles.hpp"
#include "fluidbed/options.hpp"
#include "fluidbed/kernels/packing.hpp"

#include <petscviewerhdf5.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fluidbed {

namespace {

using kernels::Vec3;

constexpr std::size_t kMaxList = 1000; // -insert_type list is for a few particles (tests, demonstrations)

enum InsertType { INSERT_LATTICE, INSERT_RANDOM, INSERT_LIST, INSERT_FILE };
const char *const InsertTypes[] = {"lattice", "random", "list", "file", "InsertType", "INSERT_", NULL};

struct GlobalParticles {
  std::vector<Vec3>       x, v, w;
  std::vector<double>     d;
  std::vector<PetscInt64> id;
};

// Reads a CSV file with a header naming its columns (x, y, z, d or diameter, optional id, vx, vy, vz, wx, wy, wz),
// such as the particles.csv a run writes.
PetscErrorCode ReadParticleCSV(MPI_Comm comm, const char *path, GlobalParticles *g)
{
  std::ifstream in(path);
  std::string   line;

  PetscFunctionBeginUser;
  PetscCheck(in.good(), comm, PETSC_ERR_FILE_OPEN, "-insert_file: cannot open %s", path);
  PetscCheck((bool)std::getline(in, line), comm, PETSC_ERR_FILE_UNEXPECTED, "-insert_file %s is empty", path);
  std::map<std::string, int> col;
  {
    std::stringstream ss(line);
    std::string       name;
    for (int c = 0; std::getline(ss, name, ','); ++c) {
      while (!name.empty() && (name.back() == '\r' || name.back() == ' ')) name.pop_back();
      col[name] = c;
    }
  }
  if (!col.count("d") && col.count("diameter")) col["d"] = col["diameter"];
  for (const char *need : {"x", "y", "d"})
    PetscCheck(col.count(need), comm, PETSC_ERR_FILE_UNEXPECTED, "-insert_file %s has no column '%s'", path, need);
  auto get = [&](const std::vector<double> &row, const char *name) { return col.count(name) ? row[col[name]] : 0.0; };
  for (long lineno = 2; std::getline(in, line); ++lineno) {
    if (line.empty()) continue;
    std::vector<double> row;
    std::stringstream   ss(line);
    std::string         tok;
    while (std::getline(ss, tok, ',')) row.push_back(std::strtod(tok.c_str(), NULL));
    PetscCheck(row.size() >= col.size(), comm, PETSC_ERR_FILE_UNEXPECTED, "-insert_file %s line %ld has %d values, the header %d", path,
               lineno, (int)row.size(), (int)col.size());
    g->x.push_back({get(row, "x"), get(row, "y"), get(row, "z")});
    g->v.push_back({get(row, "vx"), get(row, "vy"), get(row, "vz")});
    g->w.push_back({get(row, "wx"), get(row, "wy"), get(row, "wz")});
    g->d.push_back(get(row, "d"));
    g->id.push_back(col.count("id") ? (PetscInt64)get(row, "id") : (PetscInt64)g->id.size());
  }
  PetscFunctionReturn(0);
}

// Reads the /particles group of a snapshot or checkpoint HDF5 file a run wrote (position, diameter, and where
// present id, velocity, omega): a run on another grid, time step or model can start from any saved moment of an
// earlier run. Every rank reads the whole file, as for a CSV file.
PetscErrorCode ReadParticleHDF5(MPI_Comm comm, const char *path, GlobalParticles *g)
{
  PetscViewer viewer;
  PetscBool   exists, has;
  PetscInt    n = -1;

  PetscFunctionBeginUser;
  PetscCall(PetscTestFile(path, 'r', &exists));
  PetscCheck(exists, comm, PETSC_ERR_FILE_OPEN, "-insert_file: cannot open %s", path);
  PetscCall(PetscViewerHDF5Open(PETSC_COMM_SELF, path, FILE_MODE_READ, &viewer));
  // a dataset of /particles: the numbers of columns it may have (positions one per dimension: 2D files hold x, y),
  // whether every file has it, where it goes
  struct Column {
    const char          *name;
    PetscInt             min_bs, max_bs;
    bool                 required;
    std::vector<double> *flat;
  };
  std::vector<double> pos, vel, omg, dia, ids;
  const Column        columns[] = {{"position", 2, 3, true, &pos},
                                   {"diameter", 1, 1, true, &dia},
                                   {"id", 1, 1, false, &ids},
                                   {"velocity", 3, 3, false, &vel},
                                   {"omega", 3, 3, false, &omg}};
  for (const Column &c : columns) {
    std::string name = std::string("/particles/") + c.name;
    PetscCall(PetscViewerHDF5HasDataset(viewer, name.c_str(), &has));
    PetscCheck(has || !c.required, comm, PETSC_ERR_FILE_UNEXPECTED,
               "-insert_file %s has no dataset %s (a fluidbed snapshot or checkpoint has)", path, name.c_str());
    if (!has) continue;
    Vec                v;
    const PetscScalar *a;
    PetscInt           N, bs;
    PetscCall(VecCreate(PETSC_COMM_SELF, &v));
    PetscCall(PetscObjectSetName((PetscObject)v, name.c_str()));
    PetscCall(VecLoad(v, viewer)); // the block size from the dataset's columns
    PetscCall(VecGetSize(v, &N));
    PetscCall(VecGetBlockSize(v, &bs));
    const std::string widths = std::to_string(c.min_bs) + (c.max_bs > c.min_bs ? " or " + std::to_string(c.max_bs) : "");
    PetscCheck(bs >= c.min_bs && bs <= c.max_bs, comm, PETSC_ERR_FILE_UNEXPECTED, "-insert_file %s: %s has %d columns, expected %s", path,
               name.c_str(), (int)bs, widths.c_str());
    PetscCheck(n < 0 || N / bs == n, comm, PETSC_ERR_FILE_UNEXPECTED, "-insert_file %s: %s has %d rows, position %d", path, name.c_str(),
               (int)(N / bs), (int)n);
    n = N / bs;
    PetscCall(VecGetArrayRead(v, &a));
    if (bs == 2) { // 2D positions: z = 0
      c.flat->assign(3 * n, 0.0);
      for (PetscInt i = 0; i < n; ++i)
        for (PetscInt k = 0; k < 2; ++k) (*c.flat)[3 * i + k] = a[2 * i + k];
    } else c.flat->assign(a, a + N);
    PetscCall(VecRestoreArrayRead(v, &a));
    PetscCall(VecDestroy(&v));
  }
  PetscCall(PetscViewerDestroy(&viewer));
  for (PetscInt i = 0; i < n; ++i) {
    g->x.push_back({pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]});
    g->v.push_back(vel.empty() ? Vec3{} : Vec3{vel[3 * i], vel[3 * i + 1], vel[3 * i + 2]});
    g->w.push_back(omg.empty() ? Vec3{} : Vec3{omg[3 * i], omg[3 * i + 1], omg[3 * i + 2]});
    g->d.push_back(dia[i]);
    g->id.push_back(ids.empty() ? (PetscInt64)i : (PetscInt64)std::llround(ids[i]));
  }
  PetscFunctionReturn(0);
}

// -insert_file: a fluidbed HDF5 snapshot or checkpoint (.h5) or a CSV file.
PetscErrorCode ReadParticleFile(MPI_Comm comm, const char *path, GlobalParticles *g)
{
  const std::string p(path);

  PetscFunctionBeginUser;
  if (p.size() > 3 && p.compare(p.size() - 3, 3, ".h5") == 0) PetscCall(ReadParticleHDF5(comm, path, g));
  else PetscCall(ReadParticleCSV(comm, path, g));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode ParticlesInitialPositions(MPI_Comm comm, std::vector<PetscReal> *xyz, PetscBool *known)
{
  PetscEnum type = (PetscEnum)INSERT_LATTICE;
  PetscBool set;
  char      file[PETSC_MAX_PATH_LEN] = "";

  PetscFunctionBeginUser;
  xyz->clear();
  *known = PETSC_FALSE;
  // read quietly: ParticlesInsert reads and reports these options
  PetscCall(PetscOptionsGetEnum(NULL, NULL, "-insert_type", InsertTypes, &type, &set));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-insert_file", file, sizeof(file), NULL));
  if ((InsertType)type != INSERT_FILE || !file[0]) PetscFunctionReturn(0);
  GlobalParticles g;
  PetscCall(ReadParticleFile(comm, file, &g));
  xyz->reserve(3 * g.x.size());
  for (const Vec3 &x : g.x) xyz->insert(xyz->end(), {x.x, x.y, x.z});
  *known = PETSC_TRUE;
  PetscFunctionReturn(0);
}

PetscErrorCode ParticlesInsert(MPI_Comm comm, const Domain &dom, const ParticleGrid &pg, const ParticleProps &props, DM sw,
                               InsertionReport *report)
{
  const int  dim  = (int)dom.dim;
  InsertType type = INSERT_LATTICE;
  // Defaults (no scene options): 4000 particles on a loose jittered lattice.
  PetscInt               count = 4000, seed = 1;
  PetscReal              bed_height = 0.0, packing = 0.6, spacing = 1.05, jitter = 0.5, vel_random = 0.0;
  PetscReal              region[6]   = {dom.lo[0], dom.hi[0], dom.lo[1], dom.hi[1], dom.lo[2], dom.hi[2]};
  PetscReal              velocity[3] = {0, 0, 0};
  PetscInt               nregion = 2 * dim, nvel = 3;
  PetscBool              set_count = PETSC_FALSE, set_height = PETSC_FALSE;
  char                   file[PETSC_MAX_PATH_LEN] = "";
  GlobalParticles        g;
  std::vector<PetscReal> lpos(3 * kMaxList), lvel(3 * kMaxList), lomg(3 * kMaxList), ldiam(kMaxList);
  PetscInt  npos = (PetscInt)lpos.size(), nlvel = (PetscInt)lvel.size(), nlomg = (PetscInt)lomg.size(), nldiam = (PetscInt)ldiam.size();
  PetscBool set_lpos = PETSC_FALSE, set_lvel = PETSC_FALSE, set_lomg = PETSC_FALSE, set_ldiam = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, "insert_", "Initial particles", "Insertion");
  PetscCall(OptionsEnum(PetscOptionsObject, "-type",
                        "How particles are placed: lattice, random (non-overlapping), list (-insert_positions) or file (-insert_file)",
                        InsertTypes, (PetscEnum *)&type, NULL));
  PetscCall(OptionsInt(PetscOptionsObject, "-count", "Number of particles (lattice, random)", 0, PETSC_MAX_INT, &count, &set_count));
  PetscCall(OptionsReal(PetscOptionsObject, "-bed_height",
                        "Settled bed height that sets the particle count with -insert_packing (instead of -insert_count)", "m",
                        NonNegative(100.0), &bed_height, &set_height));
  PetscCall(OptionsReal(PetscOptionsObject, "-packing", "Solid fraction of the settled bed used with -insert_bed_height", "",
                        Closed(0.05, 0.74), &packing, NULL));
  PetscCall(OptionsRealArray(PetscOptionsObject, "-region", "Insertion box xmin,xmax,ymin,ymax[,zmin,zmax] (default: the domain)", "m",
                             Closed(-100.0, 100.0), region, &nregion, PETSC_TRUE, NULL));
  PetscCall(
    OptionsInt(PetscOptionsObject, "-seed", "Seed of the random jitter, fill and size distribution", 0, PETSC_MAX_INT, &seed, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-spacing", "Lattice spacing in largest diameters", "d", Closed(1.0, 100.0), &spacing, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-jitter", "Random lattice displacement as a fraction of the gap", "", Closed(0.0, 0.999),
                        &jitter, NULL));
  PetscCall(OptionsRealArray(PetscOptionsObject, "-velocity", "Initial velocity of every particle vx,vy,vz", "m/s", Closed(-1e3, 1e3),
                             velocity, &nvel, PETSC_TRUE, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-velocity_random", "Amplitude of a random initial velocity added per component", "m/s",
                        Closed(0.0, 1e3), &vel_random, NULL));
  PetscCall(OptionsRealArray(PetscOptionsObject, "-positions", "list: particle centres x,y,z,x,y,z,...", "m", AnyReal(), lpos.data(), &npos,
                             PETSC_FALSE, &set_lpos));
  PetscCall(OptionsRealArray(PetscOptionsObject, "-velocities", "list: velocities vx,vy,vz,...", "m/s", AnyReal(), lvel.data(), &nlvel,
                             PETSC_FALSE, &set_lvel));
  PetscCall(OptionsRealArray(PetscOptionsObject, "-omegas", "list: angular velocities wx,wy,wz,...", "rad/s", AnyReal(), lomg.data(),
                             &nlomg, PETSC_FALSE, &set_lomg));
  PetscCall(OptionsRealArray(PetscOptionsObject, "-diameters", "list: diameters [m] (default -particle_diameter)", "", AnyReal(),
                             ldiam.data(), &nldiam, PETSC_FALSE, &set_ldiam));
  PetscCall(OptionsString(
    PetscOptionsObject, "-file",
    "file: CSV with columns x,y,z,d[,id,vx,vy,vz,wx,wy,wz] (a run's particles.csv), or a run's snapshot or checkpoint .h5 (its /particles)",
    "a CSV file", file, sizeof(file), NULL));
  PetscOptionsEnd();
  if (!set_lpos) npos = 0; // not given: no list

  for (int a = 0; a < dim; ++a) {
    PetscCheck(region[2 * a] < region[2 * a + 1], comm, PETSC_ERR_ARG_OUTOFRANGE, "-insert_region: min %.6g >= max %.6g along %c",
               (double)region[2 * a], (double)region[2 * a + 1], "xyz"[a]);
    PetscCheck(region[2 * a] >= dom.lo[a] - 1e-12 && region[2 * a + 1] <= dom.hi[a] + 1e-12, comm, PETSC_ERR_ARG_OUTOFRANGE,
               "-insert_region [%.6g, %.6g] m along %c is outside the box: allowed within [%.6g, %.6g] m (-domain_l%c)",
               (double)region[2 * a], (double)region[2 * a + 1], "xyz"[a], (double)dom.lo[a], (double)dom.hi[a], "xyz"[a]);
  }
  if (dim == 2) {
    region[4] = dom.lo[2];
    region[5] = dom.hi[2];
  }
  const kernels::Box box{{region[0], region[2], region[4]}, {region[1], region[3], region[5]}};
  std::mt19937_64    rng((std::uint64_t)seed);

  if (type == INSERT_LATTICE || type == INSERT_RANDOM) {
    PetscCheck(!(set_count && set_height), comm, PETSC_ERR_USER_INPUT, "give either -insert_count or -insert_bed_height, not both");
    if (set_height) {
      // a settled bed taller than the region (by default the box) cannot be placed, however loosely
      const PetscReal room = box.hi.y - box.lo.y;
      PetscCheck(bed_height <= room, comm, PETSC_ERR_ARG_OUTOFRANGE,
                 "-insert_bed_height %.6g m is taller than the %s (%.6g m): allowed at most %.6g m", (double)bed_height,
                 room < dom.len[1] ? "insertion region -insert_region" : "box -domain_ly", (double)room, (double)room);
      const PetscReal d3    = props.d_max > props.d_min
                                ? (PetscPowReal(props.d_max, 4) - PetscPowReal(props.d_min, 4)) / (4.0 * (props.d_max - props.d_min))
                                : PetscPowReal(props.d_min, 3);
      const PetscReal vmean = PETSC_PI / 6.0 * d3;
      const PetscReal area  = (box.hi.x - box.lo.x) * (dim == 3 ? box.hi.z - box.lo.z : dom.len[2]);
      count                 = (PetscInt)PetscFloorReal(packing * area * bed_height / vmean + 0.5);
    }
    g.d = kernels::draw_diameters((std::size_t)count, props.d_min, props.d_max, rng);
    try {
      if (type == INSERT_LATTICE) g.x = kernels::lattice_fill(box, dim, count, props.d_max, spacing * props.d_max, jitter, rng);
      else g.x = kernels::random_fill(box, dim, g.d, 1e-3 * props.d_min, rng);
    } catch (const std::exception &e) {
      // the bed height sets the count at -insert_packing, while the particles start on a looser lattice or fill
      PetscCheck(!set_height, comm, PETSC_ERR_USER_INPUT,
                 "-insert_bed_height %.6g m (%lld particles at -insert_packing %.6g) does not fit: -insert_type %s: %s; lower "
                 "-insert_bed_height, or enlarge -insert_region or the box",
                 (double)bed_height, (long long)count, (double)packing, InsertTypes[type], e.what());
      SETERRQ(comm, PETSC_ERR_USER_INPUT, "-insert_type %s: %s; enlarge -insert_region or reduce the count", InsertTypes[type], e.what());
    }
  } else if (type == INSERT_LIST) {
    PetscCheck(npos % 3 == 0 && npos > 0, comm, PETSC_ERR_USER_INPUT, "-insert_positions needs x,y,z triples, got %d values", (int)npos);
    const PetscInt n = npos / 3;
    PetscCheck(!set_lvel || nlvel == 3 * n, comm, PETSC_ERR_USER_INPUT, "-insert_velocities needs %d values (3 per particle), got %d",
               (int)(3 * n), (int)nlvel);
    PetscCheck(!set_lomg || nlomg == 3 * n, comm, PETSC_ERR_USER_INPUT, "-insert_omegas needs %d values (3 per particle), got %d",
               (int)(3 * n), (int)nlomg);
    PetscCheck(!set_ldiam || nldiam == n, comm, PETSC_ERR_USER_INPUT, "-insert_diameters needs %d values, got %d", (int)n, (int)nldiam);
    for (PetscInt i = 0; i < n; ++i) {
      g.x.push_back({lpos[3 * i], lpos[3 * i + 1], lpos[3 * i + 2]});
      g.d.push_back(set_ldiam ? ldiam[i] : props.d_min);
      if (set_lvel) g.v.push_back({lvel[3 * i], lvel[3 * i + 1], lvel[3 * i + 2]});
      if (set_lomg) g.w.push_back({lomg[3 * i], lomg[3 * i + 1], lomg[3 * i + 2]});
    }
  } else {
    PetscCheck(file[0], comm, PETSC_ERR_USER_INPUT, "-insert_type file needs -insert_file");
    PetscCall(ReadParticleFile(comm, file, &g));
    report->file = file;
  }

  const std::size_t N = g.x.size();
  if (g.id.size() != N) {
    g.id.resize(N);
    for (std::size_t i = 0; i < N; ++i) g.id[i] = (PetscInt64)i;
  }
  g.v.resize(N, Vec3{velocity[0], velocity[1], velocity[2]});
  g.w.resize(N, Vec3{});
  if (vel_random > 0.0)
    for (auto &vi : g.v) {
      vi.x += vel_random * (2.0 * kernels::uniform01(rng) - 1.0);
      vi.y += vel_random * (2.0 * kernels::uniform01(rng) - 1.0);
      vi.z += vel_random * (2.0 * kernels::uniform01(rng) - 1.0);
    }

  // Validate: diameters within the props' range, every sphere inside the box and clear of the walls.
  PetscReal solid = 0.0;
  for (std::size_t i = 0; i < N; ++i) {
    if (dim == 2) {
      g.x[i].z = 0.0;
      g.v[i].z = 0.0;
      g.w[i].x = g.w[i].y = 0.0;
    }
    // a resting contact overlaps a wall: a settled bed's floor particles (a -insert_file from a settling run) overlap it by
    // up to 1.2% of d in the 2D 750 um bed; allow 5%
    const PetscReal r = 0.45 * g.d[i];
    PetscCheck(g.d[i] > 0.0 && g.d[i] <= props.d_max * (1 + 1e-12), comm, PETSC_ERR_ARG_OUTOFRANGE,
               "particle %lld has diameter %.6g m outside (0, %.6g] (set -particle_diameter_max for larger particles)", (long long)g.id[i],
               (double)g.d[i], (double)props.d_max);
    const PetscReal c[3] = {g.x[i].x, g.x[i].y, g.x[i].z};
    for (int a = 0; a < dim; ++a) {
      const bool wall_lo = dom.IsParticleWall(2 * a), wall_hi = dom.IsParticleWall(2 * a + 1);
      PetscCheck(c[a] - (wall_lo ? r : 0.0) >= dom.lo[a] && c[a] + (wall_hi ? r : 0.0) <= dom.hi[a] && c[a] < dom.hi[a], comm,
                 PETSC_ERR_ARG_OUTOFRANGE,
                 "particle %lld at (%.6g, %.6g, %.6g) m with diameter %.6g m lies outside the box [%.6g, %.6g] along axis %d or overlaps "
                 "its wall by more than 5%% of d",
                 (long long)g.id[i], (double)c[0], (double)c[1], (double)c[2], (double)g.d[i], (double)dom.lo[a], (double)dom.hi[a], a);
    }
    solid += PETSC_PI / 6.0 * g.d[i] * g.d[i] * g.d[i];
  }

  // Keep the particles whose particle cell this rank owns.
  std::vector<std::size_t> mine;
  for (std::size_t i = 0; i < N; ++i) {
    const PetscReal c[3] = {g.x[i].x, g.x[i].y, g.x[i].z};
    bool            own  = true;
    for (int a = 0; a < dim; ++a) {
      PetscInt cell = (PetscInt)PetscFloorReal((c[a] - dom.lo[a]) / pg.h[a]);
      cell          = PetscMin(PetscMax(cell, 0), pg.n[a] - 1);
      own           = own && cell >= pg.cell_lo[a] && cell < pg.cell_hi[a];
    }
    if (own) mine.push_back(i);
  }
  PetscCall(DMSwarmSetLocalSizes(sw, (PetscInt)mine.size(), 1024));
  ParticleArrays p;
  PetscCall(ParticleArraysGet(sw, &p));
  for (PetscInt k = 0; k < p.n; ++k) {
    const std::size_t i    = mine[(std::size_t)k];
    const PetscReal   c[3] = {g.x[i].x, g.x[i].y, g.x[i].z};
    for (int a = 0; a < dim; ++a) p.x[dim * k + a] = c[a];
    p.v[3 * k + 0] = g.v[i].x;
    p.v[3 * k + 1] = g.v[i].y;
    p.v[3 * k + 2] = g.v[i].z;
    p.w[3 * k + 0] = g.w[i].x;
    p.w[3 * k + 1] = g.w[i].y;
    p.w[3 * k + 2] = g.w[i].z;
    for (int c3 = 0; c3 < 3; ++c3) p.f[3 * k + c3] = p.t[3 * k + c3] = p.dref[3 * k + c3] = 0.0;
    p.dcoef[k] = 0.0;
    p.dcell[k] = 0;
    p.d[k]     = g.d[i];
    p.id[k]    = g.id[i];
    for (PetscInt s = 0; s < p.K; ++s) {
      p.ckey[p.K * k + s] = kFreeSlot;
      for (PetscInt c = 0; c < p.hs; ++c) p.chist[p.hs * (p.K * k + s) + c] = 0.0;
    }
  }
  PetscCall(ParticleArraysRestore(sw, &p));

  const PetscReal vol           = (box.hi.x - box.lo.x) * (box.hi.y - box.lo.y) * (box.hi.z - box.lo.z);
  report->count                 = (PetscInt64)N;
  report->solid_fraction_region = solid / vol;
  PetscFunctionReturn(0);
}

} // namespace fluidbed
