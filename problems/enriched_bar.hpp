/// The `enriched-bar` problem as a definition (003, Samaniego et al.): a 1D bar of particles
/// 1 m apart (E = 200 GPa, ρ = 7850) or a 2D square patch, the node interval a crack is swept
/// through, the crack tip, and the sweep's settings (DMAX values, positions, mass schemes).
/// The `crack-sweep` analysis (analyses/crack_sweep.cpp) runs it with the extended EFG.
#pragma once
#include <string>
#include <vector>

#include "problems/problem.hpp"
#include "stability/enriched_mass.hpp"

namespace mfv {

/// The bar or patch a crack-sweep case sweeps a crack through.
struct EnrichedBarDefinition {
  int dim = 1;        ///< 1: the 003 bar; 2: the square patch (003 §4.3.1)
  int n = 10;         ///< particles per side
  int interval = 4;   ///< the node interval the crack is moved through
  double tip = 0.9;   ///< 2D: relative y of the tip (003 §4.3.1: "relative position of y = 0.9")
  /// What the tip's relative y is relative to: the middle row of cells (false) or the patch's
  /// height (true); 003 does not say.
  bool tip_in_patch = false;
  /// The tip's y: inside the middle row of cells, or tip·(n − 1) over the patch.
  double tip_y() const { return tip_in_patch ? tip * (n - 1) : (n / 2 - 1) + tip; }
  BarMaterial material;
  /// The problem's resolved parameters: the sweep's settings (dmax, dmax_count, dmax_step,
  /// positions, mass, mls1, tip, fit ...).
  Params sweep;
  Domain domain() const {
    const double L = n - 1.0;
    return dim == 1 ? Domain::interval(0, L) : Domain::rectangle(0, 0, L, L);
  }
};

class EnrichedBarProblem final : public Problem {
 public:
  explicit EnrichedBarProblem(const Params& p);
  const EnrichedBarDefinition& definition() const { return def_; }
  Domain domain() const override { return def_.domain(); }
  std::vector<std::string> analyses() const override { return {"crack-sweep"}; }
  std::vector<int> resolutions(Level) const override { return {def_.n}; }
  std::vector<PublishedValue> published() const override;
  std::vector<Finding> findings() const override;
  std::vector<std::string> published_notes() const override;

 private:
  EnrichedBarDefinition def_;
};

}  // namespace mfv
