/// Neighbour search over particles with nanoflann's k-d tree (O(N log N) build, O(log N + k)
/// radius queries), used by every kernel approximation.
#pragma once
#include <memory>
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

}  // namespace mfv
