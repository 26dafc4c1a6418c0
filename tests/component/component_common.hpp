// Helpers shared by the component tests: a gather of every rank's entries, a DMDA vector gathered in natural ordering, a collective check
// that prints one line and stops the test on failure, and a portable pseudo-random sequence (the same numbers on every rank, compiler and
// library, unlike the standard distributions).
#pragma once

#include <petscdmda.h>
#include <petscsys.h>

#include <cstdint>
#include <vector>

namespace fluidbed::component {

// Every rank's entries of mine, in rank order, on every rank; counts (optional) gets each rank's number of entries.
template <class T>
PetscErrorCode AllGather(MPI_Comm comm, MPI_Datatype type, const std::vector<T> &mine, std::vector<T> *all,
                         std::vector<PetscMPIInt> *counts_out = nullptr)
{
  PetscMPIInt size;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscMPIInt              n = (PetscMPIInt)mine.size();
  std::vector<PetscMPIInt> counts((std::size_t)size), displs((std::size_t)size, 0);
  PetscCallMPI(MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm));
  for (PetscMPIInt r = 1; r < size; ++r) displs[(std::size_t)r] = displs[(std::size_t)r - 1] + counts[(std::size_t)r - 1];
  all->resize((std::size_t)(displs.back() + counts.back()));
  PetscCallMPI(MPI_Allgatherv(mine.data(), n, type, all->data(), counts.data(), displs.data(), type, comm));
  if (counts_out) *counts_out = counts;
  PetscFunctionReturn(0);
}

// A DMDA global vector in natural ordering (x fastest, dof interleaved), on every rank.
inline PetscErrorCode GatherNatural(DM da, Vec g, std::vector<PetscReal> *out)
{
  Vec                nat, all;
  VecScatter         sc;
  const PetscScalar *a;
  PetscInt           n;

  PetscFunctionBeginUser;
  PetscCall(DMDACreateNaturalVector(da, &nat));
  PetscCall(DMDAGlobalToNaturalBegin(da, g, INSERT_VALUES, nat));
  PetscCall(DMDAGlobalToNaturalEnd(da, g, INSERT_VALUES, nat));
  PetscCall(VecScatterCreateToAll(nat, &sc, &all));
  PetscCall(VecScatterBegin(sc, nat, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(sc, nat, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGetLocalSize(all, &n));
  PetscCall(VecGetArrayRead(all, &a));
  out->assign(a, a + n);
  PetscCall(VecRestoreArrayRead(all, &a));
  PetscCall(VecScatterDestroy(&sc));
  PetscCall(VecDestroy(&all));
  PetscCall(VecDestroy(&nat));
  PetscFunctionReturn(0);
}

// Prints "ok: what (detail)" or "FAIL: ..." once, detail summed over the ranks, and raises an error when the check
// failed on any rank.
inline PetscErrorCode Check(MPI_Comm comm, bool ok, const char *what, long long detail)
{
  PetscFunctionBeginUser;
  int       bad = ok ? 0 : 1, any = 0;
  long long sum = 0;
  PetscCallMPI(MPI_Allreduce(&bad, &any, 1, MPI_INT, MPI_MAX, comm));
  PetscCallMPI(MPI_Allreduce(&detail, &sum, 1, MPI_LONG_LONG, MPI_SUM, comm));
  PetscCall(PetscPrintf(comm, "%s: %s (%lld)\n", any ? "FAIL" : "ok", what, sum));
  PetscCheck(!any, comm, PETSC_ERR_PLIB, "component check failed: %s", what);
  PetscFunctionReturn(0);
}

// splitmix64: uniform 64-bit numbers, and doubles in [0, 1) from their top 53 bits.
struct Random {
  std::uint64_t state;
  explicit Random(std::uint64_t seed) : state(seed) {}
  std::uint64_t Next()
  {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z               = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z               = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  double Uniform() { return (double)(Next() >> 11) * 0x1.0p-53; }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
};

} // namespace fluidbed::component
