#include "methods/approximations/particle_gradients.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "methods/core/errors.hpp"
#include "methods/core/parallel.hpp"

namespace mfv {

namespace {

void require_same_rows(const ShapeTable& a, const ShapeTable& b) {
  if (a.offsets != b.offsets || a.index != b.index)
    throw std::logic_error("particle gradient tables must share neighbour lists");
}

/// Each row's diagonal entry (row q is particle q); -1 when q is outside its own row.
int diagonal_entry(const ShapeTable& t, int q) {
  for (int k = t.offsets[q]; k < t.offsets[q + 1]; ++k)
    if (t.index[k] == q) return k;
  return -1;
}

/// M⁻¹ into `inverse` (lu and inverse are the caller's, reused), or SingularError with what()
/// when M is singular or nearly so (relative to its size); the message is built only then,
/// since this runs once per point. With `fallback` the singular case gives inverse = I and
/// returns true instead of throwing (the callers' headers say what the identity means).
template <class Matrix, class Message>
bool invert_or_throw(const Matrix& M, Eigen::FullPivLU<Matrix>& lu, Matrix& inverse,
                     const Message& what, bool fallback = false) {
  lu.compute(M);
  if (!lu.isInvertible() ||
      !(std::abs(lu.determinant()) > 1e-12 * std::pow(M.norm(), static_cast<double>(M.rows())))) {
    if (!fallback) throw SingularError(what());
    inverse.setIdentity(M.rows(), M.cols());
    return true;
  }
  inverse = lu.inverse();
  return false;
}

/// Copy of the row structure with values δ_IJ, gradients zeroed, into t (storage reused).
void delta_table(const ShapeTable& s, ShapeTable& t) {
  t.dim = s.dim;
  t.order = 1;
  t.offsets = s.offsets;
  t.index = s.index;
  t.value.assign(s.entries(), 0.0);
  t.grad.assign(static_cast<std::size_t>(s.entries()) * s.dim, 0.0);
  t.hess.clear();
  for (int q = 0; q < s.points(); ++q) {
    const int k = diagonal_entry(s, q);
    if (k < 0) throw std::logic_error("a particle lies outside its own support");
    t.value[k] = 1;
  }
}

}  // namespace

ShapeTable sph_symmetric_gradient(const ShapeTable& sph) {
  ShapeTable t;
  sph_symmetric_gradient(sph, t, 1);
  return t;
}

void sph_symmetric_gradient(const ShapeTable& sph, ShapeTable& t, int threads) {
  delta_table(sph, t);
  const int dim = sph.dim;
  const int n = sph.points();
  // Row q writes only its own entries (its diagonal included): rows are independent.
#pragma omp parallel for schedule(static) num_threads(std::max(1, threads)) if (run_parallel(threads, n))
  for (int q = 0; q < n; ++q) {
    const int kd = diagonal_entry(sph, q);
    for (int k = sph.offsets[q]; k < sph.offsets[q + 1]; ++k) {
      if (k == kd) continue;
      for (int d = 0; d < dim; ++d) {
        t.grad[k * dim + d] = sph.grad[k * dim + d];
        t.grad[kd * dim + d] -= sph.grad[k * dim + d];
      }
    }
  }
}

void sph_symmetric_gradient_in_place(ShapeTable& t, int threads) {
  const int dim = t.dim;
  const int n = t.points();
  t.hess.clear();
  if (t.grad.size() != static_cast<std::size_t>(t.entries()) * dim)
    throw std::logic_error("the SPH table needs its first derivatives");
  FirstError error;
  // As sph_symmetric_gradient: the off-diagonal gradients stay, the diagonal's is minus their
  // sum in the same order, the values become δ_IJ.
#pragma omp parallel for schedule(static) num_threads(std::max(1, threads)) if (run_parallel(threads, n))
  for (int q = 0; q < n; ++q) {
    const int kd = diagonal_entry(t, q);
    if (kd < 0) {
      error.keep(q, std::make_exception_ptr(
                        std::logic_error("a particle lies outside its own support")));
      continue;
    }
    double diag[3] = {0, 0, 0};
    for (int k = t.offsets[q]; k < t.offsets[q + 1]; ++k) {
      t.value[k] = k == kd ? 1.0 : 0.0;
      if (k == kd) continue;
      for (int d = 0; d < dim; ++d) diag[d] -= t.grad[k * dim + d];
    }
    for (int d = 0; d < dim; ++d) t.grad[kd * dim + d] = diag[d];
  }
  error.rethrow();
}

RandlesLiberskyTables randles_libersky(const ShapeTable& sph, const ParticleSet& p) {
  RandlesLiberskyTables out;
  randles_libersky(sph, p, out, 1);
  return out;
}

void randles_libersky(const ShapeTable& sph, const ParticleSet& p, RandlesLiberskyTables& out,
                      int threads, DegenerateMarks* degenerate) {
  const int dim = sph.dim;
  const int n = sph.points();
  threads = std::max(1, threads);
  delta_table(sph, out.trial);
  delta_table(sph, out.test);
  ShapeTable& G = out.trial;
  ShapeTable& H = out.test;
  if (degenerate) degenerate->cover(n);
  FirstError error;
  // Trial rows: c_IJ = Bᵀ_I g_IJ with g_IJ = V_J ∇W(X_I - X_J) from the SPH table; row I
  // writes only its own entries.
#pragma omp parallel num_threads(threads) if (run_parallel(threads, n))
  {
    Eigen::MatrixXd Binv(dim, dim), Bi(dim, dim), Bt(dim, dim);
    Eigen::FullPivLU<Eigen::MatrixXd> lu(dim, dim);
    Eigen::VectorXd g(dim), c(dim);
#pragma omp for schedule(static)
    for (int I = 0; I < n; ++I) {
      try {
        Binv.setZero();
        for (int k = sph.offsets[I]; k < sph.offsets[I + 1]; ++k) {
          const int J = sph.index[k];
          for (int a = 0; a < dim; ++a)
            for (int b = 0; b < dim; ++b)
              Binv(a, b) += (p.x(a, J) - p.x(a, I)) * sph.grad[k * dim + b];
        }
        const bool fell_back = invert_or_throw(
            Binv, lu, Bi,
            [I] {
              return fmt::format("rlm: the normalization matrix B⁻¹ (001 eq 34) of particle {} "
                                 "is singular; its neighbours are too few or collinear: raise "
                                 "the support (dmax)",
                                 I);
            },
            degenerate != nullptr);
        if (fell_back) degenerate->mark(I);
        Bt = Bi.transpose();
        const int kd = diagonal_entry(sph, I);
        for (int k = sph.offsets[I]; k < sph.offsets[I + 1]; ++k) {
          if (k == kd) continue;
          for (int d = 0; d < dim; ++d) g[d] = sph.grad[k * dim + d];
          c.noalias() = Bt * g;
          for (int d = 0; d < dim; ++d) {
            G.grad[k * dim + d] = c[d];
            G.grad[kd * dim + d] -= c[d];
          }
        }
      } catch (...) {
        error.keep(I, std::current_exception());
      }
    }
  }
  error.rethrow();
  // Test rows: f_I = -V_I Σ_J (σ_J + σ_I)·c_IJ. The coefficient of σ_J (J ≠ I) is -V_I c_IJ,
  // stored at row q = J, entry I, divided by the weight V_J of that row; the coefficient of
  // σ_I is -V_I Σ_J c_IJ, stored at row I, entry I, divided by V_I. Each entry is written by
  // one I: the diagonal by I itself, entry I of row J by I.
  for (int I = 0; I < n; ++I) {
    const int kd = diagonal_entry(sph, I);
    for (int d = 0; d < dim; ++d) H.grad[kd * dim + d] = G.grad[kd * dim + d];
  }
#pragma omp parallel for schedule(static) num_threads(threads) if (run_parallel(threads, n))
  for (int I = 0; I < n; ++I) {
    const int kd = diagonal_entry(sph, I);
    try {
      for (int k = sph.offsets[I]; k < sph.offsets[I + 1]; ++k) {
        if (k == kd) continue;
        const int J = sph.index[k];
        // Entry I of row J (rows share symmetric neighbour lists: constant dilation). The
        // kernel tables list rows in ascending particle index, so a binary search finds it; a
        // table in another order is searched through.
        const int* first = sph.index.data() + sph.offsets[J];
        const int* last = sph.index.data() + sph.offsets[J + 1];
        const int* it = std::lower_bound(first, last, I);
        if (it == last || *it != I) it = std::find(first, last, I);
        const int kji = it != last ? static_cast<int>(it - sph.index.data()) : -1;
        if (kji < 0)
          throw InputError("rlm needs symmetric neighbour lists (one dilation for all particles)");
        for (int d = 0; d < dim; ++d)
          H.grad[kji * dim + d] = -p.volume[I] / p.volume[J] * G.grad[k * dim + d];
      }
    } catch (...) {
      error.keep(n + I, std::current_exception());
    }
  }
  error.rethrow();
}

ShapeTable corrected_gradient(const ShapeTable& shepard, const ShapeTable& values,
                              const ParticleSet& p, const Eigen::MatrixXd& points) {
  ShapeTable t;
  corrected_gradient(shepard, values, p, points, t, 1);
  return t;
}

namespace {

/// corrected_gradient's rows, with the 2 × 2 (or dim × dim) correction in `Matrix`: fixed
/// size in 2D (the same LU, pivots and products as the dynamic size, bit for bit, without its
/// allocations per point), dynamic otherwise.
template <class Matrix>
void corrected_rows(const ShapeTable& shepard, const ParticleSet& p, const Eigen::MatrixXd& points,
                    ShapeTable& t, int threads, DegenerateMarks* degenerate) {
  const int dim = shepard.dim;
  const int n = shepard.points();
  FirstError error;
#pragma omp parallel num_threads(std::max(1, threads)) if (run_parallel(threads, n))
  {
    Matrix M(dim, dim), a(dim, dim);
    Eigen::FullPivLU<Matrix> lu(dim, dim);
    // Eigen's own default threshold (ε × the diagonal's size), set explicitly: the fixed-size
    // LU would otherwise carry an unset prescribed threshold that GCC warns about.
    lu.setThreshold(Eigen::NumTraits<double>::epsilon() * dim);
    Eigen::VectorXd g(dim), G(dim);
#pragma omp for schedule(static)
    for (int q = 0; q < n; ++q) {
      try {
        if (degenerate) {
          // An empty support (the Shepard row sums to zero, its fallback): no value and no
          // gradient, so the point takes part in no sum.
          double sum = 0;
          for (int k = shepard.offsets[q]; k < shepard.offsets[q + 1]; ++k)
            sum += shepard.value[k];
          if (sum == 0) {
            for (int k = shepard.offsets[q]; k < shepard.offsets[q + 1]; ++k) t.value[k] = 0;
            degenerate->mark(q);
            continue;
          }
        }
        // M_jb = Σ_I ∂_j W^S_I (X_I - x)_b: the shift by x changes nothing (Σ ∇W^S = 0) but
        // keeps the sums well scaled.
        M.setZero();
        for (int k = shepard.offsets[q]; k < shepard.offsets[q + 1]; ++k)
          for (int j = 0; j < dim; ++j)
            for (int b = 0; b < dim; ++b)
              M(j, b) += shepard.grad[k * dim + j] * (p.x(b, shepard.index[k]) - points(b, q));
        // G_I = a ∇W^S_I with a = M⁻¹ (eq 31: A aᵀ = I with A = Mᵀ).
        const bool fell_back = invert_or_throw(
            M, lu, a,
            [q] {
              return fmt::format("kbm: the correction matrix A (001 eq 31) is singular at point "
                                 "{}; its support holds too few or collinear particles: raise "
                                 "the support (dmax)",
                                 q);
            },
            degenerate != nullptr);
        if (fell_back) degenerate->mark(q);
        if (dim <= 2) {
          // a g by hand: with one or two terms a sum has one rounding whatever its order, so
          // this is Eigen's product bit for bit, without its dynamic-size call per entry.
          for (int k = shepard.offsets[q]; k < shepard.offsets[q + 1]; ++k)
            for (int d = 0; d < dim; ++d) {
              double v = a(d, 0) * shepard.grad[k * dim];
              if (dim == 2) v += a(d, 1) * shepard.grad[k * dim + 1];
              t.grad[k * dim + d] = v;
            }
          continue;
        }
        for (int k = shepard.offsets[q]; k < shepard.offsets[q + 1]; ++k) {
          for (int j = 0; j < dim; ++j) g[j] = shepard.grad[k * dim + j];
          G.noalias() = a * g;
          for (int d = 0; d < dim; ++d) t.grad[k * dim + d] = G[d];
        }
      } catch (...) {
        error.keep(q, std::current_exception());
      }
    }
  }
  error.rethrow();
}

}  // namespace

void corrected_gradient(const ShapeTable& shepard, const ShapeTable& values,
                        const ParticleSet& p, const Eigen::MatrixXd& points, ShapeTable& t,
                        int threads, DegenerateMarks* degenerate) {
  require_same_rows(shepard, values);
  const int dim = shepard.dim;
  const int n = shepard.points();
  t.dim = values.dim;
  t.order = 1;
  t.offsets = values.offsets;
  t.index = values.index;
  t.value = values.value;
  t.grad.assign(static_cast<std::size_t>(t.entries()) * dim, 0.0);
  t.hess.clear();
  if (degenerate) degenerate->cover(n);
  if (dim == 2)
    corrected_rows<Eigen::Matrix2d>(shepard, p, points, t, threads, degenerate);
  else
    corrected_rows<Eigen::MatrixXd>(shepard, p, points, t, threads, degenerate);
}

}  // namespace mfv
