/// `j2-viscoplastic`: Needleman's (1989) rate-dependent J2 flow (001 §9.4, the compressed
/// plate) with the Jaumann rate of the Kirchhoff stress τ = F·P (001 eq 76):
///   τ^∇J = C : (D − Dᵖ),  Dᵖ = (3 ε̄̇ / 2σ̄) τ',  σ̄ = [3/2 τ':τ']^{1/2},
///   ε̄̇ = ε̇0 [σ̄ / g(ε̄)]^{1/m},
/// g(ε̄) the rational or linear softening law of j2_viscoplastic.hpp, floored at g_r > 0, and
/// σ0 scaled by a seeded per-point factor ξ (the imperfection). One step F_old → F_new: the
/// Hughes–Winget rotated elastic trial τ_trial (jaumann_update.hpp, shared with j2-jaumann),
/// then a backward-Euler return along the trial deviator, Δε̄ ≥ 0 solving
///   σ̄_trial − 3μ Δε̄ = g(ε̄_n + Δε̄) [Δε̄ / (ε̇0 Δt)]^m.
/// m = 0.01 makes the rate law stiff (ε̄̇ ∝ σ̄^100), so the rate is never evaluated
/// explicitly: the equation is solved for x = ln Δε̄ in the form
///   φ(x) = m ln(Δε̄ / ε̇0Δt) − ln(σ̄_trial − 3μΔε̄) + ln g(ε̄_n + Δε̄) = 0,
/// whose terms are all O(1), by Newton's method kept inside a bracket (bisection in x when a
/// Newton step leaves it). Δt = 0 (a trial evaluation) is elastic: no flow in zero time.
#include "methods/materials/j2_viscoplastic.hpp"

#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <utility>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "methods/materials/jaumann_update.hpp"
#include "methods/materials/material.hpp"

namespace mfv {

namespace {

constexpr const char* kPeridigmInput =
    "Peridigm test/verification/ViscoplasticNeedlemanFullyPrescribedTension_NoFlaw/"
    "ViscoplasticNeedlemanFullyPrescribedTension_NoFlaw.xml (github.com/peridigm/peridigm, "
    "2013); a code's input, not Needleman 1989 or Belytschko et al. 1994 (not found)";
constexpr const char* kPeridigmModel =
    "Peridigm src/materials/viscoplastic_needleman_correspondence.cxx (github.com/peridigm/"
    "peridigm), which cites Peirce, Shih & Needleman 1984, Comput. Struct. 18:875 "
    "(github.com/peridigm/peridigm/issues/90); Needleman 1989's own form not confirmed";
constexpr const char* kOurChoice = "our choice, not found";

/// Per-point history: the shared F − I and τ (jaumann::Slots), then ε̄, Δε̄/Δt and ξ − 1.
struct Layout {
  int dim;
  int plastic_strain() const { return jaumann::Slots{dim}.end(); }
  int plastic_strain_rate() const { return plastic_strain() + 1; }
  int yield_factor() const { return plastic_strain_rate() + 1; }
  int size() const { return yield_factor() + 1; }
};

enum class Softening { rational, linear };

struct Constants {
  double E, nu, sigma0, eps0, N, m, rate0, eps1, h1, residual, imperfection;
  Softening softening;
  std::uint64_t seed;
};

class J2Viscoplastic final : public Material {
 public:
  explicit J2Viscoplastic(const Constants& c) : c_(c) {
    mu_ = c.E / (2 * (1 + c.nu));
    lambda_ = c.E * c.nu / ((1 + c.nu) * (1 - 2 * c.nu));
  }

  using Material::first_piola;

  int state_size(int dim) const override { return Layout{dim}.size(); }
  bool rate_dependent() const override { return true; }

  void initial_state(int dim, int n, double* state) const override {
    const Layout l{dim};
    // The draw of j2-jaumann (one mt19937_64 over the points, the 53-bit mapping written out).
    std::mt19937_64 gen(c_.seed);
    for (int q = 0; q < n; ++q) {
      const double u = static_cast<double>(gen() >> 11) * 0x1.0p-53;  // [0, 1)
      state[static_cast<long>(l.size()) * q + l.yield_factor()] = c_.imperfection * (2 * u - 1);
    }
  }

  std::vector<std::string> state_names(int dim) const override {
    std::vector<std::string> names = jaumann::slot_names(dim);
    names.push_back("plastic_strain");
    names.push_back("plastic_strain_rate");
    names.push_back("yield_factor_minus_1");
    return names;
  }

  /// Without a time step no time passes: the elastic response (see the dt overload).
  void first_piola(int dim, int n, const double* F, double* P, double* state) const override {
    first_piola(dim, n, F, P, state, 0.0);
  }

  void first_piola(int dim, int n, const double* F, double* P, double* state,
                   double dt) const override {
    jaumann::check_call("j2-viscoplastic", dim, state);
    if (!(dt >= 0) || !std::isfinite(dt))
      throw std::logic_error(fmt::format("material 'j2-viscoplastic': time step {} is not a "
                                         "finite non-negative number",
                                         dt));
    const Layout l{dim};
    const int dd = dim * dim;
    for (int q = 0; q < n; ++q) {
      double* s = state + static_cast<long>(l.size()) * q;
      Eigen::Matrix3d F_old, F_new, tau;
      jaumann::load(dim, s, F + dd * q, F_old, F_new, tau);
      jaumann::elastic_trial(F_old, F_new, lambda_, mu_, tau);
      const double de = dt > 0 ? flow(1 + s[l.yield_factor()], s[l.plastic_strain()], dt, tau) : 0;
      s[l.plastic_strain()] += de;
      s[l.plastic_strain_rate()] = dt > 0 ? de / dt : 0;
      jaumann::store(dim, F_new, tau, P + dd * q, s);
    }
  }

  double wave_speed(int, double density) const override {
    return std::sqrt((lambda_ + 2 * mu_) / density);
  }

  std::string description(int dim) const override {
    return fmt::format(
        "J2 viscoplastic (Needleman 1989), Jaumann rate of Kirchhoff stress (001 eq 76) E={:g} "
        "nu={:g} sigma0={:g} eps0={:g} N={:g} m={:g} rate0={:g} eps1={:g} softening={}{} "
        "residual={:g} imperfection={:g} seed={}{}",
        c_.E, c_.nu, c_.sigma0, c_.eps0, c_.N, c_.m, c_.rate0, c_.eps1,
        c_.softening == Softening::rational ? "rational" : "linear",
        c_.softening == Softening::linear ? fmt::format(" h1={:g}", c_.h1) : std::string(),
        c_.residual, c_.imperfection, c_.seed,
        dim == 1 ? " uniaxial strain" : dim == 2 ? " plane strain" : "");
  }

  /// g(ε̄) and dg/dε̄ for the yield factor ξ (the floor's slope is 0).
  std::pair<double, double> g(double ebar, double factor) const {
    const double s0 = c_.sigma0 * factor;
    double value, slope;
    if (c_.softening == Softening::rational) {
      const double a = 1 + ebar / c_.eps0, r = ebar / c_.eps1, d = 1 + r * r;
      const double power = s0 * std::pow(a, c_.N);
      value = power / d;
      slope = value * (c_.N / (c_.eps0 * a) - 2 * r / (c_.eps1 * d));
    } else if (ebar <= c_.eps1) {
      value = s0 * std::pow(1 + ebar / c_.eps0, c_.N);
      slope = value * c_.N / (c_.eps0 + ebar);
    } else {
      value = s0 * std::pow(1 + c_.eps1 / c_.eps0, c_.N) + c_.h1 * (ebar - c_.eps1);
      slope = c_.h1;
    }
    if (!(value > c_.residual)) return {c_.residual, 0.0};
    return {value, slope};
  }

 private:
  /// Δε̄ of one step of length dt > 0, returning τ's deviator from the trial in place.
  double flow(double factor, double ebar, double dt, Eigen::Matrix3d& tau) const {
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    const double p = tau.trace() / 3;
    Eigen::Matrix3d dev = tau - p * I;
    const double sbar = std::sqrt(1.5 * dev.squaredNorm());
    if (!(sbar > 0)) return 0;
    const double three_mu = 3 * mu_, cap = sbar / three_mu;  // Δε̄ < cap keeps σ̄ > 0
    const double log_rate_step = std::log(c_.rate0 * dt);
    // φ(x) and dφ/dx at x = ln Δε̄; φ increases from −∞ (Δε̄ → 0) to +∞ (Δε̄ → cap) while
    // 3μ + g' > 0, which the parameter checks ensure.
    auto phi = [&](double x, double& slope) {
      const double de = std::exp(x), left = sbar - three_mu * de;
      const auto [gv, gs] = g(ebar + de, factor);
      slope = c_.m + three_mu * de / left + de * gs / gv;
      return c_.m * (x - log_rate_step) - std::log(left) + std::log(gv);
    };
    // Below Δε̄ = 1e-18 cap the stress change 3μΔε̄ is under round-off of σ̄: no flow.
    double lo = std::log(cap) - 18 * std::log(10.0), hi = std::log(cap), slope;
    if (phi(lo, slope) >= 0) return 0;
    // The rate law at the start of the step, σ̄ = σ̄_trial: the explicit guess, clamped.
    double x = log_rate_step + (std::log(sbar) - std::log(g(ebar, factor).first)) / c_.m;
    if (!(x > lo && x < hi)) x = 0.5 * (lo + hi);
    for (int it = 0; it < 200; ++it) {
      const double f = phi(x, slope);
      if (f < 0) lo = x; else hi = x;
      if (f == 0 || hi - lo < 1e-14 * std::max(1.0, std::abs(x))) break;
      double next = x - f / slope;
      if (!(slope > 0) || !(next > lo && next < hi)) next = 0.5 * (lo + hi);
      if (std::abs(next - x) < 1e-14 * std::max(1.0, std::abs(x))) {
        x = next;
        break;
      }
      x = next;
    }
    const double de = std::exp(x);
    dev *= 1 - three_mu * de / sbar;
    tau = dev + p * I;
    return de;
  }

  Constants c_;
  double lambda_, mu_;
};

}  // namespace

double Needleman1989Parameters::value(std::string_view name) const {
  for (const SourcedParameter& e : entries)
    if (e.name == name) return e.value;
  throw std::out_of_range(fmt::format("no Needleman 1989 parameter '{}'", name));
}

Needleman1989Parameters needleman_1989_parameters() {
  const double E = 211e9, sigma0 = 460e6;
  return {{{"E", E, "Pa", kPeridigmInput},
           {"nu", 0.3, "-", fmt::format("{} (Peridigm's 1D test uses 0)", kOurChoice)},
           {"density", 7800, "kg/m^3", kPeridigmInput},
           {"sigma0", sigma0, "Pa", kPeridigmInput},
           {"eps0", 0.00218, "-", fmt::format("{} (= sigma0/E)", kPeridigmInput)},
           {"N", 0.1, "-", kPeridigmInput},
           {"m", 0.01, "-", kPeridigmInput},
           {"rate0", 1e-3, "1/s", kPeridigmInput},
           {"eps1", 0.436, "-", fmt::format("{} (= 200 eps0)", kPeridigmInput)},
           {"h1", -E / 100, "Pa", fmt::format("{} (= -E/100; the linear law only)", kOurChoice)},
           {"residual", sigma0 / 100, "Pa", fmt::format("{} (= sigma0/100)", kOurChoice)},
           {"imperfection", 0.0, "-",
            fmt::format("{} (the plate's imperfection is in 001 Fig. 14, missing)", kOurChoice)}},
          "rational",
          kPeridigmModel};
}

void register_j2_viscoplastic(MaterialRegistry& r) {
  const Needleman1989Parameters t = needleman_1989_parameters();
  r.add("j2-viscoplastic",
        "Needleman's (1989) viscoplastic J2 flow (001 9.4, the compressed plate): Jaumann rate "
        "of Kirchhoff stress (001 eq 76), rate law ebar_dot = rate0 (sigma_bar/g)^(1/m), g "
        "softening (rational or linear) floored at a residual, seeded per-point factor xi on "
        "sigma0; implicit return in the plastic strain increment; plane strain in 2D",
        {ParamSpec::positive("E", t.value("E"), "Young's modulus, Pa"),
         ParamSpec::number("nu", t.value("nu"), "Poisson's ratio in [0, 0.5) (our choice)"),
         ParamSpec::positive("sigma0", t.value("sigma0"), "reference flow stress sigma0, Pa"),
         ParamSpec::number("eps0", 0.0, "reference strain eps0 of the hardening (1 + ebar/eps0)^N; "
                                        "0 means sigma0/E"),
         ParamSpec::number("N", t.value("N"), "strain-hardening exponent N in [0, 1]"),
         ParamSpec::positive("m", t.value("m"), "strain-rate sensitivity m in (0, 1]"),
         ParamSpec::positive("rate0", t.value("rate0"), "reference plastic strain rate, 1/s"),
         ParamSpec::positive("eps1", t.value("eps1"),
                             "softening strain eps1 (rational: g / (1 + (ebar/eps1)^2); linear: "
                             "where the linear branch starts)"),
         ParamSpec::choice("softening", t.softening_law, {"rational", "linear"},
                           "softening law of g (see j2_viscoplastic.hpp)"),
         ParamSpec::number("h1", t.value("h1"),
                           "slope of the linear softening branch, Pa, <= 0 and > -3 mu (linear "
                           "law only; our choice)"),
         ParamSpec::positive("residual", t.value("residual"),
                             "floor of g, Pa, below sigma0 (our choice)"),
         ParamSpec::number("imperfection", t.value("imperfection"),
                           "relative amplitude a in [0, 1) of the per-point factor xi on sigma0, "
                           "uniform in [1 - a, 1 + a]"),
         capped(ParamSpec::count("seed", 1, 1, "seed of the imperfection draw (mt19937_64)"),
                2e9)},
        [](const Params& p) -> std::unique_ptr<Material> {
          const auto refuse = [](const std::string& what) {
            throw InputError("material 'j2-viscoplastic': " + what);
          };
          Constants c{};
          c.E = p.number("E");
          c.nu = p.number("nu");
          c.sigma0 = p.number("sigma0");
          c.eps0 = p.number("eps0");
          c.N = p.number("N");
          c.m = p.number("m");
          c.rate0 = p.number("rate0");
          c.eps1 = p.number("eps1");
          c.h1 = p.number("h1");
          c.residual = p.number("residual");
          c.imperfection = p.number("imperfection");
          c.softening = p.text("softening") == "linear" ? Softening::linear : Softening::rational;
          c.seed = static_cast<std::uint64_t>(p.integer("seed"));
          if (c.nu < 0 || c.nu >= 0.5)
            refuse(fmt::format("nu = {} is outside [0, 0.5); give a Poisson's ratio such as 0.3",
                               c.nu));
          const double mu = c.E / (2 * (1 + c.nu)),
                       lambda = c.E * c.nu / ((1 + c.nu) * (1 - 2 * c.nu));
          // σ̄ = √(3/2 τ':τ') squares stresses of the size of the moduli: that must not overflow.
          if (!std::isfinite(9 * (lambda + 2 * mu) * (lambda + 2 * mu)))
            refuse(fmt::format("E = {} is too large (stresses of that size overflow when "
                               "squared); give E in Pa, e.g. 2.11e11",
                               c.E));
          if (c.sigma0 >= c.E)
            refuse(fmt::format("sigma0 = {} is not below E = {}; give the flow stress in Pa, "
                               "e.g. 4.6e8",
                               c.sigma0, c.E));
          if (c.eps0 < 0)
            refuse(fmt::format("eps0 = {} is negative; give a positive reference strain or 0 "
                               "for sigma0/E",
                               c.eps0));
          if (c.eps0 == 0) c.eps0 = c.sigma0 / c.E;
          if (c.N < 0 || c.N > 1)
            refuse(fmt::format("N = {} is outside [0, 1]; give a hardening exponent such as 0.1",
                               c.N));
          if (c.m > 1)
            refuse(fmt::format("m = {} is above 1 (a flow stress growing faster than the rate); "
                               "give a rate sensitivity such as 0.01",
                               c.m));
          if (c.rate0 > 1e12)
            refuse(fmt::format("rate0 = {} /s is beyond any strain rate of the engine; give a "
                               "reference rate such as 1e-3",
                               c.rate0));
          if (c.softening == Softening::linear && c.h1 > 0)
            refuse(fmt::format("h1 = {} is positive: the linear branch softens; give h1 <= 0, "
                               "e.g. -E/100 = {}",
                               c.h1, -c.E / 100));
          if (!(c.h1 > -3 * mu))
            refuse(fmt::format("h1 = {} is at or below -3 mu = {}, where the return has no "
                               "unique solution; give h1 > -3 mu, e.g. -E/100 = {}",
                               c.h1, -3 * mu, -c.E / 100));
          if (c.residual >= c.sigma0)
            refuse(fmt::format("residual = {} is not below sigma0 = {}; give a small floor such "
                               "as sigma0/100 = {}",
                               c.residual, c.sigma0, c.sigma0 / 100));
          if (c.imperfection < 0 || c.imperfection >= 1)
            refuse(fmt::format("imperfection = {} is outside [0, 1); give a relative amplitude "
                               "such as 0.01",
                               c.imperfection));
          return std::make_unique<J2Viscoplastic>(c);
        });
}

}  // namespace mfv
