/// Assembly of 2D linear elasticity from any method's gradient tables (001 Table 1 read as
/// B matrices): K = Σ_q w_q B^test_qᵀ D B^trial_q, tractions on the method's boundary rule.
///
/// K is built straight into its compressed column-major storage, in two passes over the
/// tables' sparsity (no triplets, no sparse-product temporaries, so the time per particle
/// does not grow with N):
///   symbolic: particle J couples with the particles I of the test rows of the points q in
///     J's trial support; the trial table transposed (the points of each particle) and a
///     marker array count them, which gives the column starts;
///   numeric: per J, the 2×2 blocks K_IJ = Σ_q w_q B^test_I(q)ᵀ D B^trial_J(q), with
///     B_J = [∂x N_J, 0; 0, ∂y N_J; ∂y N_J, ∂x N_J], accumulated in a dense workspace by the
///     sorted position of I, then written to columns 2J and 2J+1.
/// Each column is computed by one thread in a fixed order, so K is the same on any thread
/// count (OpenMP over particles). The particles are visited along a Hilbert curve of
/// their positions, not in index order: consecutive columns then read the table rows of one
/// small neighbourhood, which stays in cache, where a lattice numbered row by row would sweep
/// several whole rows of the lattice per column (megabytes beyond 10^4 particles; measured:
/// 9 % less user time for efg-ni at 10^5 and 10^6 particles, bench/README.md).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>
#include <omp.h>

#include "methods/core/errors.hpp"
#include "methods/core/parallel.hpp"
#include "methods/ordering.hpp"
#include "problems/problem.hpp"

namespace mfv {

namespace {

void check_gradient_table(const ShapeTable& t, int points, const char* which) {
  if (t.dim != 2 || t.grad.size() != static_cast<std::size_t>(t.entries()) * 2)
    throw std::logic_error("2D elasticity needs gradient tables of a 2D discretization");
  if (t.points() != points)
    throw std::logic_error(fmt::format("2D elasticity: the {} table has {} points, the quadrature "
                                       "rule {}",
                                       which, t.points(), points));
}

/// The order in which the assembly visits the particles: along the Hilbert curve of their
/// positions (methods/ordering.hpp, the curve the explicit engine's reorder=hilbert uses), or
/// by index when a position is not finite (the curve refuses those; the tables then carry the
/// NaNs to the solve's own non-finite check). Only the traversal order: K does not depend on it.
std::vector<int> visiting_order(const Eigen::MatrixXd& x) {
  if (x.allFinite()) return hilbert_order(x);
  std::vector<int> order(static_cast<std::size_t>(x.cols()));
  std::iota(order.begin(), order.end(), 0);
  return order;
}

/// A table's entries grouped by particle: for particle J, entries offsets[J]..offsets[J+1]-1
/// hold the points q (ascending) whose support holds J and the entry k of J in row q.
struct TransposedTable {
  std::vector<int> offsets;
  std::unique_ptr<int[]> point, entry;  // uninitialized until transpose writes them
};

/// Throws when an entry of `t` names no particle (an index outside 0..particles-1).
void check_particle_indices(const std::vector<int>& index, int particles) {
  for (const int J : index)
    if (J < 0 || J >= particles)
      throw std::logic_error(fmt::format("2D elasticity: a table names particle {} of {}", J,
                                         particles));
}

TransposedTable transpose(const ShapeTable& t, int particles) {
  TransposedTable tt;
  tt.offsets.assign(particles + 1, 0);
  for (const int J : t.index) ++tt.offsets[J + 1];
  for (int J = 0; J < particles; ++J) tt.offsets[J + 1] += tt.offsets[J];
  const std::size_t entries = t.index.size();
  tt.point.reset(new int[entries]);
  tt.entry.reset(new int[entries]);
  std::vector<int> next(tt.offsets.begin(), tt.offsets.end() - 1);
  for (int q = 0; q < t.points(); ++q)
    for (int k = t.offsets[q]; k < t.offsets[q + 1]; ++k) {
      const int slot = next[t.index[k]]++;
      tt.point[slot] = q;
      tt.entry[slot] = k;
    }
  return tt;
}

/// Calls visit(I) once for each particle I coupled with particle J (in the test support of a
/// point in J's trial support); `mark` holds per particle the last J that visited it (reused
/// across calls, so no clearing per J).
template <class Visit>
void for_each_coupled(int J, const TransposedTable& trial_t, const ShapeTable& test,
                      std::vector<int>& mark, Visit&& visit) {
  for (int p = trial_t.offsets[J]; p < trial_t.offsets[J + 1]; ++p) {
    const int q = trial_t.point[p];
    for (int k = test.offsets[q]; k < test.offsets[q + 1]; ++k) {
      const int I = test.index[k];
      if (mark[I] != J) {
        mark[I] = J;
        visit(I);
      }
    }
  }
}

/// The number of particles coupled with particle J (the symbolic pass).
int count_coupled(int J, const TransposedTable& trial_t, const ShapeTable& test,
                  std::vector<int>& mark) {
  int m = 0;
  for_each_coupled(J, trial_t, test, mark, [&m](int) { ++m; });
  return m;
}

/// The particles coupled with particle J, sorted (the numeric pass).
void coupled_particles(int J, const TransposedTable& trial_t, const ShapeTable& test,
                       std::vector<int>& mark, std::vector<int>& rows) {
  rows.clear();
  for_each_coupled(J, trial_t, test, mark, [&rows](int I) { rows.push_back(I); });
  std::sort(rows.begin(), rows.end());
}

/// Builds K in place: Eigen 3.4's SparseMatrix has no move assignment, so returning it and
/// assigning would copy every non-zero once more.
void stiffness(const Discretization& d, const Eigen::Matrix3d& D, Eigen::SparseMatrix<double>& K) {
  const int n = d.particles.size();
  const ShapeTable& trial = d.trial_q;
  const ShapeTable& test = d.test_q;
  const int nq = d.quadrature.size();
  check_gradient_table(trial, nq, "trial");
  check_gradient_table(test, nq, "test");
  check_particle_indices(trial.index, n);
  check_particle_indices(test.index, n);
  const TransposedTable trial_t = transpose(trial, n);
  const std::vector<int> order = visiting_order(d.particles.x);
  const double* w = d.quadrature.weights.data();
  const int threads = std::max(1, omp_get_max_threads());
  const bool parallel = run_parallel(threads, n);
  // Per-thread workspaces, allocated here: an exception (bad_alloc) may not leave a parallel
  // region, and none of the loops below allocates once these are sized.
  struct Workspace {
    std::vector<int> mark, slot, rows;
    std::vector<double> block;
  };
  std::vector<Workspace> work(parallel ? threads : 1);
  for (Workspace& ws : work) ws.mark.assign(n, -1);

  // Symbolic pass: the coupled particles of each J; columns 2J and 2J+1 hold 2 rows each.
  std::vector<std::int64_t> start(static_cast<std::size_t>(n) + 1, 0);
#pragma omp parallel num_threads(threads) if (parallel)
  {
    std::vector<int>& mark = work[omp_get_thread_num()].mark;
#pragma omp for schedule(dynamic, 256)
    for (int t = 0; t < n; ++t) start[order[t] + 1] = count_coupled(order[t], trial_t, test, mark);
  }
  std::int64_t widest = 0;
  for (int J = 0; J < n; ++J) {
    widest = std::max(widest, start[J + 1]);
    start[J + 1] += start[J];
  }
  const std::int64_t nnz = 4 * start[n];
  if (nnz > std::numeric_limits<int>::max())
    throw InputError(fmt::format("2D elasticity: K would have {} non-zeros, more than the 2^31 - 1 "
                                 "its indices address; lower --nodes or the support size",
                                 nnz));
  for (Workspace& ws : work) {
    ws.mark.assign(n, -1);  // the numeric pass visits each J again: no stale marks
    ws.slot.assign(n, 0);
    ws.rows.reserve(widest);
    ws.block.reserve(4 * widest);
  }

  K.resize(2 * n, 2 * n);
  K.resizeNonZeros(static_cast<Eigen::Index>(nnz));
  int* outer = K.outerIndexPtr();
  int* inner = K.innerIndexPtr();
  double* value = K.valuePtr();
  for (int J = 0; J < n; ++J) {
    const std::int64_t m = start[J + 1] - start[J];
    outer[2 * J] = static_cast<int>(4 * start[J]);
    outer[2 * J + 1] = static_cast<int>(4 * start[J] + 2 * m);
  }
  outer[2 * n] = static_cast<int>(nnz);

  // Numeric pass: column block J from the points of its trial support.
#pragma omp parallel num_threads(threads) if (parallel)
  {
    Workspace& ws = work[omp_get_thread_num()];
    std::vector<int>& mark = ws.mark;
    std::vector<int>& slot = ws.slot;
    std::vector<int>& rows = ws.rows;
    std::vector<double>& block = ws.block;
#pragma omp for schedule(dynamic, 256)
    for (int t = 0; t < n; ++t) {
      const int J = order[t];
      coupled_particles(J, trial_t, test, mark, rows);
      const int m = static_cast<int>(rows.size());
      for (int i = 0; i < m; ++i) slot[rows[i]] = i;
      block.assign(4 * static_cast<std::size_t>(m), 0.0);
      for (int p = trial_t.offsets[J]; p < trial_t.offsets[J + 1]; ++p) {
        const int q = trial_t.point[p];
        const int kJ = trial_t.entry[p];
        const double gx = trial.grad[2 * kJ], gy = trial.grad[2 * kJ + 1];
        // w_q D B_J(q): the stresses of unit u_x (a) and unit u_y (b) of particle J.
        const double a0 = w[q] * (D(0, 0) * gx + D(0, 2) * gy);
        const double a1 = w[q] * (D(1, 0) * gx + D(1, 2) * gy);
        const double a2 = w[q] * (D(2, 0) * gx + D(2, 2) * gy);
        const double b0 = w[q] * (D(0, 1) * gy + D(0, 2) * gx);
        const double b1 = w[q] * (D(1, 1) * gy + D(1, 2) * gx);
        const double b2 = w[q] * (D(2, 1) * gy + D(2, 2) * gx);
        for (int k = test.offsets[q]; k < test.offsets[q + 1]; ++k) {
          const double hx = test.grad[2 * k], hy = test.grad[2 * k + 1];
          double* b = &block[4 * static_cast<std::size_t>(slot[test.index[k]])];
          b[0] += hx * a0 + hy * a2;  // K(2I,   2J)
          b[1] += hy * a1 + hx * a2;  // K(2I+1, 2J)
          b[2] += hx * b0 + hy * b2;  // K(2I,   2J+1)
          b[3] += hy * b1 + hx * b2;  // K(2I+1, 2J+1)
        }
      }
      const std::size_t cx = static_cast<std::size_t>(outer[2 * J]);
      const std::size_t cy = static_cast<std::size_t>(outer[2 * J + 1]);
      for (int i = 0; i < m; ++i) {
        const int r = 2 * rows[i];
        inner[cx + 2 * i] = r;
        inner[cx + 2 * i + 1] = r + 1;
        value[cx + 2 * i] = block[4 * i];
        value[cx + 2 * i + 1] = block[4 * i + 1];
        inner[cy + 2 * i] = r;
        inner[cy + 2 * i + 1] = r + 1;
        value[cy + 2 * i] = block[4 * i + 2];
        value[cy + 2 * i + 1] = block[4 * i + 3];
      }
    }
  }
}

}  // namespace

AssembledSystem assemble_elasticity(const Discretization& d, const ElasticityBVP& bvp) {
  const int n = d.particles.size();
  AssembledSystem s;
  s.components = 2;
  stiffness(d, bvp.material.D(), s.K);
  s.f = Eigen::VectorXd::Zero(2 * n);
  if (bvp.body_force) {
    const Eigen::MatrixXd b = bvp.body_force(d.quadrature.points);
    const ShapeTable& t = d.test_q;
    for (int q = 0; q < t.points(); ++q)
      for (int k = t.offsets[q]; k < t.offsets[q + 1]; ++k)
        for (int c = 0; c < 2; ++c)
          s.f[2 * t.index[k] + c] += d.quadrature.weights[q] * t.value[k] * b(c, q);
  }
  for (const auto& [side, traction] : bvp.tractions) {
    const IntegrationRule b = d.boundary_rule(side);
    const ShapeTable t = d.test_on(b);
    const Eigen::MatrixXd tv = traction(b.points);
    for (int q = 0; q < b.size(); ++q)
      for (int k = t.offsets[q]; k < t.offsets[q + 1]; ++k)
        for (int c = 0; c < 2; ++c) s.f[2 * t.index[k] + c] += b.weights[q] * t.value[k] * tv(c, q);
  }
  // Essential conditions at the particles of each clamped side (their projections onto the
  // side): both components.
  std::vector<double> px, py, val;
  for (const auto& [side, disp] : bvp.displacements) {
    const IntegrationRule b = nodal_boundary_rule(d.domain, d.particles, side);
    // Particle-value methods fix the particle itself, at its own position.
    Eigen::MatrixXd at = b.points;
    if (d.particle_values)
      for (int q = 0; q < b.size(); ++q) at.col(q) = d.particles.x.col(b.cell[q]);
    const Eigen::MatrixXd g = disp(at);
    for (int q = 0; q < b.size(); ++q)
      for (int c = 0; c < 2; ++c) {
        // A corner particle on two clamped sides is constrained once (a repeated constraint
        // would make the multiplier system singular).
        bool repeated = false;
        for (std::size_t i = 0; i < val.size() && !repeated; ++i)
          repeated = s.constraint_particles[i] == b.cell[q] && s.constraint_components[i] == c &&
                     px[i] == at(0, q) && py[i] == at(1, q);
        if (repeated) continue;
        px.push_back(at(0, q));
        py.push_back(at(1, q));
        val.push_back(g(c, q));
        s.constraint_components.push_back(c);
        s.constraint_particles.push_back(b.cell[q]);
      }
  }
  // A clamp that covers the supports: every particle whose support reaches a clamped side (a
  // non-zero trial function at the side's particle projections or at its Gauss points) is
  // held at the prescribed displacement at its own position, so that no free particle's
  // support is cut by the clamp.
  for (const int side : bvp.clamp_supports) {
    const auto disp = bvp.displacements.find(side);
    if (disp == bvp.displacements.end())
      throw InputError(fmt::format("2D elasticity: side {} clamps the supports but has no "
                                   "prescribed displacement",
                                   side));
    std::vector<bool> held(n, false), reaches(n, false);
    for (const int I : s.constraint_particles) held[I] = true;
    for (const IntegrationRule& b :
         {nodal_boundary_rule(d.domain, d.particles, side), d.boundary_rule(side)}) {
      const ShapeTable t = d.trial_at(b.points, 0);
      for (int k = 0; k < t.entries(); ++k)
        if (t.value[k] != 0) reaches[t.index[k]] = true;
    }
    std::vector<int> extra;
    for (int I = 0; I < n; ++I)
      if (reaches[I] && !held[I]) extra.push_back(I);
    const Eigen::Index m = static_cast<Eigen::Index>(extra.size());
    Eigen::MatrixXd at(2, m);
    for (Eigen::Index i = 0; i < m; ++i) at.col(i) = d.particles.x.col(extra[i]);
    const Eigen::MatrixXd g = disp->second(at);
    for (Eigen::Index i = 0; i < m; ++i)
      for (int c = 0; c < 2; ++c) {
        px.push_back(at(0, i));
        py.push_back(at(1, i));
        val.push_back(g(c, i));
        s.constraint_components.push_back(c);
        s.constraint_particles.push_back(extra[i]);
      }
  }
  s.constraint_points.resize(2, static_cast<Eigen::Index>(px.size()));
  for (std::size_t i = 0; i < px.size(); ++i) s.constraint_points.col(i) << px[i], py[i];
  s.constraint_values = Eigen::Map<Eigen::VectorXd>(val.data(), static_cast<Eigen::Index>(val.size()));
  return s;
}

}  // namespace mfv
