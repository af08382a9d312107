/// The 1×1 and 2×2 dense algebra of a point's deformation gradient, shared by the native and
/// the PETSc explicit engines so both compute F⁻¹, det F and products in the same order (their
/// results agree bit for bit on one rank). Matrices are column-major D × D arrays.
#pragma once

namespace mfv {

template <int D>
struct SmallMatrix {
  /// C = A B
  static void multiply(const double* A, const double* B, double* C) {
    for (int j = 0; j < D; ++j)
      for (int i = 0; i < D; ++i) {
        double s = 0;
        for (int k = 0; k < D; ++k) s += A[i + D * k] * B[k + D * j];
        C[i + D * j] = s;
      }
  }
  static double det(const double* F) {
    if constexpr (D == 1) return F[0];
    else return F[0] * F[3] - F[1] * F[2];
  }
  /// Fi = F⁻¹ (no singularity test: a non-positive det F is the caller's blow-up check)
  static void invert(const double* F, double* Fi) {
    if constexpr (D == 1) {
      Fi[0] = 1 / F[0];
    } else {
      const double J = det(F);
      Fi[0] = F[3] / J;
      Fi[1] = -F[1] / J;
      Fi[2] = -F[2] / J;
      Fi[3] = F[0] / J;
    }
  }
};

}  // namespace mfv
