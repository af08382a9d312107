/// `elastic-patch`: the displacement patch test of 2D elasticity: a linear field u = A x + b
/// prescribed on the whole boundary of the unit square, no body force; a method passes when
/// it reproduces the field inside to round-off (Krongauz & Belytschko; 001 §3.3).
#include <fmt/format.h>

#include "problems/problem.hpp"

namespace mfv {

namespace {

class ElasticPatch final : public BoundaryValueProblem {
 public:
  ElasticPatch() {
    material_.E = 1.0;
    material_.nu = 0.25;
  }
  Domain domain() const override { return Domain::rectangle(0, 0, 1, 1); }
  int components() const override { return 2; }
  std::string resolution_name() const override { return "particles per side"; }

  ParticleSet particles(int n, double perturbation) const override {
    if (n < 3)
      throw InputError(fmt::format("elastic-patch: nodes = particles per side, at least 3, got {}", n));
    return rectangle_lattice(domain(), n, n, Placement::boundary, perturbation, 11);
  }

  void exact_field(const Eigen::MatrixXd& X, Eigen::MatrixXd& u,
                   Eigen::MatrixXd& g) const override {
    // u_x = 0.1 + 0.2x + 0.3y, u_y = -0.1 + 0.15x - 0.25y: every strain component non-zero.
    u.resize(2, X.cols());
    g.resize(4, X.cols());
    for (Eigen::Index i = 0; i < X.cols(); ++i) {
      u(0, i) = 0.1 + 0.2 * X(0, i) + 0.3 * X(1, i);
      u(1, i) = -0.1 + 0.15 * X(0, i) - 0.25 * X(1, i);
      g.col(i) << 0.2, 0.3, 0.15, -0.25;
    }
  }

  AssembledSystem assemble(const Discretization& d) const override {
    ElasticityBVP bvp;
    bvp.material = material_;
    for (int side = 0; side < 4; ++side)
      bvp.displacements[side] = [this](const Eigen::MatrixXd& X) {
        Eigen::MatrixXd u, g;
        exact_field(X, u, g);
        return u;
      };
    return assemble_elasticity(d, bvp);
  }

  /// The energy norm's integrand σ(∇v):ε(∇v) and the stress (Voigt xx, yy, xy) for VTK
  /// files, of the patch's material rather than the default gradient.
  Eigen::VectorXd energy_density(const Eigen::MatrixXd& grad) const override {
    return material_.energy_density(grad);
  }
  Eigen::MatrixXd flux(const Eigen::MatrixXd& grad) const override { return material_.stress(grad); }
  std::vector<std::string> flux_names() const override { return {"sxx", "syy", "sxy"}; }

  IntegrationRule common_error_rule(const ParticleSet& p) const override {
    return uniform_gauss_rule_2d(domain(), 20, 20, 4);
  }
  bool errors_on_method_rule() const override { return true; }
  std::vector<int> resolutions(Level) const override { return {5, 9}; }

 private:
  LinearElastic material_;
};

}  // namespace

void register_elastic_patch(ProblemRegistry& r) {
  r.add("elastic-patch",
        "displacement patch test: linear field on the unit square, all sides prescribed "
        "(nodes = particles per side)",
        {}, [](const Params&) { return std::make_unique<ElasticPatch>(); });
}

}  // namespace mfv
