/// Crack enrichment of a meshfree approximation (003 §3, the extended EFG): a decorator that
/// appends enriched columns to any approximation's shape table, and the Gauss-cell rule whose
/// cells are split at the crack.
///
/// 003 eq 8: u^h(X) = Σ_I Φ_I u_I + Σ_{I∈W_b} Φ_I H(f(X)) a_I + Σ_{I∈W_s} Φ_I Σ_K B_K b_KI,
/// H = ±1 on either side of the crack (eq 9, signed by f = n·(X − X_crack), eq 10); W_b: nodes
/// whose support the crack cuts completely, W_s: nodes whose support holds the crack tip. 003
/// does not write B_K out; we take the LEFM branch functions of Belytschko & Black / Moës et
/// al. (003 cites both): B = √r {sin θ/2, cos θ/2, sin θ/2 sin θ, cos θ/2 sin θ} in polar
/// coordinates (r, θ) about the tip, θ = 0 ahead of it, θ = ±π on the crack faces.
///
/// Unknown layout: columns 0..N−1 are the particles' (the wrapped approximation's), column
/// N + e is enrichment e of `EnrichedApproximation::enrichments` (one unknown per column and
/// field component, like a particle's).
#pragma once
#include <limits>
#include <memory>
#include <vector>

#include "methods/approximations/approximation.hpp"
#include "methods/integration/integration.hpp"

namespace mfv {

/// A straight crack: 1D a point; 2D a vertical segment x = position from below the domain up
/// to its tip (003 §4.3.1's experiments move a crack across a patch, through it or with a tip).
struct Crack {
  int dim = 1;
  double position = 0;  ///< 1D: the crack point; 2D: the abscissa of the crack line
  double tip = std::numeric_limits<double>::infinity();  ///< 2D: y of the tip (∞: through)
  bool branch = false;  ///< 2D: tip-enrich the nodes whose support holds the tip (W_s)

  bool has_tip() const { return dim == 2 && tip < std::numeric_limits<double>::infinity(); }
  /// Signed side of x (eq 10's f, without the distance): > 0 right of the crack.
  double side(const double* x) const { return x[0] - position; }
};

enum class EnrichmentKind { step, branch1, branch2, branch3, branch4 };

/// One enriched column: the particle whose shape function it multiplies and the function.
struct Enrichment {
  int node = 0;
  EnrichmentKind kind = EnrichmentKind::step;
};

/// Which nodes the crack enriches, given their supports |x − x_I| < a_I·support: step for a
/// support the crack crosses completely (W_b), four branch functions for one that holds the
/// tip when crack.branch (W_s), nothing otherwise (a tip inside a support without branch
/// functions leaves that node unenriched: the opening then closes smoothly ahead of the tip).
std::vector<Enrichment> crack_enrichments(const Crack& crack, const ParticleSet& particles,
                                          double kernel_support);

/// Decorator: the wrapped approximation's N_J plus ψ_e(x) N_{I(e)}(x) for every enrichment.
/// Gradients ψ ∇N + N ∇ψ (∇H = 0 off the crack); second derivatives for step columns only.
class EnrichedApproximation final : public Approximation {
 public:
  EnrichedApproximation(std::shared_ptr<const Approximation> base, Crack crack,
                        double kernel_support);
  ShapeTable evaluate(const ParticleSet& particles, const Eigen::MatrixXd& points,
                      int order) const override;
  int minimum_support_count(int dim) const override { return base_->minimum_support_count(dim); }
  int reproduction_order() const override { return base_->reproduction_order(); }
  std::vector<Enrichment> enrichments(const ParticleSet& particles) const {
    return crack_enrichments(crack_, particles, kernel_support_);
  }
  const Crack& crack() const { return crack_; }

 private:
  std::shared_ptr<const Approximation> base_;
  Crack crack_;
  double kernel_support_;
};

/// Gauss cells between the particles (1D) or the lattice quadrilaterals of a boundary-placed
/// rectangular lattice (2D), n (n×n) points per cell, with every cell the crack crosses split
/// at the crack into two cells of n (n×n) points each (003 §3: cut cells are subdivided so
/// that no Gauss point straddles the jump). IntegrationRule::cell names the parent cell.
class CrackCellScheme final : public IntegrationScheme {
 public:
  CrackCellScheme(Crack crack, int n, std::shared_ptr<const IntegrationScheme> boundary)
      : crack_(crack), n_(n), boundary_(std::move(boundary)) {}
  IntegrationRule rule(const Domain& domain, const ParticleSet& particles) const override;
  IntegrationRule boundary_rule(const Domain& domain, const ParticleSet& particles,
                                int side) const override {
    return boundary_->boundary_rule(domain, particles, side);
  }

 private:
  Crack crack_;
  int n_;
  std::shared_ptr<const IntegrationScheme> boundary_;
};

}  // namespace mfv
