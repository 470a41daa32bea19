#pragma once
// The eigen-decomposition of a symmetric 3x3 matrix, the one home of it (Algorithm 1's spread of contact points, the
// principal axes a mesh's symmetries are searched about): cyclic Jacobi (Golub & Van Loan 8.4, the stable form) in a
// fixed order of double operations, so every machine gets the same bits. Slow but unconditionally stable, and the
// matrices are 3x3.
#include <array>
#include <cmath>

namespace sva {

struct SymmetricEigen3 {
  std::array<double, 3> values;                  // in the order the sweeps leave them (not sorted)
  std::array<std::array<double, 3>, 3> vectors;  // vectors[row][j]: column j is the eigenvector of values[j]
};

// `m` is read as its symmetric part (m + m^T) / 2.
inline SymmetricEigen3 symmetric_eigen3(const std::array<std::array<double, 3>, 3>& m) {
  double a[3][3], v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a[i][j] = 0.5 * (m[i][j] + m[j][i]);
  const auto rotate = [](double(&x)[3][3], int p, int q, double c, double s, bool columns) {
    for (int k = 0; k < 3; ++k) {
      double& xp = columns ? x[k][p] : x[p][k];
      double& xq = columns ? x[k][q] : x[q][k];
      const double xkp = xp, xkq = xq;
      xp = c * xkp - s * xkq;
      xq = s * xkp + c * xkq;
    }
  };
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    const double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
    if (off <= 1e-30 * diag || off == 0.0) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0.0) continue;
        // The rotation that zeroes a[p][q].
        const double tau = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        const double t = (tau >= 0 ? 1.0 : -1.0) / (std::fabs(tau) + std::sqrt(1.0 + tau * tau));
        const double c = 1.0 / std::sqrt(1.0 + t * t), s = t * c;
        rotate(a, p, q, c, s, true);
        rotate(a, p, q, c, s, false);
        rotate(v, p, q, c, s, true);
      }
  }
  SymmetricEigen3 out;
  for (int i = 0; i < 3; ++i) {
    out.values[i] = a[i][i];
    for (int j = 0; j < 3; ++j) out.vectors[i][j] = v[i][j];
  }
  return out;
}

}  // namespace sva
