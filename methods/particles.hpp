/// Particle sets: positions, integration volumes (Voronoi cells) and dilations (support sizes).
#pragma once
#include <cstdint>
#include <vector>

#include <Eigen/Dense>

namespace mfv {

/// Axis-aligned box domain [lower, upper].
struct Domain {
  int dim = 1;
  Eigen::VectorXd lower, upper;
  static Domain interval(double a, double b);
  double measure() const;
};

struct ParticleSet {
  int dim = 1;
  Eigen::MatrixXd x;          ///< dim × N positions
  Eigen::VectorXd volume;     ///< Voronoi volume ΔV_J (1D: half the distance to each neighbour)
  Eigen::VectorXd dilation;   ///< support scale a_J: the kernel argument is |x - x_J| / a_J
  double spacing = 0;         ///< nominal Δx of the lattice the set was built from

  int size() const { return static_cast<int>(x.cols()); }
};

/// N equally spaced particles on [a, b] (both ends included), optionally perturbed by
/// uniform random offsets of ±perturbation·Δx on interior particles (seeded, reproducible);
/// volumes from the 1D Voronoi diagram (the trapezoidal rule of 004 II §6).
ParticleSet uniform_line(const Domain& domain, int n, double perturbation = 0.0,
                         std::uint64_t seed = 1);

/// Recomputes 1D Voronoi volumes for sorted positions.
Eigen::VectorXd voronoi_volumes_1d(const Eigen::VectorXd& sorted_x, double a, double b);

}  // namespace mfv
