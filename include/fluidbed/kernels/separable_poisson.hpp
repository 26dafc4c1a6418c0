// The projection's operator with one constant face coefficient on a uniform cell-centred grid is separable: a sum over
// the axes of w_a T_a, w_a = A_a / h_a, where T_a is the 1D second difference (times -1) along a with that axis's
// boundaries. Transforms diagonalise T_a along the walled and periodic axes (cosine and Fourier modes, as FFTW's
// real-to-real transforms order them) and a tridiagonal solve along the remaining axis finishes the inverse: the fast
// Poisson preconditioner of the pressure solve (src/fluid/fast_poisson.cpp, docs/fluid.md). Plain functions, no
// PETSc; tests/unit/test_separable_poisson.cpp checks them against the matrices they diagonalise and dense solves.
#pragma once

#include <cmath>

namespace fluidbed::kernels {

// The boundaries of one axis of the pressure grid, as the projection's assembly treats them (src/fluid/pressure.cpp):
// a wall on both sides (no pressure flux: T_00 = T_nn = 1), periodic (circulant 2, -1, -1), or a wall below and a
// pressure outlet above (phi = 0 on the upper face, half a cell from the last centre: T_nn = 3).
enum class LineBC { WallWall, Periodic, WallPressure };

// The entry (j, l) of T for an axis of n cells (for tests and checks; the periodic two-cell axis joins the pair by
// both faces, 2 and -2, as the assembly does).
inline double line_matrix_entry(LineBC bc, int n, int j, int l)
{
  if (bc == LineBC::Periodic) {
    if (n == 1) return 0.0;
    if (j == l) return 2.0;
    const int d = ((l - j) % n + n) % n;
    if (n == 2) return -2.0;
    return (d == 1 || d == n - 1) ? -1.0 : 0.0;
  }
  if (j == l) {
    double t = 0.0;
    if (j > 0) t += 1.0;
    if (j < n - 1) t += 1.0;
    else if (bc == LineBC::WallPressure) t += 2.0; // the face at distance h/2: A / (h/2) = 2 A / h
    return t;
  }
  return (l == j - 1 || l == j + 1) ? -1.0 : 0.0;
}

// The eigenvalue of T for the mode at index k of the transform that diagonalises it, in FFTW's output order:
// - WallWall, DCT-II (FFTW_REDFT10, mode cos(pi k (j + 1/2) / n)): 4 sin^2(pi k / (2 n));
// - Periodic, real-to-halfcomplex (FFTW_R2HC: index k <= n/2 the cosine of frequency k, n - k its sine): 4 sin^2(pi k / n),
//   the same for both members of a pair;
// - WallPressure, DCT-IV (FFTW_REDFT11, mode cos(pi (k + 1/2)(j + 1/2) / n)): 4 sin^2(pi (2k + 1) / (4 n)).
inline double line_eigenvalue(LineBC bc, int n, int k)
{
  double s = 0.0;
  switch (bc) {
  case LineBC::WallWall:
    s = std::sin(M_PI * k / (2.0 * n));
    break;
  case LineBC::Periodic:
    s = std::sin(M_PI * k / n);
    break;
  case LineBC::WallPressure:
    s = std::sin(M_PI * (2.0 * k + 1.0) / (4.0 * n));
    break;
  }
  return 4.0 * s * s;
}

// The orthonormal mode k of T at cell j, in the order of line_eigenvalue (and of FFTW's output): for short axes, whose
// transform is cheaper as a small dense matrix across the planes than as FFTW's strided transforms.
inline double line_mode(LineBC bc, int n, int k, int j)
{
  switch (bc) {
  case LineBC::WallWall:
    return std::sqrt((k == 0 ? 1.0 : 2.0) / n) * std::cos(M_PI * k * (j + 0.5) / n);
  case LineBC::WallPressure:
    return std::sqrt(2.0 / n) * std::cos(M_PI * (k + 0.5) * (j + 0.5) / n);
  case LineBC::Periodic:
    if (k == 0) return 1.0 / std::sqrt((double)n);
    if (2 * k == n) return (j % 2 ? -1.0 : 1.0) / std::sqrt((double)n);
    if (2 * k < n) return std::sqrt(2.0 / n) * std::cos(2.0 * M_PI * k * j / n);
    return std::sqrt(2.0 / n) * std::sin(2.0 * M_PI * (n - k) * j / n);
  }
  return 0.0;
}

// In place on blocks of outer x n x inner values: x[o][k][q] <- sum_j V[j][k] x[o][j][q] (transpose: sum_k V[j][k]
// x[o][k][q] into place j), V[j * n + k] = line_mode(k, j): the forward (backward) transform along an axis of n <= 16
// cells whose stride is inner. Works through the planes in chunks of 256 positions copied to the stack, so the data is
// read and written once.
inline void dense_line_transform(int n, long inner, long outer, const double *V, bool transpose, double *x)
{
  constexpr long chunk = 256;
  double         t[16 * chunk];
  for (long o = 0; o < outer; ++o) {
    double *b = x + o * n * inner;
    for (long q0 = 0; q0 < inner; q0 += chunk) {
      const long c = inner - q0 < chunk ? inner - q0 : chunk;
      for (int j = 0; j < n; ++j)
        for (long q = 0; q < c; ++q) t[j * chunk + q] = b[j * inner + q0 + q];
      for (int k = 0; k < n; ++k) {
        double *y = b + k * inner + q0;
        for (long q = 0; q < c; ++q) y[q] = 0.0;
        for (int j = 0; j < n; ++j) {
          const double  v  = transpose ? V[k * n + j] : V[j * n + k];
          const double *tj = t + j * chunk;
          for (long q = 0; q < c; ++q) y[q] += v * tj[q];
        }
      }
    }
  }
}

// A forward and a backward transform of FFTW in a row multiply by this (they are inverse up to it).
inline double line_transform_scale(LineBC bc, int n)
{
  return bc == LineBC::Periodic ? n : 2.0 * n;
}

// Thomas factors of the rows [j0, j1) of w T + lambda I (an axis of n cells with boundaries bc, not periodic) as a
// block of their own, their couplings to rows outside it left to the right-hand side: inv[j - j0] = 1 / pivot j. When
// the block is the whole axis and singular (lambda = 0 between two walls: the constant mode), pin_last sets the last
// pivot's inverse to 0 instead.
inline void tridiagonal_piece_factor(LineBC bc, int n, int j0, int j1, double w, double lambda, double *inv, bool pin_last = false)
{
  for (int j = j0; j < j1; ++j) {
    const double b     = w * line_matrix_entry(bc, n, j, j) + lambda;
    const double pivot = j == j0 ? b : b - w * w * inv[j - j0 - 1];
    inv[j - j0]        = (pin_last && j == j1 - 1) ? 0.0 : 1.0 / pivot;
  }
}

// Thomas factors of w T + lambda I along an axis of n cells with boundaries bc (not periodic): inv[j] = 1 / pivot j.
// When the system is singular (lambda = 0 between two walls: the constant mode) the last pivot is zero and inv[n-1] is
// set to 0, which pins the last unknown at 0 and solves the other n - 1 equations: the symmetric pseudo-solve of the
// constant null space, which the Krylov method projects out.
inline void tridiagonal_factor(LineBC bc, int n, double w, double lambda, double *inv)
{
  tridiagonal_piece_factor(bc, n, 0, n, w, lambda, inv, bc == LineBC::WallWall && lambda == 0.0);
}

// Solves (w T + lambda_i I) x_i = s r_i in place for m interleaved lines (x[j m + i], i < m) of n cells with their
// factors inv[j m + i] (tridiagonal_factor of line i); s scales the right-hand side (the transforms' normalisation).
inline void tridiagonal_solve_lines(int n, int m, double w, double s, const double *inv, double *x)
{
  for (int i = 0; i < m; ++i) x[i] = s * x[i] * inv[i];
  for (int j = 1; j < n; ++j) {
    double       *xj = x + (long)j * m;
    const double *xp = xj - m, *ij = inv + (long)j * m;
    for (int i = 0; i < m; ++i) xj[i] = (s * xj[i] + w * xp[i]) * ij[i];
  }
  for (int j = n - 2; j >= 0; --j) {
    double       *xj = x + (long)j * m;
    const double *xn = xj + m, *ij = inv + (long)j * m;
    for (int i = 0; i < m; ++i) xj[i] += w * ij[i] * xn[i];
  }
}

// The partition method: the line solve of an axis whose cells are split among P ranks, without moving the line.
// Part r holds the cells [cut[r], cut[r + 1]) (cut[0] = 0, cut[P] = n). Every part but the last keeps its last cell,
// cut[r + 1] - 1, as a separator; the rest of the part, its piece [piece_begin, piece_end), is solved on its own with
// its couplings to the separators moved to the right-hand side (each piece at least one cell: parts but the last
// hold two or more). With the pieces eliminated, the separators' equations form a symmetric tridiagonal system of
// P - 1 unknowns (the Schur complement) that each rank solves from three numbers per part: its piece's first and last
// values solved alone and its separator's right-hand side. Each piece is then solved again with its separators' values.
// The result is the whole line's solve (exact up to round-off); where the line is singular (the constant mode between
// two walls) the last separator is pinned at 0, which is again a symmetric pseudo-solve of the constant null space.
inline int piece_begin(const int *cut, int r)
{
  return cut[r];
}
inline int piece_end(const int *cut, int P, int r)
{
  return r < P - 1 ? cut[r + 1] - 1 : cut[P];
}

// The Schur complement on the separators of one line of w T + lambda I, factored: sinv[r] (r < P - 1) the inverse
// pivots, cpl[r] (r < P - 2) = w^2 (T_p^-1)_{last, first} of the piece p = r + 1 between separators r and r + 1 (the
// system's off-diagonal is -cpl). scratch holds at least twice the longest piece's cells.
// The system's diagonal at separator r: w T_rr + lambda - w^2 ((T_r^-1)_{last, last} + (T_{r+1}^-1)_{first, first}).
inline void separator_factor(LineBC bc, int n, int P, const int *cut, double w, double lambda, double *sinv, double *cpl, double *scratch)
{
  const bool pin        = bc == LineBC::WallWall && lambda == 0.0;
  double     prev_first = 0.0; // (T_{r+1}^-1)_{first, first} of the piece after separator r, filled as r + 1 is done
  for (int r = P - 1; r >= 0; --r) {
    const int j0 = piece_begin(cut, r), j1 = piece_end(cut, P, r), m = j1 - j0;
    double   *inv = scratch, *e = scratch + m;
    tridiagonal_piece_factor(bc, n, j0, j1, w, lambda, inv);
    for (int j = 0; j < m; ++j) e[j] = j == 0 ? 1.0 : 0.0;
    tridiagonal_solve_lines(m, 1, w, 1.0, inv, e); // T_r^-1 e_first: its first and last entries
    const double first_first = e[0], last_first = e[m - 1];
    for (int j = 0; j < m; ++j) e[j] = j == m - 1 ? 1.0 : 0.0;
    tridiagonal_solve_lines(m, 1, w, 1.0, inv, e); // T_r^-1 e_last: its last entry
    const double last_last = e[m - 1];
    if (r < P - 1) {
      const int sep = cut[r + 1] - 1;
      sinv[r]       = w * line_matrix_entry(bc, n, sep, sep) + lambda - w * w * (last_last + prev_first); // the diagonal, for now
    }
    if (r >= 1 && r < P - 1) cpl[r - 1] = w * w * last_first;
    prev_first = first_first;
  }
  for (int r = 0; r < P - 1; ++r) {
    const double pivot = r == 0 ? sinv[0] : sinv[r] - cpl[r - 1] * cpl[r - 1] * sinv[r - 1];
    sinv[r]            = (pin && r == P - 2) ? 0.0 : 1.0 / pivot;
  }
}

// Solves the separators' system (separator_factor) in place: on entry s[r] = separator r's right-hand side + w (the
// last value of piece r + the first value of piece r + 1, each solved alone); on return the separators' values.
inline void separator_solve(int P, const double *sinv, const double *cpl, double *s)
{
  const int m = P - 1;
  s[0] *= sinv[0];
  for (int r = 1; r < m; ++r) s[r] = (s[r] + cpl[r - 1] * s[r - 1]) * sinv[r];
  for (int r = m - 2; r >= 0; --r) s[r] += cpl[r] * sinv[r] * s[r + 1];
}

} // namespace fluidbed::kernels
