/// The `time-step` analysis: the critical time step of central differences for any
/// registered method on a TimeStepProblem's structure, Δt_crit = 2/√λ_max of K φ = λ M φ with K
/// the explicit engine's own tangent stiffness (stability/critical_step.hpp) and M the lumped
/// or the consistent mass. Δt is also printed over Δx/c (c the dilatational wave speed):
/// linear FEM gives 1 (lumped) and 1/√3 (consistent) in 1D. For rkpm it adds the GRK table
/// of 004 III §5.2, Δt against the dilation index j, and the kernel stability count of
/// 004 III §5.1 (nodes under a Gaussian window, eq 5.1.3).
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "analyses/figures.hpp"
#include "methods/core/clock.hpp"
#include "methods/core/errors.hpp"
#include "problems/time_step.hpp"
#include "stability/critical_step.hpp"

namespace mfv {

using namespace time_step_headline;

namespace {

struct StepPair {
  double lumped = 0, consistent = 0;  ///< 0: not computed
  double row_sum = 0;                 ///< row-sum lumped consistent mass; 0: not computed
  double power = 0;                   ///< engine's power iteration (lumped), 0 if not run
  double window = 0;                  ///< dilation a of the middle particle (eq 5.2.5's r)
  CriticalStep lumped_detail, consistent_detail, row_sum_detail;
  GrkEq525Sum eq525_sums;             ///< eq 5.2.5 as a sum over the particles (Gaussian rkpm)
};

/// Δt of one method on the problem's particles.
StepPair steps(const TimeStepDefinition& p, const Registries& cat, const Method& method,
               int nodes, bool lumped, bool consistent, bool row_sum, bool power,
               const EigenOptions& eo,
               std::string* setup, std::string* description, int* particles, double* dxc,
               std::string* skipped = nullptr) {
  if (nodes < 3) throw InputError(fmt::format("time-step needs at least 3 nodes, got {}", nodes));
  const Domain dom = p.domain();
  const int dim = dom.dim;
  ParticleSet ps = p.block ? rectangle_lattice(dom, nodes, (nodes - 1) / 2 + 1, Placement::boundary)
                          : uniform_line(dom, nodes);
  Params mp;
  mp.set("E", p.block ? TimeStepDefinition::kBlockE : TimeStepDefinition::kE);
  mp.set("nu", p.block ? TimeStepDefinition::kBlockNu : 0.0);
  if (p.block) mp.set("plane", "strain");
  const auto material = std::shared_ptr<const Material>(cat.materials.create("svk", mp));
  const double rho = p.block ? TimeStepDefinition::kBlockRho : TimeStepDefinition::kRho * TimeStepDefinition::kA;  // 1D: mass per length
  const double c = material->wave_speed(dim, p.block ? TimeStepDefinition::kBlockRho : TimeStepDefinition::kRho);
  const double dx = ps.spacing > 0 ? ps.spacing : (dom.upper[0] - dom.lower[0]) / (nodes - 1);
  Discretization d = method.discretize(dom, std::move(ps), 1);
  // The explicit engine's force tables span the particles only (no enrichment unknowns).
  refuse_enrichment(d, "the time-step analysis");
  if (description) *description = d.description;
  // Row-sum mass: like the consistent one, only where the unknowns have shape functions.
  if (d.particle_values) {
    if (row_sum && !lumped)
      throw InputError(fmt::format("{} has no shape-function values at its points "
                                   "(collocation), so no row-sum mass; use mass=lumped",
                                   d.description));
    row_sum = false;
  }
  if (consistent && lumped && d.particle_values) {
    // mass=both on a collocation method: its unknowns are particle values with no shape
    // functions at the points, so only the lumped mass exists.
    consistent = false;
    if (skipped)
      *skipped = fmt::format("consistent mass skipped: {} has no shape-function values at its "
                             "points (collocation)",
                             d.description);
  }
  if (particles) *particles = d.particles.size();
  if (dxc) *dxc = dx / c;
  const int n = d.particles.size();
  const double window = n > 0 ? d.particles.dilation[n / 2] : 0.0;
  const GrkEq525Sum eq525_sums =
      p.block ? GrkEq525Sum{} : grk_critical_step_eq525_sums(d, dx, c);
  std::vector<int> fixed;
  if (p.fixed)
    for (int I = 0; I < n; ++I)
      if (d.particles.x(0, I) <= dom.lower[0] + 1e-9 * dx)
        for (int k = 0; k < dim; ++k) fixed.push_back(dim * I + k);
  DynamicsModel model;
  model.material = material;
  model.density = p.block ? TimeStepDefinition::kBlockRho : TimeStepDefinition::kRho;
  model.mass = lumped_masses(d.particles, rho, MassLumping::volume);
  for (int u : fixed) model.prescribed.push_back({u / dim, u % dim, 0.0});
  const Eigen::VectorXd masses = model.mass;
  DynamicsOptions opt;
  opt.frame = p.frame;
  opt.threads = 1;
  ExplicitDynamics engine(method, std::move(d), std::move(model), opt);
  StepPair out;
  out.window = window;
  out.eq525_sums = eq525_sums;
  CriticalStepOptions o;
  o.fixed = fixed;
  o.eigen = eo;
  if (lumped) {
    o.mass = MassKind::lumped;
    out.lumped_detail = critical_step(engine, masses, rho, o);
    out.lumped = out.lumped_detail.dt;
  }
  if (consistent) {
    o.mass = MassKind::consistent;
    out.consistent_detail = critical_step(engine, masses, rho, o);
    out.consistent = out.consistent_detail.dt;
  }
  if (row_sum) {
    o.mass = MassKind::row_sum;
    out.row_sum_detail = critical_step(engine, masses, rho, o);
    out.row_sum = out.row_sum_detail.dt;
  }
  if (power) out.power = engine.critical_time_step(60);
  if (setup)
    *setup = fmt::format(
        "{}, {} particles (Δx = {:g}), {}, ρ = {:g}, c = {:.6g} (Δx/c = {:.6g}), {}, {} kernel, "
        "K by central differences of the engine's force (step 1e-6 Δx)",
        p.block ? "2:1 plane-strain block [0,1]×[0,0.5]" : "004 III §6 bar L = 100 in, A = 1 in²",
        n, dx, material->description(dim), p.block ? TimeStepDefinition::kBlockRho : TimeStepDefinition::kRho, c, dx / c,
        p.fixed ? (p.block ? "left side fixed" : "x = 0 fixed") : "free ends",
        p.frame == KernelFrame::lagrangian ? "Lagrangian" : "Eulerian");
  return out;
}

class TimeStep final : public FigureAnalysis {
 public:
  bool accepts(const Problem& problem) const override {
    return dynamic_cast<const TimeStepProblem*>(&problem) != nullptr;
  }
  void run(const AnalysisContext& c, CaseResult& r) const override {
  const TimeStepDefinition& p =
        definition_of<TimeStepProblem>(c, "time-step", "a structure (a TimeStepProblem)")
            .definition();
    const double t0 = cpu_seconds();
    const int nodes = c.spec.nodes > 0 ? c.spec.nodes : 21;
    const bool want_lumped = p.mass == "lumped" || p.mass == "both",
               want_consistent = p.mass == "consistent" || p.mass == "both",
               want_row_sum = p.mass == "row-sum" || p.mass == "both";
    // mass=both on a collocation method: lumped only, said in the verdicts (steps()).
    bool consistent = want_consistent;
    std::string skipped;
    EigenOptions eo;
    eo.keep_spectrum = true;
    std::string setup, description;
    int particles = 0;
    double dxc = 0;
    const StepPair s = steps(p, c.plugins, c.method, nodes, want_lumped, consistent, want_row_sum,
                             want_lumped, eo, &setup, &description, &particles, &dxc, &skipped);
    const bool row_sum = s.row_sum > 0;
    if (!skipped.empty()) consistent = false;
    const double t1 = cpu_seconds();
    r.particles = particles;
    r.dim = p.block ? 2 : 1;
    r.components = r.dim;
    r.h = p.block ? 1.0 / (nodes - 1) : TimeStepDefinition::kL / (nodes - 1);
    r.method_description = description;
    FigureData& a = r.emplace<FigureData>();
    const CriticalStep& any = want_lumped  ? s.lumped_detail
                              : row_sum    ? s.row_sum_detail
                                           : s.consistent_detail;
    a.setup = fmt::format("{}; {} free unknowns, reach {:.3g} Δx, {} colours, {} force "
                          "evaluations per mass; eigensolver: {}",
                          setup, any.unknowns, any.probe.reach / r.h, any.probe.colours,
                          any.probe.force_evaluations, any.eigen.solver);
    if (!skipped.empty()) a.verdicts.push_back(skipped);
    if (want_lumped) {
      r.headline[kLumped] = s.lumped;
      r.headline[kLumpedRatio] = s.lumped / dxc;
      a.verdicts.push_back(fmt::format(
          "lumped mass: Δt = {:.5g} = {:.4f} Δx/c; power iteration (60 steps) {:.5g}", s.lumped,
          s.lumped / dxc, s.power));
    }
    if (consistent) {
      r.headline[kConsistent] = s.consistent;
      r.headline[kConsistentRatio] = s.consistent / dxc;
      a.verdicts.push_back(fmt::format("consistent mass: Δt = {:.5g} = {:.4f} Δx/c", s.consistent,
                                       s.consistent / dxc));
    }
    if (row_sum) {
      r.headline[kRowSum] = s.row_sum;
      r.headline[kRowSumRatio] = s.row_sum / dxc;
      a.verdicts.push_back(fmt::format("row-sum mass (consistent mass lumped by rows): Δt = "
                                       "{:.5g} = {:.4f} Δx/c",
                                       s.row_sum, s.row_sum / dxc));
    }
    if (want_lumped && consistent) {
      r.headline[kMassRatio] = s.consistent / s.lumped;
      a.verdicts.push_back(fmt::format("consistent / lumped = {:.4f} (linear FEM in 1D: 1/√3 = "
                                       "0.5774)",
                                       s.consistent / s.lumped));
    }
    // Gaussian rkpm on the bar: 004 III eq 5.2.5 in each reading, beside our eigenvalues.
    if (!p.block && c.spec.method == "rkpm" &&
        c.plugins.methods.resolve("rkpm", c.spec.method_params).text("kernel") == "gaussian") {
      const double eq525 = grk_critical_step_eq525(s.window, r.h, r.h / dxc);
      r.headline[kEq525] = eq525;
      r.headline[kEq525OverSqrt2] = eq525 / std::sqrt(2.0);
      r.headline[kEq525Node] = s.eq525_sums.at_middle;
      r.headline[kEq525Min] = s.eq525_sums.smallest;
      if (row_sum) r.headline[kEq525OverRowSum] = eq525 / s.row_sum;
      if (want_lumped) r.headline[kEq525OverLumped] = eq525 / s.lumped;
      a.verdicts.push_back(fmt::format(
          "eq 5.2.5 (004 III's analytic column) for this window: continuous interior sum {:.5g} "
          "s, the printed sum at the middle node {:.5g} s, its smallest value over x {:.5g} s "
          "(at x = {:.4g})",
          eq525, s.eq525_sums.at_middle, s.eq525_sums.smallest, s.eq525_sums.x_smallest));
    }
    if (any.eigen.asymmetry > 1e-6)
      a.verdicts.push_back(fmt::format("K is not symmetric (max |K − Kᵀ| / max |K| = {:.2e}): "
                                       "largest |Im λ| = {:.3g} of λ_max = {:.6g}",
                                       any.eigen.asymmetry, any.eigen.max_imaginary,
                                       any.eigen.lambda_max));
    // The spectrum: ω_k (sorted), both masses.
    {
      FigureData::Table t{"spectrum", {"mode"}, {}};
      std::vector<const std::vector<double>*> cols;
      if (want_lumped) t.columns.push_back("omega_lumped"), cols.push_back(&s.lumped_detail.eigen.spectrum);
      if (row_sum) t.columns.push_back("omega_row_sum"), cols.push_back(&s.row_sum_detail.eigen.spectrum);
      if (consistent)
        t.columns.push_back("omega_consistent"), cols.push_back(&s.consistent_detail.eigen.spectrum);
      std::size_t rows = 0;
      for (auto* v : cols) rows = std::max(rows, v->size());
      a.figures.push_back({"spectrum", "Frequencies of K φ = ω² M φ", "mode", "ω Δx / c", false,
                           "linespoints"});
      for (std::size_t k = 0; k < cols.size(); ++k) {
        const std::string& col = t.columns[k + 1];
        FigureData::Curve cv{"spectrum",
                             col == "omega_lumped"    ? "lumped"
                             : col == "omega_row_sum" ? "row-sum"
                                                      : "consistent",
                             {}, {}};
        for (std::size_t i = 0; i < cols[k]->size(); ++i) {
          const double l = (*cols[k])[i];
          cv.x.push_back(static_cast<double>(i + 1));
          cv.y.push_back((l >= 0 ? std::sqrt(l) : -std::sqrt(-l)) * dxc);
        }
        a.curves.push_back(std::move(cv));
      }
      for (std::size_t i = 0; i < rows; ++i) {
        std::vector<double> line{static_cast<double>(i + 1)};
        for (auto* v : cols) {
          const double l = i < v->size() ? (*v)[i] : NAN;
          line.push_back(l >= 0 ? std::sqrt(l) : -std::sqrt(-l));
        }
        t.rows.push_back(std::move(line));
      }
      if (rows) a.tables.push_back(std::move(t));
    }
    // rkpm: the GRK table of 004 III §5.2, Δt against j, and the §5.1 window count.
    if (c.spec.method == "rkpm") {
      const Params base = c.plugins.methods.resolve("rkpm", c.spec.method_params);
      EigenOptions quiet;
      auto at_j = [&](double j) {
        Params mq = base;
        mq.set("j", j);
        const auto m = c.plugins.methods.create("rkpm", mq);
        return steps(p, c.plugins, *m, nodes, true, true, true, false, quiet, nullptr, nullptr,
                     nullptr, nullptr);
      };
      // 004 III's table is the Gaussian window's (GRK): with another kernel its narrow
      // windows (j = −1) hold one particle and no basis; the analysis says so instead of
      // failing (issue 46: every analysis for every kernel the method accepts).
      const bool gaussian = base.text("kernel") == "gaussian";
      if (!p.block && !gaussian)
        a.verdicts.push_back(fmt::format(
            "the GRK table of 004 III §5.2 is the Gaussian window's (eq 5.2.5 and its j = −1 "
            "… 1 rows): not computed for kernel {}; the critical steps above are this kernel's",
            base.text("kernel")));
      if (!p.block && gaussian) {
        FigureData::Table t{"grk-table",
                              {"j", "dt_lumped", "dt_row_sum", "dt_consistent",
                               "paper_analytic", "eq525_ours", "eq525_sum_middle",
                               "eq525_sum_smallest", "paper_numeric", "fem_l_over_c"},
                              {}};
        for (const auto& row : kGrkTable) {
          const StepPair q = at_j(row[0]);
          // Eq 5.2.5 holds for the Gaussian window only (problems/time_step.hpp).
          const double eq525 = base.text("kernel") == "gaussian"
                                   ? grk_critical_step_eq525(q.window, r.h, r.h / dxc)
                                   : NAN;
          const bool g = base.text("kernel") == "gaussian";
          const double mid = g ? q.eq525_sums.at_middle : NAN;
          const double low = g ? q.eq525_sums.smallest : NAN;
          t.rows.push_back({row[0], q.lumped, q.row_sum, q.consistent, row[1], eq525, mid, low,
                            row[2], dxc});
          a.verdicts.push_back(fmt::format(
              "GRK j = {:g} ({} {}): Δt lumped (particle volumes) {:.4g}, row-sum {:.4g}, "
              "consistent {:.4g}; 004 numeric {:.4g} s; 004 analytic {:.4g}, eq 5.2.5 as we "
              "read it: continuous {:.4g}, sum at the middle node {:.4g}, smallest sum over x "
              "{:.4g} s",
              row[0], base.text("kernel"), base.text("rule"), q.lumped, q.row_sum, q.consistent,
              row[2], row[1], eq525, mid, low));
        }
        a.tables.push_back(std::move(t));
      }
      if (p.sweep) {
        a.figures.push_back({"dt-vs-j", "Critical step against the dilation index j",
                             "j", "Δt / (Δx/c)", false, "linespoints"});
        FigureData::Curve cl{"dt-vs-j", "lumped", {}, {}}, cc{"dt-vs-j", "consistent", {}, {}};
        FigureData::Table t{"dt-vs-j", {"j", "dt_lumped_over_dxc", "dt_consistent_over_dxc"}, {}};
        for (double j = -1.5; j <= 1.5 + 1e-9; j += 0.5) {
          StepPair q;
          try {
            q = at_j(j);
          } catch (const SingularError& e) {
            // A window too narrow for the kernel's support: that j has no step, said so.
            a.verdicts.push_back(fmt::format("sweep j = {:g}: no step ({})", j, e.what()));
            continue;
          }
          cl.x.push_back(j), cl.y.push_back(q.lumped / dxc);
          cc.x.push_back(j), cc.y.push_back(q.consistent / dxc);
          t.rows.push_back({j, q.lumped / dxc, q.consistent / dxc});
        }
        a.curves.push_back(std::move(cl));
        a.curves.push_back(std::move(cc));
        a.tables.push_back(std::move(t));
      }
      FigureData::Table w{"window-nodes",
                            {"j", "n_2s_ours", "n_2s_paper", "n_3s_ours", "n_3s_paper"},
                            {}};
      double worst = 0;
      for (const auto& row : kWindowTable) {
        const double n2 = gaussian_window_nodes(row[0], std::exp(-4.0));
        const double n3 = gaussian_window_nodes(row[0], std::exp(-9.0));
        worst = std::max({worst, std::abs(n2 - row[1]), std::abs(n3 - row[2])});
        w.rows.push_back({row[0], n2, row[1], n3, row[2]});
      }
      a.tables.push_back(std::move(w));
      r.headline["n(j,R) worst deviation from 004 III §5.1"] = worst;  // the ledger's measure
      a.verdicts.push_back(fmt::format("004 III §5.1 window count n(j, R) reproduced to {:.3f} nodes "
                                       "(the paper rounds to 0.01)",
                                       worst));
    }
    r.cpu.assembly = t1 - t0;
    r.cpu.solve = cpu_seconds() - t1;
  }
};

}  // namespace

void register_time_step_analysis(AnalysisRegistry& r) {
  r.add("time-step",
        "critical time step 2/omega_max of central differences: K from the explicit engine's "
        "force, lumped or consistent mass; the 004 III §5 GRK table and window count",
        {}, [](const Params&) { return std::make_unique<TimeStep>(); });
}

}  // namespace mfv
