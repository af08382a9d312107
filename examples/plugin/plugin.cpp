/// An mfv plugin in its own repository: one kernel and one problem, built against an
/// installed mfv (CMakeLists.txt here) and loaded by `mfv --plugin libmfv_example_plugin.so`
/// or a manifest's `[suite] plugins`. Read it as numbered steps.
#include <cmath>

#include "apps/plugin.hpp"

namespace example {

// 1. A kernel: the quadratic kernel of Johnson, Stryk & Beissel (1996),
//    W(s) = 3/16 s² − 3/4 s + 3/4 for s ≤ 2, which, unlike the cubic spline, keeps its slope
//    growing as particles approach (no tensile clumping in compression). KernelFormula turns
//    the scalar formula into mfv's batch kernel.
class JohnsonQuadratic final : public mfv::KernelFormula<JohnsonQuadratic> {
 public:
  void formula(double s, double& w, double& dw, double& d2w) const {
    w = 3.0 / 16 * s * s - 0.75 * s + 0.75;
    dw = 3.0 / 8 * s - 0.75;
    d2w = 3.0 / 8;
  }
  double support() const override { return 2.0; }
  // ∫ W(|x|) dx over R^d: 1 in 1D, π/2 in 2D, 4π/5 in 3D, so C = 1, 2/π, 5/(4π) normalize
  // it; SPH divides by this integral in the problem's dimension, so W itself stays unscaled.
  double integral(int dim) const override {
    return dim == 1 ? 1.0 : dim == 2 ? M_PI / 2 : 0.8 * M_PI;
  }
};

void register_kernels(mfv::KernelRegistry& r) {
  r.add("johnson-quadratic",
        "quadratic kernel 3/16 s^2 - 3/4 s + 3/4, support s<=2 (Johnson, Stryk & Beissel 1996; "
        "example plugin)",
        {}, [](const mfv::Params&) { return std::make_unique<JohnsonQuadratic>(); });
}

// 2. A problem: −u'' = π² sin(πx) on [0, 1] with u(0) = u(1) = 0, exact u = sin(πx). The
//    analyses, norms, rates and reports of mfv work on it unchanged.
class SineBar final : public mfv::ScalarProblem {
 public:
  mfv::Domain domain() const override { return mfv::Domain::interval(0, 1); }
  void exact(const Eigen::MatrixXd& x, Eigen::VectorXd& u, Eigen::VectorXd& du) const override {
    u = (M_PI * x.row(0).array()).sin().matrix().transpose();
    du = (M_PI * (M_PI * x.row(0).array()).cos()).matrix().transpose();
  }
  mfv::AssembledSystem assemble(const mfv::Discretization& d) const override {
    mfv::AssembledSystem s =
        mfv::assemble_scalar_1d(d, {}, [](double x) { return M_PI * M_PI * std::sin(M_PI * x); });
    s.constraint_points.resize(1, 2);
    s.constraint_points << 0.0, 1.0;
    s.constraint_values = Eigen::VectorXd::Zero(2);
    return s;
  }
  std::vector<int> resolutions(mfv::Level) const override { return {11, 21, 41}; }
};

void register_problems(mfv::ProblemRegistry& r) {
  r.add("sine-bar", "-u'' = pi^2 sin(pi x) on [0, 1], u = 0 at both ends (example plugin)", {},
        [](const mfv::Params&) { return std::make_unique<SineBar>(); });
}

}  // namespace example

// 3. The entry point: hand the registration functions to mfv's catalogue.
MFV_PLUGIN(plugin) {
  plugin.kernels.push_back(example::register_kernels);
  plugin.problems.push_back(example::register_problems);
}
