#include "fluidbed/io.hpp"
#include "fluidbed/fluid.hpp"

#include <algorithm>
#include <cstdio>
#include <numeric>

namespace fluidbed {

PetscErrorCode WriteParticlesCSV(DM sw, const char *path)
{
  constexpr int          kCols = 14; // id, d, x(3), v(3), w(3), f(3)
  MPI_Comm               comm  = PetscObjectComm((PetscObject)sw);
  PetscMPIInt            rank, size;
  ParticleArrays         p;
  std::vector<PetscReal> rows;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(ParticleArraysGet(sw, &p));
  rows.assign((std::size_t)p.n * kCols, 0.0);
  for (PetscInt i = 0; i < p.n; ++i) {
    PetscReal *r = &rows[(std::size_t)i * kCols];
    r[0]         = (PetscReal)p.id[i]; // exact below 2^53
    r[1]         = p.d[i];
    for (PetscInt a = 0; a < p.dim; ++a) r[2 + a] = p.x[p.dim * i + a];
    for (int a = 0; a < 3; ++a) {
      r[5 + a]  = p.v[3 * i + a];
      r[8 + a]  = p.w[3 * i + a];
      r[11 + a] = p.f[3 * i + a];
    }
  }
  PetscCall(ParticleArraysRestore(sw, &p));

  int              nloc = (int)rows.size();
  std::vector<int> counts(size), displs(size, 0);
  PetscCallMPI(MPI_Gather(&nloc, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm));
  std::vector<PetscReal> all;
  if (!rank) {
    for (int r = 1; r < size; ++r) displs[r] = displs[r - 1] + counts[r - 1];
    all.resize((std::size_t)(displs[size - 1] + counts[size - 1]));
  }
  PetscCallMPI(MPI_Gatherv(rows.data(), nloc, MPIU_REAL, all.data(), counts.data(), displs.data(), MPIU_REAL, 0, comm));
  OutputFile out;
  PetscCall(OutputFileOpen(comm, path, OutputFile::REPLACE, &out));
  if (!rank) {
    const std::size_t        n = all.size() / kCols;
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return all[a * kCols] < all[b * kCols]; });
    OutputFilePrintf(&out, "id,d,x,y,z,vx,vy,vz,wx,wy,wz,fx,fy,fz\n");
    for (std::size_t k : order) {
      const PetscReal *r = &all[k * kCols];
      OutputFilePrintf(&out, "%lld", (long long)r[0]);
      for (int c = 1; c < kCols; ++c) OutputFilePrintf(&out, ",%.17g", (double)r[c]);
      OutputFilePrintf(&out, "\n");
    }
  }
  PetscCall(OutputFileClose(comm, &out));
  PetscFunctionReturn(0);
}

namespace {

// particles.csv and fluid_cells.csv, the state a run that no guard stopped ends with.
class FinalTables final : public Output {
public:
  explicit FinalTables(PetscBool particles) : particles_(particles) {}
  const char *Name() const override { return "tables"; }

  PetscErrorCode Finalize(const RunView &run) override
  {
    const std::string dir = run.output_dir;

    PetscFunctionBeginUser;
    if (run.swarm && particles_) PetscCall(WriteParticlesCSV(run.swarm, (dir + "/" + run_files::particles).c_str()));
    if (run.fluid && FluidWantsCellsCSV(run.fluid)) PetscCall(FluidWriteCellsCSV(run.fluid, (dir + "/" + run_files::fluid_cells).c_str()));
    PetscFunctionReturn(0);
  }

private:
  PetscBool particles_; // -output_particles
};

} // namespace

PetscErrorCode FinalTablesCreate(const RunView &run, PetscBool particles, std::unique_ptr<Output> *out)
{
  PetscFunctionBeginUser;
  out->reset();
  if ((run.swarm && particles) || (run.fluid && FluidWantsCellsCSV(run.fluid))) *out = std::make_unique<FinalTables>(particles);
  PetscFunctionReturn(0);
}

namespace {
std::string Quote(const std::string &s)
{
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

// A JSON number, null when not finite (JSON has no NaN or inf).
std::string NumberText(double v)
{
  char buf[64];
  if (std::isfinite(v)) snprintf(buf, sizeof(buf), "%.10g", v);
  else snprintf(buf, sizeof(buf), "null");
  return buf;
}
} // namespace

void JsonWriter::Number(const char *key, double v)
{
  body += (body.empty() ? "" : ",\n") + Quote(key) + ": " + NumberText(v);
}
void JsonWriter::Integer(const char *key, long long v)
{
  body += (body.empty() ? "" : ",\n") + Quote(key) + ": " + std::to_string(v);
}
void JsonWriter::String(const char *key, const std::string &v)
{
  body += (body.empty() ? "" : ",\n") + Quote(key) + ": " + Quote(v);
}
void JsonWriter::Object(const char *key, const JsonWriter &inner)
{
  body += (body.empty() ? "" : ",\n") + Quote(key) + ": " + inner.Text();
}
void JsonWriter::StringArray(const char *key, const std::vector<std::string> &v)
{
  std::string list;
  for (const std::string &s : v) list += (list.empty() ? "" : ", ") + Quote(s);
  body += (body.empty() ? "" : ",\n") + Quote(key) + ": [" + list + "]";
}
void JsonWriter::Bool(const char *key, bool v)
{
  body += (body.empty() ? "" : ",\n") + Quote(key) + ": " + (v ? "true" : "false");
}
void JsonWriter::NumberArray(const char *key, const std::vector<double> &v)
{
  std::string list;
  for (double x : v) list += (list.empty() ? "" : ", ") + NumberText(x);
  body += (body.empty() ? "" : ",\n") + Quote(key) + ": [" + list + "]";
}
void JsonWriter::IntegerArray(const char *key, const std::vector<long long> &v)
{
  std::string list;
  for (long long x : v) list += (list.empty() ? "" : ", ") + std::to_string(x);
  body += (body.empty() ? "" : ",\n") + Quote(key) + ": [" + list + "]";
}
void JsonWriter::BoolArray(const char *key, const std::vector<bool> &v)
{
  std::string list;
  for (bool x : v) list += (list.empty() ? "" : ", ") + std::string(x ? "true" : "false");
  body += (body.empty() ? "" : ",\n") + Quote(key) + ": [" + list + "]";
}
std::string JsonWriter::Text() const
{
  return "{\n" + body + "\n}";
}

PetscErrorCode JsonWrite(MPI_Comm comm, const char *path, const JsonWriter &json)
{
  PetscFunctionBeginUser;
  PetscCall(OutputWriteText(comm, path, json.Text() + "\n"));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
