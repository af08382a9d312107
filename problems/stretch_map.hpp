/// The `stretch-map` problem as a definition: a 2D lattice of the rubber of 000 eq 5.1 /
/// 001 eq 18 under homogeneous principal stretches (λ1, λ2) on a grid, the kernel frames to
/// compare and the directions sampled (001 Fig. 1). The `stretch-map` analysis runs it.
#pragma once
#include <string>
#include <vector>

#include "problems/problem.hpp"
#include "stability/lattice.hpp"

namespace mfv {

/// Headline values of a stretch-map case.
namespace stretch_map_headline {
inline constexpr int kBreakdown = -2;  ///< no discrete model: the kernel support lost its particles
inline constexpr const char* kStates = "states";
inline constexpr const char* kPdeStable = "PDE-stable states";
inline constexpr const char* kLagStable = "Lagrangian-stable states";
inline constexpr const char* kEulStable = "Eulerian-stable states";
inline constexpr const char* kPdeNotLag = "states PDE-stable but Lagrangian-unstable";
inline constexpr const char* kPdeNotEul = "states PDE-stable but Eulerian-unstable";
inline constexpr const char* kLagNotPde = "states PDE-unstable but Lagrangian-stable";
inline constexpr const char* kEulNotPde = "states PDE-unstable but Eulerian-stable";
inline constexpr const char* kLagBreak = "states without a Lagrangian discretization";
inline constexpr const char* kEulBreak = "states without an Eulerian discretization";
inline constexpr const char* kLagAgree = "fraction of states where Lagrangian agrees with PDE";
inline constexpr const char* kEulAgree = "fraction of states where Eulerian agrees with PDE";

}  // namespace stretch_map_headline

/// The states and the lattice a stretch-map case analyses.
struct StretchMapDefinition {
  LatticeKind lattice = LatticeKind::rectangular;
  double lambda_min = 0.5, lambda_max = 2;
  int grid = 2;  ///< states per stretch axis
  bool lagrangian = true, eulerian = true;
  std::vector<double> angles;  ///< wave directions θ in degrees
  int points = 3;              ///< wave numbers per direction
  double density = 1;
  Params material_params;      ///< the rubber's c1, c2, lambda
  double mu0 = 1;              ///< initial shear modulus c1 + c2
  /// The i-th stretch of the grid.
  double stretch(int i) const { return lambda_min + (lambda_max - lambda_min) * i / (grid - 1); }
};

class StretchMapProblem final : public Problem {
 public:
  explicit StretchMapProblem(const Params& p);
  const StretchMapDefinition& definition() const { return def_; }
  Domain domain() const override { return Domain::rectangle(-1, -1, 1, 1); }
  std::vector<std::string> analyses() const override { return {"stretch-map"}; }
  std::string resolution_name() const override {
    return "states per stretch axis (the grid parameter)";
  }
  std::vector<int> resolutions(Level) const override { return {def_.grid}; }
  std::vector<std::string> published_notes() const override;
  std::vector<Finding> findings() const override;

 private:
  StretchMapDefinition def_;
};

}  // namespace mfv
