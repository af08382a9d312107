/// `cantilever`: Timoshenko's cantilever under a parabolic end shear (001 §9.1; Timoshenko &
/// Goodier), exact displacements and stresses. 001's Fig. 5 with the dimensions is missing
/// from our copy: we use the customary meshfree benchmark L = 48, D = 12, E = 3e7, ν = 0.3,
/// P = 1000 (catalogue), plane stress by default.
#include <cmath>

#include <fmt/format.h>

#include "problems/finding_tally.hpp"
#include "problems/problem.hpp"

namespace mfv {

namespace {

constexpr const char* kTip = "tip deflection u_y(L,0)";

/// The VCI order a study ran with (vci, not a method of 001): "false", "linear" (vci=true or
/// linear) or "quadratic".
std::string vci_of(const StudySummary& s) {
  const std::string v = s.params.has("vci") ? s.params.text("vci") : "false";
  return v == "true" ? "linear" : v;
}

/// The studies of `method` with (fixed_support) or without a fixed `radius` parameter, and
/// with variationally consistent integration of order `vci` ("false": none).
std::vector<const StudySummary*> of(const std::vector<StudySummary>& all, const std::string& method,
                                    bool fixed_support = false, const std::string& vci = "false") {
  std::vector<const StudySummary*> out;
  for (const auto& s : all)
    if (s.method == method && s.params.has("radius") == fixed_support && vci_of(s) == vci &&
        s.resolutions >= 3)
      out.push_back(&s);
  return out;
}

std::string describe(const StudySummary& s) {
  return fmt::format("{}: L2 rate {:.2f} ({}), energy rate {:.2f}, finest L2 {:.2e}, energy "
                     "{:.2e} ({} particles)",
                     s.label, s.l2_rate, s.l2_trend.label(), s.energy_rate, s.l2_rel_finest,
                     s.energy_rel_finest, s.finest_particles);
}

/// "converges" as reports/convergence.hpp judges it: the finest error the smallest, the last
/// pairwise and the fitted rate at least kConvergesMinRate.
constexpr const char* kConvergesCriterion =
    "L2 errors converge: the finest is the smallest and the last pairwise and the fitted rate "
    "are at least 0.5 (reports/convergence.hpp)";

Verdict not_run(const std::string& what) { return {"not run", "no study of " + what}; }

/// A verdict with the numbers it rests on: each study's L2 errors per resolution and, when
/// the claim is of a rate, its pairwise rates (the ledger's uncertainty, issue 44).
Verdict numbered(Verdict v, const std::vector<const StudySummary*>& studies, bool rates) {
  for (const auto* s : studies) {
    v.numbers.push_back(finding::l2_per_resolution(*s));
    if (rates) v.numbers.push_back(finding::l2_rate_per_pair(*s));
  }
  return v;
}

/// 001 §9.1's statements about Figs. 6 and 7, each with the criterion we hold our run to.
std::vector<Finding> cantilever_findings() {
  std::vector<Finding> f;
  f.push_back({"001 §9.1", "EFG with cell integration gives the best results",
               "efg-ci has the smallest finest L2 and energy errors of the five methods (same "
               "finest resolution)",
               [](const std::vector<StudySummary>& all) -> Verdict {
                 const auto ci = of(all, "efg-ci");
                 if (ci.empty()) return not_run("efg-ci");
                 std::string worse;
                 bool best = true;
                 std::vector<const StudySummary*> used = {ci[0]};
                 for (const char* m : {"sph", "rlm", "kbm-si", "kbm-ni", "efg-ni"})
                   for (const auto* s : of(all, m))
                     if (s->finest_nodes == ci[0]->finest_nodes) {
                       used.push_back(s);
                       const bool beats = s->l2_rel_finest < ci[0]->l2_rel_finest ||
                                          s->energy_rel_finest < ci[0]->energy_rel_finest;
                       best = best && !beats;
                       worse += fmt::format("; {} {:.1e}/{:.1e}", s->label, s->l2_rel_finest,
                                            s->energy_rel_finest);
                     }
                 return numbered({best ? "reproduced" : "not reproduced",
                                  fmt::format("efg-ci L2/energy {:.1e}/{:.1e}{}", ci[0]->l2_rel_finest,
                                              ci[0]->energy_rel_finest, worse)},
                                 used, false);
               }, "efg-ci-best"});
  f.push_back({"001 §9.1", "KBM with stress points: displacement rate close to 2",
               "kbm-si L2 rate in [1.7, 2.3]", [](const std::vector<StudySummary>& all) -> Verdict {
                 const auto k = of(all, "kbm-si");
                 if (k.empty()) return not_run("kbm-si");
                 const bool ok = k[0]->l2_rate >= 1.7 && k[0]->l2_rate <= 2.3;
                 return numbered({ok ? "reproduced" : "not reproduced", describe(*k[0])}, {k[0]},
                                 true);
               }, "kbm-si-rate"});
  f.push_back({"001 §9.1",
               "EFG ni and KBM si converge a little slower than EFG ci, with larger errors",
               "each converges (reports/convergence.hpp) with an L2 rate within 0.5 below "
               "efg-ci's (or above it) and a larger finest L2 error",
               [](const std::vector<StudySummary>& all) -> Verdict {
                 const auto ci = of(all, "efg-ci");
                 if (ci.empty()) return not_run("efg-ci");
                 int ok = 0, n = 0;
                 std::string text;
                 std::vector<const StudySummary*> used = {ci[0]};
                 for (const char* m : {"efg-ni", "kbm-si"})
                   for (const auto* s : of(all, m)) {
                     ++n;
                     used.push_back(s);
                     const bool good = s->l2_trend.converges() &&
                                       s->l2_rate >= ci[0]->l2_rate - 0.5 &&
                                       s->l2_rel_finest > ci[0]->l2_rel_finest;
                     ok += good;
                     text += fmt::format("{}{}: rate {:.2f}, {} ({})", text.empty() ? "" : "; ",
                                         s->label, s->l2_rate, trend_name(s->l2_trend.trend),
                                         good ? "as stated" : "not");
                   }
                 if (n == 0) return not_run("efg-ni or kbm-si");
                 return numbered({ok == n ? "reproduced" : ok > 0 ? "partly" : "not reproduced",
                                  fmt::format("efg-ci rate {:.2f}; {}", ci[0]->l2_rate, text)},
                                 used, true);
               }, "efg-ni-kbm-si-slower"});
  f.push_back({"001 §9.1", "RLM and KBM with nodal integration yield poor results",
               "rlm and kbm-ni: each with a finest L2 error larger than that of every method "
               "001 calls good (efg-ci, efg-ni, kbm-si: \"pretty good results\") at the same "
               "finest resolution",
               [](const std::vector<StudySummary>& all) -> Verdict {
                 // The methods 001 calls good, with their finest errors.
                 std::vector<const StudySummary*> good;
                 for (const char* m : {"efg-ci", "efg-ni", "kbm-si"})
                   for (const auto* s : of(all, m)) good.push_back(s);
                 if (good.empty()) return not_run("efg-ci, efg-ni or kbm-si");
                 int ok = 0, n = 0;
                 std::string text;
                 std::vector<const StudySummary*> used = good;
                 for (const char* m : {"rlm", "kbm-ni"})
                   for (const auto* s : of(all, m)) {
                     ++n;
                     used.push_back(s);
                     bool poor = true;
                     int compared = 0;
                     std::string beside;
                     for (const auto* g : good) {
                       if (g->finest_nodes != s->finest_nodes) continue;
                       ++compared;
                       poor = poor && s->l2_rel_finest > g->l2_rel_finest;
                       beside += fmt::format("{}{} {:.2e}", beside.empty() ? "" : ", ", g->label,
                                             g->l2_rel_finest);
                     }
                     poor = poor && compared > 0;
                     ok += poor;
                     text += fmt::format(
                         "{}{}: finest L2 {:.2e}, {} ({})", text.empty() ? "" : "; ", s->label,
                         s->l2_rel_finest,
                         poor ? "poorer than every good method" : "not poorer than every one",
                         beside.empty() ? "no good method at its resolution" : beside);
                   }
                 if (n == 0) return not_run("rlm or kbm-ni");
                 return numbered({ok == n ? "reproduced" : ok > 0 ? "partly" : "not reproduced", text},
                                 used, false);
               }, "rlm-kbm-ni-poor"});
  f.push_back({"001 §9.1", "SPH does not converge at all (support shrinking with the spacing)",
               "sph: the L2 errors do not converge (not: the finest the smallest with the last "
               "pairwise and the fitted rate at least 0.5)",
               [](const std::vector<StudySummary>& all) -> Verdict {
                 const auto s = of(all, "sph");
                 if (s.empty()) return not_run("sph");
                 const bool ok = !s[0]->l2_trend.converges();
                 return numbered({ok ? "reproduced" : "not reproduced", describe(*s[0])}, {s[0]},
                                 true);
               }, "sph-no-convergence"});
  f.push_back({"001 §9.1, Fig. 7", "SPH converges when the support is held constant",
               std::string("sph with a fixed radius: ") + kConvergesCriterion,
               [](const std::vector<StudySummary>& all) -> Verdict {
                 const auto s = of(all, "sph", true);
                 if (s.empty()) return not_run("sph with radius=");
                 const bool ok = s[0]->l2_trend.converges();
                 return numbered({ok ? "reproduced" : "not reproduced", describe(*s[0])}, {s[0]},
                                 true);
               }, "sph-constant-support"});
  f.push_back({"001 §9.1, Fig. 7", "EFG with cell integration converges with a constant support",
               std::string("efg-ci with a fixed radius: ") + kConvergesCriterion,
               [](const std::vector<StudySummary>& all) -> Verdict {
                 const auto s = of(all, "efg-ci", true);
                 if (s.empty()) return not_run("efg-ci with radius=");
                 const bool ok = s[0]->l2_trend.converges();
                 return numbered({ok ? "reproduced" : "not reproduced", describe(*s[0])}, {s[0]},
                                 true);
               },
               "efg-ci-constant-support"});
  // Not from 001: the same claim measured with VCI (Chen, Hillman & Rüter 2013), which
  // removes the quadrature defect of the Shepard test functions that stalls kbm-si.
  f.push_back({"001 §9.1 (VCI: Chen, Hillman & Rüter 2013, not from 001)",
               "KBM si with VCI: the displacement rate close to 2 that 001 states for KBM si, "
               "measured with variationally consistent integration",
               "kbm-si vci=true L2 rate in [1.7, 2.3]; kbm-ni and efg-ni with and without VCI "
               "listed beside it",
               [](const std::vector<StudySummary>& all) -> Verdict {
                 const auto k = of(all, "kbm-si", false, "linear");
                 if (k.empty()) return not_run("kbm-si vci=true");
                 const bool ok = k[0]->l2_rate >= 1.7 && k[0]->l2_rate <= 2.3;
                 std::string text = describe(*k[0]);
                 for (const char* m : {"kbm-si", "kbm-ni", "efg-ni"})
                   for (const char* v : {"false", "linear"}) {
                     if (std::string(m) == "kbm-si" && std::string(v) == "linear") continue;
                     for (const auto* s : of(all, m, false, v)) text += "; " + describe(*s);
                   }
                 return numbered({ok ? "reproduced under a stated reading" : "not reproduced", text},
                                 {k[0]}, true);
               },
               "kbm-si-rate-vci"});
  // Not from 001 either (issue 43): quadratic VCI also meets the second divergence identity,
  // the one a linear stress needs, which Shepard test functions (not linearly complete) leave
  // unmet under stress-point sums. The rate of an asymptotic claim ("close to two") is the
  // observed order on the finest pair, with the errors converging.
  f.push_back({"001 §9.1 (quadratic VCI: Chen, Hillman & Rüter 2013, not from 001)",
               "KBM si with quadratic VCI: the displacement rate close to 2 that 001 states for "
               "KBM si",
               std::string("kbm-si vci=quadratic: the L2 rate of the finest pair in [1.7, 2.3] "
                           "and ") + kConvergesCriterion,
               [](const std::vector<StudySummary>& all) -> Verdict {
                 const auto k = of(all, "kbm-si", false, "quadratic");
                 if (k.empty()) return not_run("kbm-si vci=quadratic");
                 const auto& pw = k[0]->l2_trend.pairwise;
                 const double last = pw.empty() ? NAN : pw.back();
                 const bool ok = last >= 1.7 && last <= 2.3 && k[0]->l2_trend.converges();
                 return numbered({ok ? "reproduced under a stated reading" : "not reproduced",
                                  fmt::format("{}; finest-pair L2 rate {:.2f}", describe(*k[0]), last)},
                                 {k[0]}, true);
               },
               "kbm-si-rate-vci-quadratic"});
  return f;
}

class Cantilever final : public BoundaryValueProblem {
 public:
  /// How x = 0 is held (001 §9.1 does not say; its Fig. 5 is missing from our copy).
  enum class Clamp { side, supports, timoshenko };

  Cantilever(bool plane_strain, Placement placement, Clamp clamp)
      : placement_(placement), clamp_(clamp) {
    material_.E = 3e7;
    material_.nu = 0.3;
    material_.plane_strain = plane_strain;
    // Plane strain: the plane-stress solution with E/(1-ν²) and ν/(1-ν).
    Ee_ = plane_strain ? material_.E / (1 - material_.nu * material_.nu) : material_.E;
    nue_ = plane_strain ? material_.nu / (1 - material_.nu) : material_.nu;
  }

  Domain domain() const override { return Domain::rectangle(0, -D_ / 2, L_, D_ / 2); }
  int components() const override { return 2; }
  std::string resolution_name() const override { return "particles across the depth"; }

  /// ny particles across the depth, 4(ny-1)+1 along the length: square lattices, L/D = 4.
  ParticleSet particles(int ny, double perturbation) const override {
    if (ny < 2)
      throw InputError(fmt::format("cantilever: nodes counts particles across the depth and "
                                   "must be at least 2, got {}",
                                   ny));
    const std::int64_t nx = placement_ == Placement::boundary ? 4 * (std::int64_t{ny} - 1) + 1
                                                               : 4 * std::int64_t{ny};
    return rectangle_lattice(domain(), nx, ny, placement_, perturbation);
  }

  /// Timoshenko & Goodier: u_x = -Py/(6EI)[(6L-3x)x + (2+ν)(y²-D²/4)],
  /// u_y = P/(6EI)[3νy²(L-x) + (4+5ν)D²x/4 + (3L-x)x²].
  void exact_field(const Eigen::MatrixXd& X, Eigen::MatrixXd& u,
                   Eigen::MatrixXd& g) const override {
    const double I = D_ * D_ * D_ / 12, c = P_ / (6 * Ee_ * I), nu = nue_;
    u.resize(2, X.cols());
    g.resize(4, X.cols());
    for (Eigen::Index i = 0; i < X.cols(); ++i) {
      const double x = X(0, i), y = X(1, i);
      u(0, i) = -c * y * ((6 * L_ - 3 * x) * x + (2 + nu) * (y * y - D_ * D_ / 4));
      u(1, i) = c * (3 * nu * y * y * (L_ - x) + (4 + 5 * nu) * D_ * D_ * x / 4 + (3 * L_ - x) * x * x);
      g(0, i) = -c * y * (6 * L_ - 6 * x);
      g(1, i) = -c * ((6 * L_ - 3 * x) * x + (2 + nu) * (3 * y * y - D_ * D_ / 4));
      g(2, i) = c * (-3 * nu * y * y + (4 + 5 * nu) * D_ * D_ / 4 + 6 * L_ * x - 3 * x * x);
      g(3, i) = c * 6 * nu * y * (L_ - x);
    }
  }

  /// σ_xx = -P(L-x)y/I, σ_yy = 0, σ_xy = P/(2I)(D²/4 - y²).
  Eigen::MatrixXd exact_stress(const Eigen::MatrixXd& X) const {
    const double I = D_ * D_ * D_ / 12;
    Eigen::MatrixXd s(3, X.cols());
    for (Eigen::Index i = 0; i < X.cols(); ++i) {
      const double x = X(0, i), y = X(1, i);
      s.col(i) << -P_ * (L_ - x) * y / I, 0.0, P_ / (2 * I) * (D_ * D_ / 4 - y * y);
    }
    return s;
  }

  AssembledSystem assemble(const Discretization& d) const override {
    ElasticityBVP bvp;
    bvp.material = material_;
    // x = L: t = σ·n = (σ_xx, σ_xy) = (0, P/(2I)(D²/4 - y²)); top and bottom are free.
    bvp.tractions[1] = [this](const Eigen::MatrixXd& X) {
      Eigen::MatrixXd s = exact_stress(X), t(2, X.cols());
      t.row(0) = s.row(0);
      t.row(1) = s.row(2);
      return t;
    };
    // x = 0: the exact displacements (the usual reading of the clamped end).
    bvp.displacements[0] = [this](const Eigen::MatrixXd& X) {
      Eigen::MatrixXd u, g;
      exact_field(X, u, g);
      return u;
    };
    if (clamp_ == Clamp::supports) bvp.clamp_supports.insert(0);
    if (clamp_ == Clamp::timoshenko) {
      // Timoshenko & Goodier's support: x = 0 carries the solution's own traction
      // t = σ·(−1, 0) = (−σ_xx, −σ_xy), and only the rigid motion is fixed, at the particle
      // nearest the section's centre (u_x, u_y) and the top one of the section (u_x), to the
      // exact values: three conditions whatever the support, none beyond the rigid modes.
      bvp.displacements.clear();
      bvp.tractions[0] = [this](const Eigen::MatrixXd& X) {
        Eigen::MatrixXd s = exact_stress(X), t(2, X.cols());
        t.row(0) = -s.row(0);
        t.row(1) = -s.row(2);
        return t;
      };
      AssembledSystem a = assemble_elasticity(d, bvp);
      const ParticleSet& p = d.particles;
      int centre = -1, top = -1;
      for (int I = 0; I < p.size(); ++I) {
        if (!(p.sides[I] & Side::left)) continue;
        if (centre < 0 || std::abs(p.x(1, I)) < std::abs(p.x(1, centre))) centre = I;
        if (top < 0 || p.x(1, I) > p.x(1, top)) top = I;
      }
      if (centre < 0 || top == centre)
        throw InputError("cantilever: clamp=timoshenko needs at least two particles on x = 0");
      Eigen::MatrixXd at(2, 3);
      at << p.x.col(centre), p.x.col(centre), p.x.col(top);
      Eigen::MatrixXd u, g;
      exact_field(at, u, g);
      a.constraint_points = at;
      a.constraint_values = Eigen::Vector3d(u(0, 0), u(1, 1), u(0, 2));
      a.constraint_components = {0, 1, 0};
      a.constraint_particles = {centre, centre, top};
      return a;
    }
    return assemble_elasticity(d, bvp);
  }

  Eigen::VectorXd energy_density(const Eigen::MatrixXd& grad) const override {
    return material_.energy_density(grad);
  }
  Eigen::MatrixXd flux(const Eigen::MatrixXd& grad) const override { return material_.stress(grad); }
  std::vector<std::string> flux_names() const override { return {"sxx", "syy", "sxy"}; }

  IntegrationRule common_error_rule(const ParticleSet& p) const override {
    // 4×4 Gauss on a uniform grid at least as fine as the lattice (and never coarser than
    // 96×24 cells), the same for every method at a resolution.
    const int cy = std::max(24, p.lattice[1] > 1 ? p.lattice[1] - 1 : 24);
    return uniform_gauss_rule_2d(domain(), 4 * cy, cy, 4);
  }
  bool errors_on_method_rule() const override { return true; }

  std::vector<int> resolutions(Level level) const override {
    if (level == Level::quick) return {5, 9, 17, 33};
    // 85 to 40,501 particles (17×5 … 401×101).
    return {5, 9, 17, 33, 65, 101};
  }

  std::map<std::string, double> headline(const Discretization& d,
                                         const Eigen::VectorXd& u) const override {
    Eigen::MatrixXd x(2, 1);
    x << L_, 0.0;
    Eigen::MatrixXd v, g;
    d.trial_at(x, 0).field(u, 2, v, g);
    return {{kTip, v(1, 0)}};
  }
  std::map<std::string, double> headline_exact() const override {
    Eigen::MatrixXd x(2, 1), u, g;
    x << L_, 0.0;
    exact_field(x, u, g);
    return {{kTip, u(1, 0)}};
  }

  std::vector<Finding> findings() const override { return cantilever_findings(); }

  std::vector<std::string> published_notes() const override {
    return {
        "001 gives no numbers for the cantilever, only Fig. 6 (error against particle spacing "
        "for the five methods) and Fig. 7 (SPH and EFG ci with a constant support), whose "
        "plots are missing from our copy; the findings it states in §9.1 are checked one by one "
        "in the verdict table above. Dimensions are not given either: we use L = 48, D = 12, "
        "E = 3e7, ν = 0.3, P = 1000, plane stress.",
        "Energy error: 001 eq 74 defines ‖u‖_energy = ∫ P:Fᵀ dΩ without a square root. We "
        "report the usual sqrt(∫ (ε_h-ε):D:(ε_h-ε) / ∫ ε:D:ε); eq 74 read literally is the "
        "square of ours, with twice the rate.",
        "KBM si and KBM ni stagnate near 1% where 001 reports a rate close to 2 for KBM si. "
        "The same tables on Gauss cells (`kbm-ci`, not a method of 001) converge at rate 2.2, "
        "so the corrected gradients and the Petrov–Galerkin coupling are sound; the "
        "stagnation comes from the quadrature. Measured per particle (tests/test_vci.cpp, 7×7 "
        "patch): the defect of the divergence identity Σ_q w_q ∇Ψ_I(x_q) − Σ_b w_b Ψ_I(x_b) n_b "
        "of the Shepard test functions, relative to Σ_q w_q |∇Ψ_I|, is up to 6.6% (RMS 2.1%) "
        "for kbm-si and 4.3% (2.7%) for kbm-ni on a uniform lattice, 14% and 47% on one "
        "perturbed by 0.3 spacings, largest where supports are cut by the edges; efg-ni's MLS "
        "test functions show 3.6% and 15%. A constant stress then leaves spurious forces of "
        "order σ·Δx at those particles, which is the patch-test error (kbm-si 1e-3 uniform, "
        "1.4e-2 perturbed) and the floor the cantilever stalls on. 001 does not say how its "
        "boundary particles were integrated.",
        "**VCI (not from 001).** With `vci=true` (variationally consistent integration of "
        "linear order, Chen, Hillman & Rüter 2013: one constant correction of the test "
        "gradients per particle so that the quadrature satisfies that identity on the same "
        "boundary rule the tractions and multipliers use) the defect vanishes to round-off and "
        "kbm-si, kbm-ni and efg-ni pass the patch test to 3e-16 on uniform and perturbed "
        "particles. On the cantilever (cases `cantilever/*-vci`, finding `kbm-si-rate-vci`) "
        "kbm-si's L2 rate over 17×5 … 129×33 rises from 0.30 to 1.48 and its finest error "
        "falls 19× (9.5e-3 → 5.1e-4), kbm-ni's from 0.99 to 1.51, and efg-ni keeps its L2 "
        "rate (1.96 → 1.94) while its energy rate rises from 0.84 to 1.59: VCI removes the "
        "stagnation, but no nodal or stress-point variant reaches rate 2 at these sizes "
        "(measured 2026-11-23). VCI is a 2013 method: the rows with it show what a consistent "
        "quadrature gives, not what 001 did.",
        "Fig. 7's constant support (radius 4.5, 1.5 spacings at the coarsest) and the clamp: "
        "001 does not say how x = 0 is held (Fig. 5 is missing). Holding only the particles on "
        "x = 0 under a fixed support tests the set-up: the free particles within the support "
        "of x = 0 see a clamp that thins as the spacing shrinks (SPH's error grew from 1.3 to "
        "2.9), and one Lagrange multiplier per boundary particle under a wide, "
        "non-interpolating MLS support over-constrains the trial space (EFG ci's L2 error fell "
        "to 4.8e-5 at h = 1.5, rose to 2.1e-3 at h = 1). `clamp=supports` holds every particle "
        "whose support reaches x = 0 at the exact displacement (SPH's case: its unknowns are "
        "the particle displacements, so this is exact); `clamp=timoshenko` loads x = 0 with "
        "the solution's own traction and fixes the rigid motion only (EFG ci's case: the "
        "problem whose solution the analytic one is, 001 [21]). Under them EFG ci converges "
        "(L2 1.2e-2, 1.2e-3, 8.4e-5, 3.8e-5, 3.8e-6 from h = 3 to 0.75) and SPH's error "
        "stays near 50 % (0.54 … 0.48): at a fixed radius its uncorrected sums are cut by the "
        "free faces y = ±6 over a strip as wide as the support, which refinement does not "
        "narrow. The verdicts above are judged on each case's own clamp; the ledger lists the "
        "others.",
        "Own-rule errors use each method's own quadrature, values and gradients (001: 'the "
        "integrals are evaluated numerically by the procedure that is used to evaluate the nodal "
        "forces'); common-rule errors use 4×4 Gauss on a uniform grid and the trial field "
        "(for SPH and RLM, whose unknowns are particle values, a linear MLS fit of those values "
        "with the method's kernel).",
    };
  }

 private:
  double L_ = 48, D_ = 12, P_ = 1000;
  LinearElastic material_;
  double Ee_, nue_;
  Placement placement_;
  Clamp clamp_;
};

}  // namespace

void register_cantilever(ProblemRegistry& r) {
  r.add("cantilever",
        "Timoshenko cantilever L=48, D=12, E=3e7, nu=0.3, parabolic end shear P=1000 (001 §9.1); "
        "nodes = particles across the depth",
        {ParamSpec::choice("plane", "stress", {"stress", "strain"}, "plane stress or plane strain"),
         ParamSpec::choice("placement", "boundary", {"boundary", "inset"},
                           "particles on the boundary (001 Fig. 4b) or inset by half a spacing "
                           "(Fig. 4a)"),
         ParamSpec::choice("clamp", "side", {"side", "supports", "timoshenko"},
                           "x = 0 (001 does not say how it is held): the exact displacement at "
                           "the particles on it (side) or at every particle whose support "
                           "reaches it (supports), or Timoshenko & Goodier's support: the exact "
                           "traction on it, the rigid motion fixed at its centre and top "
                           "particles (timoshenko)")},
        [](const Params& p) {
          return std::make_unique<Cantilever>(
              p.text("plane") == "strain",
              p.text("placement") == "inset" ? Placement::inset : Placement::boundary,
              p.text("clamp") == "supports"     ? Cantilever::Clamp::supports
              : p.text("clamp") == "timoshenko" ? Cantilever::Clamp::timoshenko
                                                : Cantilever::Clamp::side);
        });
}

}  // namespace mfv
