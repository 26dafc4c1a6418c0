// Unit tests of the separable Poisson kernels (kernels/separable_poisson.hpp): the 1D operators match the projection's
// rows, their eigenvalues belong to the transform modes FFTW leaves in that order, and the Thomas solve matches dense
// Gaussian elimination, the singular (constant-mode) system included; the partition method (a line cut among ranks,
// solved from its pieces and separators) matches the whole line's solve. No MPI, no PETSc, no FFTW.
#include <gtest/gtest.h>

#include "fluidbed/kernels/separable_poisson.hpp"

#include <cmath>
#include <functional>
#include <random>
#include <vector>

using namespace fluidbed::kernels;

namespace {

// Dense Gaussian elimination with partial pivoting of A x = b (n x n, row-major).
std::vector<double> DenseSolve(std::vector<double> A, std::vector<double> b)
{
  const int n = (int)b.size();
  for (int c = 0; c < n; ++c) {
    int p = c;
    for (int r = c + 1; r < n; ++r)
      if (std::fabs(A[r * n + c]) > std::fabs(A[p * n + c])) p = r;
    for (int q = 0; q < n; ++q) std::swap(A[c * n + q], A[p * n + q]);
    std::swap(b[c], b[p]);
    for (int r = c + 1; r < n; ++r) {
      const double f = A[r * n + c] / A[c * n + c];
      for (int q = c; q < n; ++q) A[r * n + q] -= f * A[c * n + q];
      b[r] -= f * b[c];
    }
  }
  std::vector<double> x(n);
  for (int r = n - 1; r >= 0; --r) {
    double s = b[r];
    for (int q = r + 1; q < n; ++q) s -= A[r * n + q] * x[q];
    x[r] = s / A[r * n + r];
  }
  return x;
}

const LineBC kAll[] = {LineBC::WallWall, LineBC::Periodic, LineBC::WallPressure};

} // namespace

// The rows are the assembly's (src/fluid/pressure.cpp): interior 2, -1, -1; a wall adds nothing; the outlet face at
// h/2 adds 2; periodic wraps.
TEST(SeparablePoisson, LineMatrixIsTheProjectionsRows)
{
  EXPECT_EQ(line_matrix_entry(LineBC::WallWall, 4, 0, 0), 1.0);
  EXPECT_EQ(line_matrix_entry(LineBC::WallWall, 4, 3, 3), 1.0);
  EXPECT_EQ(line_matrix_entry(LineBC::WallWall, 4, 1, 1), 2.0);
  EXPECT_EQ(line_matrix_entry(LineBC::WallWall, 4, 1, 2), -1.0);
  EXPECT_EQ(line_matrix_entry(LineBC::WallWall, 4, 0, 3), 0.0);
  EXPECT_EQ(line_matrix_entry(LineBC::WallPressure, 4, 3, 3), 3.0);
  EXPECT_EQ(line_matrix_entry(LineBC::WallPressure, 1, 0, 0), 2.0);
  EXPECT_EQ(line_matrix_entry(LineBC::Periodic, 4, 0, 3), -1.0);
  EXPECT_EQ(line_matrix_entry(LineBC::Periodic, 2, 0, 1), -2.0);
  for (LineBC bc : kAll)
    for (int n : {1, 2, 3, 7}) // every row sums to zero but the outlet's
      for (int j = 0; j < n; ++j) {
        double s = 0;
        for (int l = 0; l < n; ++l) s += line_matrix_entry(bc, n, j, l);
        EXPECT_NEAR(s, (bc == LineBC::WallPressure && j == n - 1) ? 2.0 : 0.0, 1e-15) << (int)bc << " n " << n << " row " << j;
      }
}

// T v_k = lambda_k v_k for every orthonormal mode of the transform (line_mode, in FFTW's order) to 5e-14 (the largest
// seen is 2.5e-14, at 175 cells), on odd, even and one-cell axes.
TEST(SeparablePoisson, EigenvaluesBelongToTheTransformModes)
{
  for (LineBC bc : kAll)
    for (int n : {1, 2, 3, 4, 5, 8, 16, 175}) {
      if (bc == LineBC::Periodic && n == 1) continue;
      for (int k = 0; k < n; ++k) {
        const double lam = line_eigenvalue(bc, n, k);
        double       err = 0;
        for (int j = 0; j < n; ++j) {
          double tv = 0;
          for (int l = 0; l < n; ++l) tv += line_matrix_entry(bc, n, j, l) * line_mode(bc, n, k, l);
          err = std::fmax(err, std::fabs(tv - lam * line_mode(bc, n, k, j)));
        }
        EXPECT_LT(err, 5e-14) << "bc " << (int)bc << " n " << n << " k " << k;
        EXPECT_GE(lam, 0.0);
        EXPECT_LE(lam, 4.0 + 1e-12);
      }
    }
  EXPECT_EQ(line_eigenvalue(LineBC::WallWall, 9, 0), 0.0); // the constant mode, exactly
  EXPECT_EQ(line_eigenvalue(LineBC::Periodic, 9, 0), 0.0);
  EXPECT_GT(line_eigenvalue(LineBC::WallPressure, 9, 0), 0.0); // the outlet fixes the level: no null space
}

// The modes are orthonormal (V^T V = I), and the dense transform and its transpose invert each other.
TEST(SeparablePoisson, DenseModesAreOrthonormal)
{
  for (LineBC bc : kAll)
    for (int n : {1, 2, 3, 4, 5, 8}) {
      if (bc == LineBC::Periodic && n == 1) continue;
      std::vector<double> V(n * n);
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k) V[j * n + k] = line_mode(bc, n, k, j);
      for (int k = 0; k < n; ++k) {
        for (int l = 0; l < n; ++l) {
          double dot = 0;
          for (int j = 0; j < n; ++j) dot += V[j * n + k] * V[j * n + l];
          EXPECT_NEAR(dot, k == l ? 1.0 : 0.0, 1e-13) << "bc " << (int)bc << " n " << n << " modes " << k << ", " << l;
        }
      }
      // three blocks of n x 300 (more than one chunk of the planes): the forward transform is V^T x per block, and the
      // backward transform gives the input back
      const long          inner = 300, outer = 3;
      std::vector<double> x(outer * n * inner), back(x.size());
      for (std::size_t q = 0; q < x.size(); ++q) x[q] = std::sin(0.37 * q + 0.1);
      back = x;
      dense_line_transform(n, inner, outer, V.data(), false, back.data());
      for (long o = 0; o < outer; ++o)
        for (int k = 0; k < n; ++k)
          for (long q : {0L, 255L, 256L, inner - 1}) {
            double ref = 0;
            for (int j = 0; j < n; ++j) ref += V[j * n + k] * x[(o * n + j) * inner + q];
            EXPECT_NEAR(back[(o * n + k) * inner + q], ref, 1e-13);
          }
      dense_line_transform(n, inner, outer, V.data(), true, back.data());
      for (std::size_t q = 0; q < x.size(); ++q) EXPECT_NEAR(back[q], x[q], 1e-13);
    }
}

// The Thomas solve of interleaved lines, each with its own lambda and a scale s, against dense elimination.
TEST(SeparablePoisson, TridiagonalSolveMatchesDenseElimination)
{
  std::mt19937                           gen(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (LineBC bc : {LineBC::WallWall, LineBC::WallPressure})
    for (int n : {1, 2, 3, 30}) {
      const int           m = 5;
      const double        w = 2.5, s = 0.3;
      std::vector<double> inv(n * m), x(n * m), lam(m);
      for (int i = 0; i < m; ++i) {
        lam[i] = 0.1 + 2.0 * i;
        std::vector<double> col(n);
        tridiagonal_factor(bc, n, w, lam[i], col.data());
        for (int j = 0; j < n; ++j) inv[j * m + i] = col[j];
      }
      for (double &v : x) v = u(gen);
      const std::vector<double> r = x;
      tridiagonal_solve_lines(n, m, w, s, inv.data(), x.data());
      for (int i = 0; i < m; ++i) {
        std::vector<double> A(n * n), b(n);
        for (int j = 0; j < n; ++j) {
          b[j] = s * r[j * m + i];
          for (int l = 0; l < n; ++l) A[j * n + l] = w * line_matrix_entry(bc, n, j, l) + (j == l ? lam[i] : 0.0);
        }
        const std::vector<double> ref = DenseSolve(A, b);
        for (int j = 0; j < n; ++j) EXPECT_NEAR(x[j * m + i], ref[j], 1e-12 * (1 + std::fabs(ref[j]))) << "n " << n << " line " << i;
      }
    }
}

namespace {

// A pseudo-solve of the constant mode between two walls (w T x = r, lambda = 0): solve(x) maps r to x in place. The
// unknown pin is held at 0, every equation holds for a zero-sum right-hand side (so the result is the solution up to
// a constant), and the map r -> x is symmetric, as CG needs of a preconditioner.
void CheckPinnedPseudoSolve(int n, double w, int pin, const std::function<void(std::vector<double> &)> &solve, const char *label)
{
  std::mt19937                           gen(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double>                    r(n);
  double                                 mean = 0;
  for (double &v : r) mean += (v = u(gen)) / n;
  for (double &v : r) v -= mean;
  std::vector<double> x = r;
  solve(x);
  EXPECT_EQ(x[pin], 0.0) << label;
  for (int j = 0; j < n; ++j) {
    double ax = 0;
    for (int l = 0; l < n; ++l) ax += w * line_matrix_entry(LineBC::WallWall, n, j, l) * x[l];
    EXPECT_NEAR(ax, r[j], 1e-12) << label << " row " << j;
  }
  std::vector<double> G(n * n); // symmetry of the map r -> x: e_a . G e_b = e_b . G e_a
  for (int b = 0; b < n; ++b) {
    std::vector<double> e(n, 0.0);
    e[b] = 1;
    solve(e);
    for (int a = 0; a < n; ++a) G[a * n + b] = e[a];
  }
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < a; ++b) EXPECT_NEAR(G[a * n + b], G[b * n + a], 1e-12) << label;
}

} // namespace

// The constant mode between two walls (lambda = 0): the last unknown is pinned at 0 and the other n - 1 equations
// hold, so a consistent right-hand side (zero sum) is solved up to a constant; the pseudo-solve is symmetric.
TEST(SeparablePoisson, SingularLineIsPinnedAndSymmetric)
{
  const int           n = 12;
  const double        w = 1.7;
  std::vector<double> inv(n);
  tridiagonal_factor(LineBC::WallWall, n, w, 0.0, inv.data());
  EXPECT_EQ(inv[n - 1], 0.0);
  CheckPinnedPseudoSolve(
    n, w, n - 1, [&](std::vector<double> &x) { tridiagonal_solve_lines(n, 1, w, 1.0, inv.data(), x.data()); }, "whole line");
}

namespace {

// The partition method as fast_poisson.cpp runs it across ranks, here on one process: each part's piece solved alone,
// the separators' system, each piece solved again with its separators' values. x holds the right-hand side on entry.
void PartitionedSolve(LineBC bc, int n, const std::vector<int> &cut, double w, double lambda, std::vector<double> &x)
{
  const int           P = (int)cut.size() - 1;
  std::vector<double> sinv(P), cpl(P), scratch(2 * n), s(P, 0.0), rhs = x;
  separator_factor(bc, n, P, cut.data(), w, lambda, sinv.data(), cpl.data(), scratch.data());
  std::vector<std::vector<double>> inv(P);
  for (int r = 0; r < P; ++r) {
    const int j0 = piece_begin(cut.data(), r), j1 = piece_end(cut.data(), P, r);
    inv[r].resize(j1 - j0);
    tridiagonal_piece_factor(bc, n, j0, j1, w, lambda, inv[r].data());
    tridiagonal_solve_lines(j1 - j0, 1, w, 1.0, inv[r].data(), x.data() + j0);
  }
  for (int r = 0; r < P - 1; ++r) s[r] = rhs[cut[r + 1] - 1] + w * (x[piece_end(cut.data(), P, r) - 1] + x[piece_begin(cut.data(), r + 1)]);
  separator_solve(P, sinv.data(), cpl.data(), s.data());
  for (int r = 0; r < P; ++r) {
    const int j0 = piece_begin(cut.data(), r), j1 = piece_end(cut.data(), P, r);
    for (int j = j0; j < j1; ++j) x[j] = rhs[j];
    if (r > 0) x[j0] += w * s[r - 1];
    if (r < P - 1) x[j1 - 1] += w * s[r];
    tridiagonal_solve_lines(j1 - j0, 1, w, 1.0, inv[r].data(), x.data() + j0);
    if (r < P - 1) x[j1] = s[r];
  }
}

} // namespace

// The line split among 2-5 parts (the ranks of an x-split grid), pieces of one cell included: the partitioned solve
// equals the whole line's Thomas solve to round-off, for walls, the outlet and several lambdas.
TEST(SeparablePoisson, PartitionedSolveMatchesWholeLine)
{
  std::mt19937                           gen(11);
  std::uniform_real_distribution<double> u(-1, 1);
  const std::vector<std::vector<int>>    cuts = {{0, 10, 21},           {0, 2, 21},         {0, 19, 21}, {0, 7, 9, 15, 21},
                                                 {0, 4, 8, 12, 16, 21}, {0, 2, 4, 6, 8, 21}};
  for (LineBC bc : {LineBC::WallWall, LineBC::WallPressure})
    for (double lambda : {0.05, 1.3, 7.0})
      for (const auto &cut : cuts) {
        const int           n = 21;
        const double        w = 1.9;
        std::vector<double> x(n), inv(n);
        for (double &v : x) v = u(gen);
        std::vector<double> ref = x;
        tridiagonal_factor(bc, n, w, lambda, inv.data());
        tridiagonal_solve_lines(n, 1, w, 1.0, inv.data(), ref.data());
        PartitionedSolve(bc, n, cut, w, lambda, x);
        for (int j = 0; j < n; ++j)
          EXPECT_NEAR(x[j], ref[j], 1e-12 * (1 + std::fabs(ref[j]))) << "parts " << cut.size() - 1 << " lambda " << lambda << " cell " << j;
      }
}

// The constant mode between two walls, split: the last separator is pinned at 0, every other equation holds for a
// zero-sum right-hand side, so the result is the whole line's up to a constant; the map r -> x is symmetric.
TEST(SeparablePoisson, PartitionedSingularLineIsPinnedAndSymmetric)
{
  const int    n = 13;
  const double w = 0.8;
  for (const std::vector<int> &cut : {std::vector<int>{0, 6, 13}, std::vector<int>{0, 3, 5, 9, 13}}) {
    const int P = (int)cut.size() - 1;
    CheckPinnedPseudoSolve(
      n, w, cut[P - 1] - 1, [&](std::vector<double> &x) { PartitionedSolve(LineBC::WallWall, n, cut, w, 0.0, x); },
      P == 2 ? "2 parts" : "4 parts");
  }
}
