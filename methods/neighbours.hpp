/// Neighbour search over particles with nanoflann's k-d tree (O(N log N) build, O(log N + k)
/// radius queries), used by every kernel approximation; and Verlet lists on top of it for
/// points and particles that move (Eulerian kernels): candidates within r + s (s the skin),
/// still complete while every |x_q − x_q⁰| + |x_J − x_J⁰| ≤ s, since then
/// |x_q − x_J| ≤ r implies |x_q⁰ − x_J⁰| ≤ r + s (Allen & Tildesley, Computer Simulation of
/// Liquids, §5.3.1; with the points the particles themselves the test is 2·max|Δx| ≤ s).
#pragma once
#include <memory>
#include <span>
#include <vector>

#include <Eigen/Dense>

#include "methods/particles.hpp"

namespace mfv {

class NeighbourSearch {
 public:
  explicit NeighbourSearch(const ParticleSet& particles);
  ~NeighbourSearch();
  NeighbourSearch(const NeighbourSearch&) = delete;
  NeighbourSearch& operator=(const NeighbourSearch&) = delete;

  /// Indices of particles within Euclidean distance `radius` of `point`, ascending index.
  void within(const double* point, double radius, std::vector<int>& out) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Verlet (skin) lists: for each point q the particles within r + skin of it when the lists
/// were built, ascending index. `update` rebuilds them (one k-d tree search) only when the
/// radius grew, the counts changed, or the largest point move plus the largest particle move
/// since the build exceeds the skin; the caller then filters the candidates by its exact
/// support test, so the neighbour sets are those of a fresh search whatever the skin.
/// skin = 0 rebuilds whenever anything moved (the plain search, for reference runs).
class NeighbourLists {
 public:
  /// `skin` in length units, >= 0 and finite (InputError otherwise).
  explicit NeighbourLists(double skin = 0);

  /// Makes the lists valid for `points` (dim × nq) against `particles` (dim × N) and search
  /// radius `radius`; returns whether they were rebuilt. `threads` OpenMP threads search.
  bool update(const Eigen::MatrixXd& particles, const Eigen::MatrixXd& points, double radius,
              int threads = 1);
  /// Candidate particles of point q, ascending index.
  std::span<const int> candidates(int q) const {
    return {index_.data() + offsets_[q], index_.data() + offsets_[q + 1]};
  }
  int points() const { return static_cast<int>(offsets_.size()) - 1; }
  double skin() const { return skin_; }
  long rebuilds() const { return rebuilds_; }

 private:
  double skin_ = 0, radius_ = -1;
  long rebuilds_ = 0;
  Eigen::MatrixXd particles0_, points0_;  ///< positions at the last build
  std::vector<int> offsets_{0}, index_;
};

}  // namespace mfv
