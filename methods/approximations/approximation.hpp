/// Approximations: shape functions N_J(x) and derivatives built from particles. One virtual
/// call evaluates a whole batch of points.
#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include <Eigen/Dense>

#include "methods/approximations/shape_table.hpp"
#include "methods/core/registry.hpp"
#include "methods/kernels/kernel.hpp"
#include "methods/neighbours.hpp"
#include "methods/particles.hpp"

namespace mfv {

class Approximation {
 public:
  virtual ~Approximation() = default;
  /// Shape functions and derivatives up to `order` (0..2) at the columns of `points`.
  /// Throws SingularError naming the point when a moment matrix cannot be inverted.
  virtual ShapeTable evaluate(const ParticleSet& particles, const Eigen::MatrixXd& points,
                              int order) const = 0;
  /// evaluate() into `out` in place (its vectors' storage reused), for recomputations at moved
  /// positions (Eulerian kernels): the neighbour candidates come from `lists`, updated here
  /// (rebuilt only when the particles or points moved past its skin), and the points are
  /// spread over `threads` OpenMP threads. The table equals evaluate()'s bit for bit, on any
  /// thread count. With `degenerate` (Eulerian recomputations that asked for it) a point
  /// whose support is too small or singular for the approximation falls back instead of
  /// throwing, and is marked there; what it falls back to is the approximation's to say.
  /// The default calls evaluate(), ignores the lists and offers no fallback.
  virtual void evaluate_into(const ParticleSet& particles, const Eigen::MatrixXd& points,
                             int order, NeighbourLists& lists, int threads, ShapeTable& out,
                             DegenerateMarks* degenerate = nullptr) const {
    out = evaluate(particles, points, order);
  }
  /// Fewest particles a point's support must hold (the size of the polynomial basis).
  virtual int minimum_support_count(int dim) const = 0;
  /// Whether N_J(x_I) = δ_IJ (then essential conditions can be imposed directly).
  virtual bool interpolating() const { return false; }
  /// Whether Σ N_J reproduces linear fields (consistency the tests hold it to).
  virtual int reproduction_order() const = 0;
};

/// How a moment-corrected kernel approximation is put together (Medusa's WLS<basis, weight,
/// correction> in one struct): basis order, weight, whether particle volumes enter the
/// weights (RKPM, SPH) or not (MLS), and how derivatives are taken.
struct CorrectedKernelOptions {
  int basis_order = 1;            ///< 0: Shepard, 1: linear (EFG/RKPM), 2: quadratic
  bool correct = true;            ///< false: plain kernel sum (SPH), no moment matrix
  bool volume_weighted = false;   ///< weights carry ΔV_J (RKPM eq 6.1a) or not (MLS eq 6.3)
  bool normalize_kernel = false;  ///< divide W by its integral (SPH needs ∫W = 1)
  bool diffuse_derivative = false;///< DEM/diffuse derivative: only the basis is differentiated (004 II eq 6.6)
};

/// Basis × weight × correction: N_J(x) = p(x)ᵀ M(x)⁻¹ p(x_J) w_J(x), M = Σ_J w_J p(x_J) p(x_J)ᵀ
/// (the moment matrix, 004 II eq 3.3 / 001 eq 40), w_J = W(|x - x_J|/a_J)/a_J^d [ΔV_J].
///
/// Degenerate supports (evaluate_into with `degenerate`, Eulerian recomputations only): where
/// the support holds fewer particles than the basis or the moment matrix fails the rcond test
/// (1e-13, the one that throws otherwise), the point takes the Shepard functions of the same
/// weights, N_J = w_J / Σ w (basis 1; their exact derivatives, also for the diffuse option),
/// so the partition of unity still holds there: splashes keep zero-order consistency instead
/// of ending the run, as production SPH codes fall back to the uncorrected kernel. Where Σ w
/// is zero or not a normal number (an empty support; for the uncorrected sph kernel sum, only
/// this) the row is zero: the point takes part in no sum.
class CorrectedKernelApproximation final : public Approximation {
 public:
  CorrectedKernelApproximation(std::shared_ptr<const Kernel> kernel, CorrectedKernelOptions opts,
                               std::string name);
  ShapeTable evaluate(const ParticleSet& particles, const Eigen::MatrixXd& points,
                      int order) const override;
  void evaluate_into(const ParticleSet& particles, const Eigen::MatrixXd& points, int order,
                     NeighbourLists& lists, int threads, ShapeTable& out,
                     DegenerateMarks* degenerate = nullptr) const override;
  int minimum_support_count(int dim) const override;
  int reproduction_order() const override { return options_.correct ? options_.basis_order : -1; }
  /// The search radius of a point: the kernel's support times the largest dilation.
  double search_radius(const ParticleSet& particles) const;
  const Kernel& kernel() const { return *kernel_; }

  /// From this many particles a table whose points' supports hold more than kDenseFraction of
  /// them on average is refused as dense: a meshfree support spans a few spacings, and a
  /// support over the whole body (radius=100 on a 1,701-particle cantilever took 206 s and
  /// 2.7 GB) is a mistake in the input, not a case.
  static constexpr std::int64_t kDenseFromParticles = 1000;
  static constexpr double kDenseFraction = 0.25;

 private:
  /// Refuses (InputError with the estimate) a table of `entries` entries at `points` points
  /// that is dense, overflows the int offsets, or needs more memory than is available.
  void check_table_size(std::int64_t entries, int points, const ParticleSet& particles,
                        int order) const;
  struct PointEvaluator;  // one point's row; corrected_kernel.cpp
  std::shared_ptr<const Kernel> kernel_;
  CorrectedKernelOptions options_;
  std::string name_;
};

/// Piecewise-linear hat functions on the particles taken as 1D element nodes (FEM).
class LinearElementApproximation final : public Approximation {
 public:
  ShapeTable evaluate(const ParticleSet& particles, const Eigen::MatrixXd& points,
                      int order) const override;
  int minimum_support_count(int) const override { return 2; }
  bool interpolating() const override { return true; }
  int reproduction_order() const override { return 1; }
};

/// Bilinear (Q4) elements on a 2D particle lattice: element (i, j) has the particles
/// (i,j), (i+1,j), (i+1,j+1), (i,j+1) (J = i + nx·j) as nodes, perturbed lattices give general
/// convex quadrilaterals, mapped isoparametrically from [-1, 1]².
class BilinearElementApproximation final : public Approximation {
 public:
  ShapeTable evaluate(const ParticleSet& particles, const Eigen::MatrixXd& points,
                      int order) const override;
  int minimum_support_count(int) const override { return 4; }
  bool interpolating() const override { return true; }
  int reproduction_order() const override { return 1; }
};

}  // namespace mfv
