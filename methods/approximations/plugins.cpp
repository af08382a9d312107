/// Registrations of the moment-corrected family: each line composes basis × weight × correction.
#include <fmt/format.h>

#include "methods/approximations/register.hpp"
#include "methods/kernels/kernel_choice.hpp"

namespace mfv {

namespace {

/// The kernel choice (methods/kernels/kernel_choice.hpp) followed by `more`.
ParamSchema with_kernel_choice(const KernelRegistry& k, std::string def, ParamSchema more = {}) {
  ParamSchema s = kernel_choice(k, std::move(def), "weight function W(s)");
  for (auto& spec : more) s.push_back(std::move(spec));
  return s;
}

std::unique_ptr<Approximation> corrected(const KernelRegistry& k, const Params& p,
                                         CorrectedKernelOptions o, const std::string& name) {
  std::shared_ptr<const Kernel> w = make_kernel(k, p);
  return std::make_unique<CorrectedKernelApproximation>(std::move(w), o, name);
}

/// "linear-fe" in either dimension: the particles' dimension picks 1D hats or 2D Q4.
class LinearFiniteElements final : public Approximation {
 public:
  ShapeTable evaluate(const ParticleSet& particles, const Eigen::MatrixXd& points,
                      int order) const override {
    return particles.dim == 2 ? q4_.evaluate(particles, points, order)
                              : hats_.evaluate(particles, points, order);
  }
  int minimum_support_count(int dim) const override {
    return dim == 2 ? q4_.minimum_support_count(dim) : hats_.minimum_support_count(dim);
  }
  bool interpolating() const override { return true; }
  int reproduction_order() const override { return 1; }

 private:
  LinearElementApproximation hats_;
  BilinearElementApproximation q4_;
};

}  // namespace

void register_shepard(ApproximationRegistry& r, const KernelRegistry& k) {
  r.add("shepard", "Shepard function N_J = w_J / sum w (000 eq 2.5, 001 eq 28)",
        with_kernel_choice(k, "quartic-spline"), [&k](const Params& p) {
          return corrected(k, p, {.basis_order = 0}, "shepard");
        });
}

void register_mls(ApproximationRegistry& r, const KernelRegistry& k) {
  r.add("mls", "moving least squares, linear or quadratic basis (EFG; 001 eqs 37-43)",
        with_kernel_choice(k, "cubic-window",
                           {ParamSpec::count("basis", 1, 0, "polynomial order of the basis (0, 1, 2)"),
                            ParamSpec::choice("derivative", "exact", {"exact", "diffuse"},
                                              "exact (001 eq 43) or diffuse/DEM (004 II eq 6.5)")}),
        [&k](const Params& p) {
          if (p.integer("basis") > 2)
            throw InputError("parameter 'basis' of approximation 'mls' must be 0, 1 or 2");
          return corrected(k, p,
                           {.basis_order = p.integer("basis"),
                            .diffuse_derivative = p.text("derivative") == "diffuse"},
                           "mls");
        });
}

void register_rkpm_approximation(ApproximationRegistry& r, const KernelRegistry& k) {
  r.add("rkpm",
        "reproducing kernel N_J = [C1 + C2 (x-x_J)/a] a^-1 Phi dV_J, trapezoidal moments "
        "(004 II eqs 6.1-6.2; DEM derivative eq 6.6)",
        with_kernel_choice(k, "gaussian",
                           {ParamSpec::choice("derivative", "exact", {"exact", "diffuse"},
                                              "exact (004 II eq 6.2) or DEM approximation (eq 6.6)")}),
        [&k](const Params& p) {
          return corrected(k, p,
                           {.basis_order = 1, .volume_weighted = true,
                            .diffuse_derivative = p.text("derivative") == "diffuse"},
                           "rkpm");
        });
}

void register_sph_approximation(ApproximationRegistry& r, const KernelRegistry& k) {
  r.add("sph", "SPH kernel estimate N_J = W(x - x_J) dV_J, no correction (004 II eq 2.6b)",
        with_kernel_choice(k, "gaussian"), [&k](const Params& p) {
          return corrected(k, p,
                           {.basis_order = 0, .correct = false, .volume_weighted = true,
                            .normalize_kernel = true},
                           "sph");
        });
}

void register_linear_elements(ApproximationRegistry& r, const KernelRegistry&) {
  r.add("linear-fe",
        "linear finite elements on the particles: hat functions in 1D, bilinear Q4 on a 2D "
        "lattice",
        {}, [](const Params&) { return std::make_unique<LinearFiniteElements>(); });
}

}  // namespace mfv
