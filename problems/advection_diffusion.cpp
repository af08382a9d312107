/// `advection-diffusion`: u'' - a u' = b(x) on [0, 6] (004 I §6, eq 6.1). The source b is
/// defined as u_P'' - a u_P' of the particular solution (6.7-6.8), because the printed
/// formula (6.4) mixes c1 and c2; u = u_P + A + B u_H with u_H = (e^{ax} - 1)/(e^{6a} - 1).
/// a = 0 (diffusion, u(0) = u(6) = 0) is the case of Table 6.1; a = 1000 with u(6) = 1 the
/// advection case, solved with the least-squares-stabilized weak form (6.3).
#include <cmath>

#include <fmt/format.h>

#include "problems/problem.hpp"

namespace mfv {

namespace {

struct Peak {
  double x0, c1, c2, k;
};
constexpr Peak kPeaks[2] = {{5.0, 50, 1.0, 0.5}, {2.5, 50, 3.0, 1.0}};

/// u_P and its first two derivatives: k (1 - tanh(c1 z)) / (2 cosh(c2 z)), z = x - x0.
void particular(double x, double& u, double& du, double& d2u) {
  u = du = d2u = 0;
  for (const auto& p : kPeaks) {
    const double z = x - p.x0;
    const double T = std::tanh(p.c1 * z), S2 = 1 - T * T;
    const double f = 1 - T, df = -p.c1 * S2, d2f = 2 * p.c1 * p.c1 * S2 * T;
    const double t2 = std::tanh(p.c2 * z);
    const double g = 0.5 / std::cosh(p.c2 * z);
    const double dg = -p.c2 * g * t2, d2g = p.c2 * p.c2 * g * (2 * t2 * t2 - 1);
    u += p.k * f * g;
    du += p.k * (df * g + f * dg);
    d2u += p.k * (d2f * g + 2 * df * dg + f * d2g);
  }
}

class AdvectionDiffusion final : public ScalarProblem {
 public:
  AdvectionDiffusion(double a, double tau_scale) : a_(a), tau_scale_(tau_scale) {
    g6_ = a_ == 0 ? 0.0 : 1.0;
    double u0, u6, d;
    particular(0, u0, d, d);
    particular(6, u6, d, d);
    A_ = 0 - u0;
    B_ = g6_ - u6 - A_;
  }

  Domain domain() const override { return Domain::interval(0, 6); }
  int derivative_order() const override { return a_ == 0 ? 1 : 2; }

  /// u_H and its derivative, evaluated without overflow.
  void homogeneous(double x, double& uh, double& duh) const {
    if (a_ == 0) {
      uh = x / 6;
      duh = 1.0 / 6;
      return;
    }
    const double den = -std::expm1(-6 * a_);
    uh = (std::exp(a_ * (x - 6)) - std::exp(-6 * a_)) / den;
    duh = a_ * std::exp(a_ * (x - 6)) / den;
  }

  void exact(const Eigen::MatrixXd& x, Eigen::VectorXd& u, Eigen::VectorXd& du) const override {
    u.resize(x.cols());
    du.resize(x.cols());
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      double up, dup, d2up, uh, duh;
      particular(x(0, i), up, dup, d2up);
      homogeneous(x(0, i), uh, duh);
      u[i] = up + A_ + B_ * uh;
      du[i] = dup + B_ * duh;
    }
  }

  AssembledSystem assemble(const Discretization& d) const override {
    // -u'' + a u' = f with f = -b = -(u_P'' - a u_P').
    auto f = [a = a_](double x) {
      double u, du, d2u;
      particular(x, u, du, d2u);
      return -(d2u - a * du);
    };
    ScalarForm1D form;
    form.advection = a_;
    if (a_ != 0) {
      // The stabilized form needs u'' of the trial and test functions (R(v) = -v'' + a v');
      // collocation methods and Shepard tests do not tabulate them.
      for (const ShapeTable* t : {&d.trial_q, &d.test_q})
        if (t->order < 2 || t->hess.size() != static_cast<std::size_t>(t->entries()) * t->nhess())
          throw InputError(fmt::format(
              "advection-diffusion with a = {:g} uses the stabilized weak form (004 I eq 6.3), "
              "which needs second derivatives of the trial and test functions; the method ({}) "
              "does not provide them. Use a Galerkin method (fem, efg, rkpm, wavelet) or a=0",
              a_, d.description));
      // Optimal 1D SUPG/GLS parameter τ = Δx/(2a) (coth Pe - 1/Pe), Pe = a Δx / 2 (6.2c).
      const double h = d.particles.spacing, pe = a_ * h / 2;
      form.tau = tau_scale_ * h / (2 * a_) * (1 / std::tanh(pe) - 1 / pe);
    }
    AssembledSystem sys = assemble_scalar_1d(d, form, f);
    sys.constraint_points.resize(1, 2);
    sys.constraint_points << 0.0, 6.0;
    sys.constraint_values.resize(2);
    sys.constraint_values << 0.0, g6_;
    return sys;
  }

  std::vector<int> resolutions(Level level) const override {
    if (level == Level::quick) return {31, 61, 121};
    return {31, 61, 121, 241};
  }

  std::map<std::string, double> headline(const Discretization& d,
                                         const Eigen::VectorXd& u) const override {
    Eigen::MatrixXd x(1, 2);
    x << 2.5, 5.0;
    const Eigen::VectorXd v = d.trial_at(x, 0).interpolate(u);
    return {{"u at x=2.5", v[0]}, {"u at x=5", v[1]}};
  }

  std::map<std::string, double> headline_exact() const override {
    Eigen::MatrixXd x(1, 2);
    x << 2.5, 5.0;
    Eigen::VectorXd u, du;
    exact(x, u, du);
    return {{"u at x=2.5", u[0]}, {"u at x=5", u[1]}};
  }

  std::vector<PublishedValue> published() const override {
    if (a_ != 0) return {};  // Table 6.1 is the diffusion case
    const int nodes[] = {31, 61, 121, 241};
    const std::string src = "004 I Table 6.1";
    const std::string note = "norm not stated in the paper";
    struct Row {
      std::string method;
      Params p;
      const char* quantity;
      double v[4];
    };
    auto rk = [](double j) {
      Params p;
      p.set("j", j);
      return p;
    };
    auto wl = [](int bands) {
      Params p;
      p.set("j", 1.0);
      p.set("bands", bands);
      return p;
    };
    const double nan = std::nan("");
    const std::vector<Row> rows = {
        {"fem", {}, "error u", {0.19545, 0.18977, 0.07468, 0.01827}},
        {"rkpm", rk(-2.2), "error u", {0.19511, 0.18954, 0.07829, 0.06641}},
        {"rkpm", rk(-1.0), "error u", {0.19589, 0.19054, 0.07507, 0.01839}},
        {"rkpm", rk(1.0), "error u", {0.22884, 0.11999, 0.03746, 0.00463}},
        {"wavelet", wl(2), "error u", {0.20792, 0.16593, 0.07138, nan}},
        {"wavelet", wl(4), "error u", {0.19507, 0.19137, 0.07507, nan}},
        {"fem", {}, "error du/dx", {0.80144, 0.79926, 0.56435, 0.27424}},
        {"rkpm", rk(-2.2), "error du/dx", {0.80144, 0.79910, 0.56383, 0.27401}},
        {"rkpm", rk(-1.0), "error du/dx", {0.80283, 0.80029, 0.56555, 0.27422}},
        {"rkpm", rk(1.0), "error du/dx", {0.79341, 0.63022, 0.33317, 0.07116}},
        {"wavelet", wl(2), "error du/dx", {0.79900, 0.73682, 0.54145, nan}},
        {"wavelet", wl(4), "error du/dx", {0.80149, 0.79854, 0.55935, nan}},
    };
    std::vector<PublishedValue> out;
    for (const auto& r : rows)
      for (int i = 0; i < 4; ++i)
        if (!std::isnan(r.v[i])) out.push_back({src, r.quantity, r.method, r.p, nodes[i], r.v[i], note});
    return out;
  }

  std::vector<std::string> published_notes() const override {
    if (a_ != 0)
      return {"004 I prints no table for a = 1000; the suite checks that the stabilized form "
              "stays free of node-to-node oscillation (tests/test_problems.cpp) and records the "
              "rates, which stay below 1 while the boundary layer of width 1/a is unresolved."};
    return {
        "**On Table 6.1.** The paper does not say which norm its errors use; we put our "
        "relative L2 error (\"error u\") and relative H1-seminorm error (\"error du/dx\") on "
        "the common rule beside them. At 121–241 nodes FEM and the RKPM rows agree with the "
        "table to within tens of percent; at 31–61 nodes the table's errors are nearly flat "
        "(0.195 → 0.190 for FEM) while ours fall. Varying the FEM quadrature (1–4 Gauss "
        "points per element) did not reproduce the flat trend; the paper calls the 31-node "
        "case under-integrated, and a different error quadrature at coarse resolution is the "
        "best explanation we have.",
        "The RKPM j = −2.2 row at 241 nodes (0.066, worse than at 121 nodes) is not "
        "reproduced: with a window narrower than the spacing the RK functions collapse to "
        "hat-like functions and our error follows FEM's. We take the printed value as a "
        "misprint or a quadrature artefact of the narrow window.",
    };
  }

 private:
  double a_, tau_scale_, g6_ = 0, A_ = 0, B_ = 0;
};

}  // namespace

void register_advection_diffusion(ProblemRegistry& r) {
  r.add("advection-diffusion",
        "u'' - a u' = b(x) on [0,6] with two sharp peaks (004 I §6); a=0 diffusion (Table 6.1), "
        "a=1000 advection with the stabilized weak form",
        {ParamSpec::number("a", 0.0, "advection speed over diffusivity (0: diffusion)"),
         ParamSpec::number("tau_scale", 1.0, "multiplier of the optimal stabilization parameter")},
        [](const Params& p) {
          if (p.number("a") < 0)
            throw InputError("parameter 'a' of problem 'advection-diffusion' must be >= 0");
          return std::make_unique<AdvectionDiffusion>(p.number("a"), p.number("tau_scale"));
        });
}

}  // namespace mfv
