/// `advection-diffusion`: u'' - a u' = b(x) on [0, 6] (004 I §6, eq 6.1). The source b is
/// defined as u_P'' - a u_P' of the particular solution (6.7-6.8), because the printed
/// formula (6.4) mixes c1 and c2; u = u_P + A + B u_H with u_H = (e^{ax} - 1)/(e^{6a} - 1).
/// a = 0 (diffusion, u(0) = u(6) = 0) is the case of Table 6.1; a = 1000 with u(6) = 1 the
/// advection case, solved with the least-squares-stabilized weak form (6.3).
#include <cmath>

#include <fmt/format.h>

#include "methods/integration/integration.hpp"
#include "problems/problem.hpp"

namespace mfv {

namespace {

/// Table 6.1 prints "error u" and "error du/dx" without a norm (004 I §6). The readings the
/// text allows, each a headline of the diffusion case (the relative L2 / H1-seminorm errors of
/// the common rule are the study's own): absolute L2 / H1-seminorm, the relative RMS at the
/// particles, and the relative max norm over the bar.
constexpr const char* kAbsU = "error u (absolute L2)";
constexpr const char* kAbsDu = "error du/dx (absolute H1 seminorm)";
constexpr const char* kNodalU = "error u (nodal RMS, relative)";
constexpr const char* kNodalDu = "error du/dx (nodal RMS, relative)";
constexpr const char* kMaxU = "error u (max, relative)";
constexpr const char* kMaxDu = "error du/dx (max, relative)";
/// Gauss points per particle spacing of the headline norms: the peaks are 1/c1 = 0.02 wide,
/// 0.2/20 = 0.01 apart at 31 nodes (the common rule of the study is a separate computation).
constexpr int kNormPointsPerSpacing = 20;

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
  AdvectionDiffusion(double a, double tau_scale, bool stabilized)
      : a_(a), tau_scale_(tau_scale), stabilized_(a != 0 || stabilized) {
    g6_ = a_ == 0 ? 0.0 : 1.0;
    double u0, u6, d;
    particular(0, u0, d, d);
    particular(6, u6, d, d);
    A_ = 0 - u0;
    B_ = g6_ - u6 - A_;
  }

  Domain domain() const override { return Domain::interval(0, 6); }
  int derivative_order() const override { return stabilized_ ? 2 : 1; }

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
    if (stabilized_) {
      // The stabilized form needs u'' of the trial and test functions (R(v) = -v'' + a v');
      // collocation methods and Shepard tests do not tabulate them.
      for (const ShapeTable* t : {&d.trial_q, &d.test_q})
        if (t->order < 2 || t->hess.size() != static_cast<std::size_t>(t->entries()) * t->nhess())
          throw InputError(fmt::format(
              "advection-diffusion with a = {:g} uses the stabilized weak form (004 I eq 6.3), "
              "which needs second derivatives of the trial and test functions; the method ({}) "
              "does not provide them. Use a Galerkin method (fem, efg, rkpm, wavelet) or a=0",
              a_, d.description));
      // Optimal 1D SUPG/GLS parameter τ = Δx/(2a) (coth Pe - 1/Pe), Pe = a Δx / 2 (6.2c);
      // at a = 0 its limit Δx²/12 (coth Pe − 1/Pe → Pe/3): 004 I obtains the diffusion
      // results "by setting the parameter a to zero" in the same weak form (6.3).
      const double h = d.particles.spacing, pe = a_ * h / 2;
      form.tau = a_ == 0 ? tau_scale_ * h * h / 12
                         : tau_scale_ * h / (2 * a_) * (1 / std::tanh(pe) - 1 / pe);
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
    std::map<std::string, double> out{{"u at x=2.5", v[0]}, {"u at x=5", v[1]}};
    if (a_ == 0) table61_norms(d, u, out);
    return out;
  }

  /// The norm readings of Table 6.1 (kAbsU … kMaxDu) for the diffusion case.
  void table61_norms(const Discretization& d, const Eigen::VectorXd& u,
                     std::map<std::string, double>& out) const {
    const int n = d.particles.size();
    if (n < 2) return;
    // Integrals and the max norm on a fine Gauss rule of the bar.
    const IntegrationRule rule = uniform_gauss_rule_1d(0, 6, (n - 1), kNormPointsPerSpacing);
    const ShapeTable t = d.trial_at(rule.points, 1);
    const Eigen::VectorXd uh = t.interpolate(u), duh = t.interpolate_derivative(u);
    Eigen::VectorXd ue, due;
    exact(rule.points, ue, due);
    double e0 = 0, e1 = 0, n0 = 0, n1 = 0, m0 = 0, m1 = 0, M0 = 0, M1 = 0;
    for (int q = 0; q < rule.points.cols(); ++q) {
      const double w = rule.weights[q];
      e0 += w * std::pow(uh[q] - ue[q], 2), n0 += w * ue[q] * ue[q];
      e1 += w * std::pow(duh[q] - due[q], 2), n1 += w * due[q] * due[q];
      m0 = std::max(m0, std::abs(uh[q] - ue[q])), M0 = std::max(M0, std::abs(ue[q]));
      m1 = std::max(m1, std::abs(duh[q] - due[q])), M1 = std::max(M1, std::abs(due[q]));
    }
    out[kAbsU] = std::sqrt(e0);
    out[kAbsDu] = std::sqrt(e1);
    out[kMaxU] = m0 / M0;
    out[kMaxDu] = m1 / M1;
    // At the particles: u_h(x_I) (not the coefficient u_I, which RK functions do not
    // interpolate) against u(x_I).
    const ShapeTable p = d.trial_at(d.particles.x, 1);
    const Eigen::VectorXd up = p.interpolate(u), dup = p.interpolate_derivative(u);
    Eigen::VectorXd uep, duep;
    exact(d.particles.x, uep, duep);
    out[kNodalU] = (up - uep).norm() / uep.norm();
    out[kNodalDu] = (dup - duep).norm() / duep.norm();
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
        "**On Table 6.1.** Table 6.1 is the diffusion case (a = 0, u(0) = u(6) = 0: \"Table "
        "6.1a Error of numerical solutions for the Diffusion Equation\"). The paper does not "
        "say which norm its errors use; we put our relative L2 error (\"error u\") and "
        "relative H1-seminorm error (\"error du/dx\") on the common rule beside them, and as "
        "other readings the absolute L2 / H1-seminorm errors, the relative RMS at the particles "
        "and the relative max norm over the bar (headlines; 20 Gauss points per spacing). No "
        "reading reproduces the table at every resolution (FEM, measured 2026-11-27: relative "
        "L2 0.208 0.131 0.058 0.016, absolute 0.164 0.104 0.046 0.012, nodal RMS 0.155 then "
        "< 1e-4, max 0.297 0.295 0.176 0.062; the table 0.195 0.190 0.075 0.018). At 31–61 "
        "nodes the table's errors are nearly flat while ours fall; the paper calls its 31-node "
        "solution under-integrated, and ours at 31 nodes is not converged in quadrature either "
        "(FEM 0.208 with 10 Gauss points per element, 0.154 with 20; from 61 nodes on they "
        "agree to 0.5 %). The load with 2 points per element (0.669 0.500 0.093 0.022) does not "
        "give the flat trend.",
        "The RKPM j = −2.2 row at 241 nodes (0.066, worse than at 121 nodes) is not "
        "reproduced: with a window narrower than the spacing the RK functions collapse to "
        "hat-like functions and our error follows FEM's. We take the printed value as a "
        "misprint or a quadrature artefact of the narrow window.",
    };
  }

 private:
  double a_, tau_scale_;
  bool stabilized_;
  double g6_ = 0, A_ = 0, B_ = 0;
};

}  // namespace

void register_advection_diffusion(ProblemRegistry& r) {
  r.add("advection-diffusion",
        "u'' - a u' = b(x) on [0,6] with two sharp peaks (004 I §6); a=0 diffusion (Table 6.1), "
        "a=1000 advection with the stabilized weak form",
        {ParamSpec::number("a", 0.0, "advection speed over diffusivity (0: diffusion)"),
         ParamSpec::number("tau_scale", 1.0, "multiplier of the optimal stabilization parameter"),
         ParamSpec::choice("weak_form", "auto", {"auto", "stabilized"},
                           "auto: the least-squares stabilized form (004 I eq 6.3) when a != 0, "
                           "plain Galerkin when a = 0; stabilized: eq 6.3 at a = 0 too, with "
                           "tau = tau_scale dx^2/12 (the a -> 0 limit of the optimal tau)")},
        [](const Params& p) {
          if (p.number("a") < 0)
            throw InputError("parameter 'a' of problem 'advection-diffusion' must be >= 0");
          return std::make_unique<AdvectionDiffusion>(p.number("a"), p.number("tau_scale"),
                                                      p.text("weak_form") == "stabilized");
        });
}

}  // namespace mfv
