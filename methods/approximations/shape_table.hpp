/// Shape functions N_J and their derivatives at a batch of points, stored row-compressed
/// (one row per point, one entry per particle J whose support covers the point).
#pragma once
#include <algorithm>
#include <vector>

#include <Eigen/Dense>

namespace mfv {

struct ShapeTable {
  int dim = 1;
  int order = 0;                ///< highest derivative order stored (0, 1 or 2)
  std::vector<int> offsets{0};  ///< row starts, size points()+1
  std::vector<int> index;       ///< particle J of each entry
  std::vector<double> value;    ///< N_J(x)
  std::vector<double> grad;     ///< ∂N_J/∂x_i, dim per entry
  std::vector<double> hess;     ///< ∂²N_J/∂x_i∂x_j, dim·dim per entry (row-major)

  int points() const { return static_cast<int>(offsets.size()) - 1; }
  int entries() const { return static_cast<int>(index.size()); }
  int nhess() const { return dim * dim; }

  /// Σ_J N_J(x_q) u_J for every point q (u: one scalar per particle).
  Eigen::VectorXd interpolate(const Eigen::VectorXd& u) const;
  /// Σ_J ∂N_J/∂x_d (x_q) u_J.
  Eigen::VectorXd interpolate_derivative(const Eigen::VectorXd& u, int d = 0) const;
  /// Σ_J ∂²N_J/∂x_d∂x_d (x_q) u_J.
  Eigen::VectorXd interpolate_second_derivative(const Eigen::VectorXd& u, int d = 0) const;
  /// A field of `components` per particle, interleaved in u (u_x, u_y of particle 0, ...):
  /// values (components × points) and, when the table holds them, gradients
  /// (components·dim × points; row c·dim + d is ∂u_c/∂x_d).
  void field(const Eigen::VectorXd& u, int components, Eigen::MatrixXd& values,
             Eigen::MatrixXd& gradients) const;
};

/// Where a point's support is degenerate (too few or collinear particles for a correction)
/// and the caller asked for a fallback instead of a SingularError (Eulerian recomputations
/// with Retabulation::degenerate_fallback): a table builder handed one falls back as its
/// header says and marks the point here. The builders of several tables at the same points
/// share one, so a point counts once however many of its tables fell back.
struct DegenerateMarks {
  std::vector<char> marked;  ///< one per evaluation point: 1 where a fallback was taken

  /// Grows (never clears) to n points; called before a parallel loop over them, in which
  /// point q is marked only by the thread that evaluates it.
  void cover(int n) {
    if (static_cast<int>(marked.size()) < n) marked.resize(n, 0);
  }
  void mark(int q) { marked[q] = 1; }
  long count() const { return static_cast<long>(std::count(marked.begin(), marked.end(), 1)); }
};

}  // namespace mfv
