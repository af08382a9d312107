/// `enriched-bar`: stability of the explicit extended EFG (003, Samaniego et al., "Contributions
/// to the stability analysis of explicit enriched meshfree methods"). An analysis problem:
///
/// 1. Sweep: a crack moved from one node to the next (relative position s ∈ [0, 1]) through a
///    1D bar of 10 particles 1 m apart (E = 200 GPa, ρ = 7850, DMAX = 2.3, cubic spline,
///    linear basis, 003 §4) or a 2D patch (a crack through it, or from the bottom edge to a
///    tip at relative y = 0.9 inside the middle row of cells, 003 §4.3.1); for each DMAX and
///    mass scheme (consistent eq 13, MLS1 eqs 14-16, MLS2 eqs 19-22) the ratio
///    Δt_crack / Δt_no-crack, Δt = 2/√λ_max (eq 12).
/// 2. Fit (003 §4.3.3, eqs 23-30): λ_max of the integration cell's K_cell φ = λ M_cell φ
///    (eq 29: λ = E/(ρΔx²) λ(M_dmax, K_dmax)) for an interior cell of a long uniform bar,
///    row-sum and MLS1 lumping, fitted to λ = α E/(ρ Δx² DMAX²) (eq 30) by least squares in
///    1/DMAX²; with the trimming heuristic only the shape functions whose middle half of the
///    support [0.25 s, 0.75 s] covers the cell count (even DMAX).
#include "problems/enriched_bar.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include <fmt/format.h>

#include "methods/approximations/enriched.hpp"
#include "methods/core/errors.hpp"
#include "problems/problem.hpp"
#include "verify/catalogue.hpp"
#include "verify/runner.hpp"

namespace mfv {

namespace {

int columns(const Discretization& d) { return d.particles.size() + d.enriched_unknowns; }

}  // namespace

Eigen::MatrixXd enriched_stiffness(const Discretization& d, const BarMaterial& m) {
  const ShapeTable& t = d.trial_q;
  const int dim = t.dim, nc = dim, n = columns(d) * nc;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
  Eigen::Matrix3d D = Eigen::Matrix3d::Zero();
  if (dim == 2) {
    const double E = m.E, v = m.nu;
    if (m.plane_strain) {
      const double c = E / ((1 + v) * (1 - 2 * v));
      D << c * (1 - v), c * v, 0, c * v, c * (1 - v), 0, 0, 0, c * (1 - 2 * v) / 2;
    } else {
      const double c = E / (1 - v * v);
      D << c, c * v, 0, c * v, c, 0, 0, 0, c * (1 - v) / 2;
    }
  }
  for (int q = 0; q < t.points(); ++q) {
    const int a = t.offsets[q], k = t.offsets[q + 1] - a;
    const double w = d.quadrature.weights[q];
    if (dim == 1) {
      for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j)
          K(t.index[a + i], t.index[a + j]) += w * m.E * t.grad[a + i] * t.grad[a + j];
      continue;
    }
    // B (3 × 2k): ε = (u_x,x, u_y,y, u_x,y + u_y,x).
    Eigen::MatrixXd B = Eigen::MatrixXd::Zero(3, 2 * k);
    for (int i = 0; i < k; ++i) {
      const double gx = t.grad[(a + i) * 2], gy = t.grad[(a + i) * 2 + 1];
      B(0, 2 * i) = gx;
      B(1, 2 * i + 1) = gy;
      B(2, 2 * i) = gy;
      B(2, 2 * i + 1) = gx;
    }
    const Eigen::MatrixXd Kq = w * B.transpose() * D * B;
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < k; ++j)
        K.block<2, 2>(2 * t.index[a + i], 2 * t.index[a + j]) += Kq.block<2, 2>(2 * i, 2 * j);
  }
  return K;
}

Eigen::MatrixXd enriched_mass(const Discretization& d, const BarMaterial& m, MassScheme s,
                              bool mls1_per_point) {
  const ShapeTable& t = d.trial_q;
  const int dim = t.dim, nc = columns(d), N = d.particles.size();
  // One component's matrix, expanded to the interleaved components at the end.
  Eigen::MatrixXd M1 = Eigen::MatrixXd::Zero(nc, nc);
  for (int q = 0; q < t.points(); ++q) {
    const double w = m.rho * d.quadrature.weights[q];
    for (int i = t.offsets[q]; i < t.offsets[q + 1]; ++i)
      for (int j = t.offsets[q]; j < t.offsets[q + 1]; ++j)
        M1(t.index[i], t.index[j]) += w * t.value[i] * t.value[j];
  }
  Eigen::VectorXd lumped;
  switch (s) {
    case MassScheme::consistent: break;
    case MassScheme::row_sum: lumped = M1.rowwise().sum(); break;
    case MassScheme::mls1: {
      if (d.quadrature.cell.size() != static_cast<std::size_t>(d.quadrature.size()))
        throw std::logic_error("MLS1 lumping needs the integration cell of every point");
      const int cells =
          mls1_per_point ? d.quadrature.size()
                         : *std::max_element(d.quadrature.cell.begin(), d.quadrature.cell.end()) + 1;
      Eigen::MatrixXd diag = Eigen::MatrixXd::Zero(nc, cells);  // ∫_h ρ Ñ_I²
      Eigen::VectorXd mass = Eigen::VectorXd::Zero(cells);      // M_h
      for (int q = 0; q < t.points(); ++q) {
        const double w = m.rho * d.quadrature.weights[q];
        const int h = mls1_per_point ? q : d.quadrature.cell[q];
        mass[h] += w;
        for (int i = t.offsets[q]; i < t.offsets[q + 1]; ++i)
          diag(t.index[i], h) += w * t.value[i] * t.value[i];
      }
      lumped = Eigen::VectorXd::Zero(nc);
      for (int h = 0; h < cells; ++h) {
        const double sum = diag.col(h).sum();
        if (sum > 0) lumped += mass[h] / sum * diag.col(h);  // eq 16's ϑ_h
      }
      break;
    }
    case MassScheme::mls2: {
      lumped = Eigen::VectorXd::Zero(nc);
      lumped.head(N) = M1.topLeftCorner(N, N).rowwise().sum();
      if (d.enriched_unknowns > 0) {
        const auto* e = dynamic_cast<const EnrichedApproximation*>(d.trial.get());
        if (!e) throw std::logic_error("MLS2 lumping of enrichment columns needs xefg");
        const std::vector<Enrichment> enr = e->enrichments(d.particles);
        for (int c = 0; c < static_cast<int>(enr.size()); ++c) {
          const int I = enr[c].node;
          lumped[N + c] = lumped[I] * M1(N + c, N + c) / M1(I, I);
        }
      }
      break;
    }
  }
  const int n = nc * dim;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < nc; ++i)
    for (int c = 0; c < dim; ++c) {
      if (s == MassScheme::consistent) {
        for (int j = 0; j < nc; ++j) M(i * dim + c, j * dim + c) = M1(i, j);
      } else {
        M(i * dim + c, i * dim + c) = lumped[i];
      }
    }
  return M;
}

double largest_eigenvalue(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M, bool diagonal) {
  const double inf = std::numeric_limits<double>::infinity();
  if (diagonal) {
    const Eigen::VectorXd m = M.diagonal();
    if (!(m.minCoeff() > 0)) return inf;
    const Eigen::VectorXd s = m.cwiseSqrt().cwiseInverse();
    const Eigen::MatrixXd A = s.asDiagonal() * K * s.asDiagonal();
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(A, Eigen::EigenvaluesOnly);
    return es.eigenvalues().maxCoeff();
  }
  Eigen::LLT<Eigen::MatrixXd> llt(M);
  if (llt.info() != Eigen::Success) return inf;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(K, M, Eigen::EigenvaluesOnly);
  if (es.info() != Eigen::Success) return inf;
  return es.eigenvalues().maxCoeff();
}

double critical_step(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M, bool diagonal) {
  return 2 / std::sqrt(largest_eigenvalue(K, M, diagonal));
}

namespace {

constexpr const char* kSchemeNames[] = {"consistent", "row-sum", "MLS1", "MLS2"};
const MassScheme kSweepSchemes[] = {MassScheme::consistent, MassScheme::mls1, MassScheme::mls2};

const char* scheme_name(MassScheme s) { return kSchemeNames[static_cast<int>(s)]; }

double support_factor(const std::string& convention) {
  return convention == "diameter" ? 0.5 : convention == "2h" ? 2.0 : 1.0;
}

/// One α fit: per-DMAX λ (in E/(ρΔx²)) of the row-sum and MLS1 cell problems.
struct AlphaFit {
  std::vector<double> dmax, row_sum, mls1;
  double alpha_row_sum = NAN, alpha_mls1 = NAN;
};

/// α of λ = α / DMAX² (eq 30 with E = ρ = Δx = 1), least squares in the relative misfit
/// (α/DMAX² − λ)/λ so that every DMAX counts alike (003 does not say how it fitted).
double fit_alpha(const std::vector<double>& dmax, const std::vector<double>& lambda) {
  double num = 0, den = 0;
  for (std::size_t i = 0; i < dmax.size(); ++i) {
    if (!std::isfinite(lambda[i]) || !(lambda[i] > 0)) continue;
    const double c = 1 / (dmax[i] * dmax[i] * lambda[i]);
    num += c;
    den += c * c;
  }
  return den > 0 ? num / den : NAN;
}

class EnrichedBar final : public Problem {
 public:
  explicit EnrichedBar(const Params& p) : p_(p) {
    dim_ = p.integer("dim");
    if (dim_ != 1 && dim_ != 2)
      throw InputError(fmt::format("enriched-bar: dim must be 1 (the 003 bar) or 2 (the patch), "
                                   "got {}",
                                   dim_));
    n_ = p.integer("particles");
    interval_ = p.number("interval") < 0 ? n_ / 2 - 1 : p.integer("interval");
    if (interval_ < 0 || interval_ > n_ - 2)
      throw InputError(fmt::format("enriched-bar: interval={} puts the crack outside the bar "
                                   "(node intervals 0..{} for particles={}); choose one inside",
                                   interval_, n_ - 2, n_));
    tip_ = p.number("tip_y");
    if (!(tip_ > 0 && tip_ < 1))
      throw InputError(fmt::format("enriched-bar: tip_y={} must lie strictly between 0 and 1 "
                                   "(relative y of the tip inside its row of cells)",
                                   tip_));
    mat_.E = p.number("E");
    mat_.rho = p.number("rho");
    mat_.nu = p.number("nu");
    mat_.plane_strain = p.text("plane") == "strain";
  }

  Domain domain() const override {
    const double L = n_ - 1.0;
    return dim_ == 1 ? Domain::interval(0, L) : Domain::rectangle(0, 0, L, L);
  }
  int components() const override { return dim_; }
  AssembledSystem assemble(const Discretization&) const override {
    throw std::logic_error("enriched-bar is an analysis: the runner calls analyse");
  }
  bool analysis() const override { return true; }
  std::vector<int> resolutions(Level) const override { return {n_}; }

  void analyse(const AnalysisContext& c, CaseResult& r) const override {
    if (c.spec.method != "xefg")
      throw InputError(fmt::format("enriched-bar analyses the extended EFG: run it with -m xefg "
                                   "(got method '{}')",
                                   c.spec.method));
    const Params mp = c.catalogue.methods.resolve("xefg", c.spec.method_params);
    if (mp.text("crack") != "none")
      throw InputError("enriched-bar moves the crack itself: leave the method's crack=none "
                       "(set the swept interval with the problem's 'interval')");
    const double dmax0 = mp.number("dmax");
    std::vector<double> dmaxes;
    // Defaults (0) keep a 2D run to seconds: one DMAX and six positions.
    const int ndmax = p_.integer("dmax_count") > 0 ? p_.integer("dmax_count") : dim_ == 1 ? 3 : 1;
    for (int k = 0; k < ndmax; ++k)
      dmaxes.push_back(dmax0 + k * p_.number("dmax_step"));
    const int npos = p_.integer("positions") > 0 ? p_.integer("positions") : dim_ == 1 ? 21 : 6;
    const Domain dom = domain();
    const ParticleSet base = dim_ == 1 ? uniform_line(dom, n_)
                                       : rectangle_lattice(dom, n_, n_, Placement::boundary);
    double t_assembly = 0, t_solve = 0;
    const bool mls1_point = p_.text("mls1") == "point";
    std::vector<int> active;
    for (int i = 0; i < 3; ++i)
      if (p_.text("mass") == "all" || p_.text("mass") == scheme_name(kSweepSchemes[i]))
        active.push_back(i);

    // Δt of every mass scheme for a method variant.
    const auto steps = [&](const Params& q, int& enriched) {
      const double a = cpu_seconds();
      const auto m = c.catalogue.methods.create("xefg", q);
      const Discretization d = m->discretize(dom, base, 1);
      enriched = d.enriched_unknowns;
      if (r.method_description.empty()) r.method_description = d.description;
      const Eigen::MatrixXd K = enriched_stiffness(d, mat_);
      std::vector<Eigen::MatrixXd> M(3);
      for (int i : active) M[i] = enriched_mass(d, mat_, kSweepSchemes[i], mls1_point);
      const double b = cpu_seconds();
      std::vector<double> dt(3, NAN);
      for (int i : active)
        dt[i] = critical_step(K, M[i], kSweepSchemes[i] != MassScheme::consistent);
      t_assembly += b - a;
      t_solve += cpu_seconds() - b;
      return dt;
    };

    r.dim = dim_;
    r.components = dim_;
    r.h = 1;
    r.particles = base.size();
    AnalysisData& an = r.analysis;
    const double x0 = interval_;
    const double y_tip = (n_ / 2 - 1) + tip_;
    an.setup = fmt::format(
        "{}: {} particles 1 m apart, E = {:g} Pa, rho = {:g} kg/m3{}; crack swept from x = {} "
        "to x = {} in {} steps; DMAX = {}; xefg: {}. Ratios are dt(crack)/dt(no crack) with the "
        "same mass scheme and DMAX.",
        dim_ == 1 ? "1D bar" : "2D patch", dim_ == 1 ? n_ : n_ * n_, mat_.E, mat_.rho,
        dim_ == 2 ? fmt::format(", nu = {}, plane {}, tip at y = {}", mat_.nu,
                                mat_.plane_strain ? "strain" : "stress", y_tip)
                  : "",
        x0, x0 + 1, npos - 1, fmt::join(dmaxes, ", "), mp.to_string());

    // 1. Sweeps: through crack (1D and 2D) and, in 2D, the edge crack with its tip.
    std::vector<std::string> cases{"through"};
    if (dim_ == 2) cases.push_back("edge");
    AnalysisData::Table sweep{"dt-sweep",
                              {"tip", "dmax", "position", "dt consistent", "dt MLS1", "dt MLS2",
                               "ratio consistent", "ratio MLS1", "ratio MLS2",
                               "enriched columns"},
                              {}};
    for (const std::string& kind : cases) {
      const std::string suffix = kind == "edge" ? " tip" : "";
      const std::string fig = kind == "edge" ? "dt-ratio-tip" : "dt-ratio";
      an.figures.push_back({fig,
                            kind == "edge"
                                ? fmt::format("dt ratio, crack tip at y = {} ({} enrichment)",
                                              y_tip, p_.text("tip"))
                                : "dt ratio, crack through the " +
                                      std::string(dim_ == 1 ? "bar" : "patch"),
                            "relative crack position between two nodes",
                            "dt(crack) / dt(no crack)", false, "linespoints"});
      an.figures.push_back({kind == "edge" ? "dt-tip" : "dt", "critical time step" + suffix, "relative crack position",
                            "dt (s)", false, "linespoints"});
      for (double dm : dmaxes) {
        Params q = c.spec.method_params;
        q.set("dmax", dm);
        int en = 0;
        const std::vector<double> ref = steps(q, en);
        std::vector<AnalysisData::Curve> ratio(3), abs(3);
        for (int i = 0; i < 3; ++i) {
          ratio[i] = {fig, fmt::format("{} DMAX={}", scheme_name(kSweepSchemes[i]), dm), {}, {}};
          abs[i] = {an.figures.back().id, ratio[i].label, {}, {}};
        }
        for (int k = 0; k < npos; ++k) {
          const double s = npos > 1 ? static_cast<double>(k) / (npos - 1) : 0.5;
          q.set("crack", kind.c_str());
          q.set("crack_x", x0 + s);
          if (kind == "edge") {
            q.set("crack_tip", y_tip);
            q.set("tip", p_.text("tip").c_str());
          }
          const std::vector<double> dt = steps(q, en);
          std::vector<double> row{kind == "edge" ? 1.0 : 0.0, dm, s};
          for (int i = 0; i < 3; ++i) row.push_back(dt[i]);
          for (int i = 0; i < 3; ++i) row.push_back(dt[i] / ref[i]);
          for (int i : active) {
            const double rr = dt[i] / ref[i];
            ratio[i].x.push_back(s);
            ratio[i].y.push_back(rr);
            abs[i].x.push_back(s);
            abs[i].y.push_back(dt[i]);
          }
          row.push_back(en);
          sweep.rows.push_back(row);
        }
        for (int i : active) {
          const double lo = *std::min_element(ratio[i].y.begin(), ratio[i].y.end());
          const auto at = std::min_element(ratio[i].y.begin(), ratio[i].y.end()) - ratio[i].y.begin();
          const std::string scheme = scheme_name(kSweepSchemes[i]);
          if (dm == dmax0) {
            r.headline[fmt::format("min dt ratio {}{}", scheme, suffix)] = lo;
            // s = 0: the crack through a node, 003's "worst case".
            r.headline[fmt::format("dt ratio at node {}{}", scheme, suffix)] = ratio[i].y.front();
            if (kind == "through") r.headline[fmt::format("dt no crack {}", scheme)] = ref[i];
          }
          an.verdicts.push_back(fmt::format(
              "{}{}, DMAX={}: dt ratio from {:.3f} (s = {:.2f}) to {:.3f}; dt without crack {:.4g} s",
              scheme, kind == "edge" ? " (tip)" : "", dm, lo, ratio[i].x[at],
              *std::max_element(ratio[i].y.begin(), ratio[i].y.end()), ref[i]));
          an.curves.push_back(std::move(ratio[i]));
          an.curves.push_back(std::move(abs[i]));
        }
      }
    }
    an.tables.push_back(std::move(sweep));

    // 2. The α fit of eq 30 (1D cells), for every support convention.
    AnalysisData::Table alpha{"alpha",
                              {"support factor", "dmax", "trimmed", "lambda row-sum",
                               "lambda MLS1", "alpha row-sum", "alpha MLS1", "lambda bar row-sum"},
                              {}};
    const std::string conv = mp.text("support");
    an.figures.push_back({"alpha", "eq 30 fit: lambda_max DMAX^2 rho dx^2 / E (" + conv + ")",
                          "DMAX", "alpha", false, "linespoints"});
    for (const std::string cv : {"radius", "diameter", "2h"}) {
      const double f = support_factor(cv);
      for (bool trimmed : {false, true}) {
        std::vector<double> list;
        if (trimmed) {
          for (int dm = 2; dm <= 8; dm += 2) list.push_back(dm);
        } else {
          // The same support radii (2..8 Δx) in every convention.
          for (int k = 0; k <= 12; ++k) list.push_back((2 + 0.5 * k) / f);
        }
        AlphaFit fit;
        for (double dm : list) {
          double lr, l1, lbar;
          cell_eigenvalues(c, mp, cv, dm, trimmed, lr, l1, lbar, t_assembly, t_solve);
          if (!std::isfinite(lr) && !std::isfinite(l1)) continue;
          fit.dmax.push_back(dm);
          fit.row_sum.push_back(lr);
          fit.mls1.push_back(l1);
          alpha.rows.push_back({f, dm, trimmed ? 1.0 : 0.0, lr, l1, lr * dm * dm, l1 * dm * dm,
                                lbar});
        }
        fit.alpha_row_sum = fit_alpha(fit.dmax, fit.row_sum);
        fit.alpha_mls1 = fit_alpha(fit.dmax, fit.mls1);
        const std::string t = trimmed ? " trimmed" : "";
        if (cv == conv) {
          r.headline["alpha row-sum" + t] = fit.alpha_row_sum;
          r.headline["alpha MLS1" + t] = fit.alpha_mls1;
          for (int s = 0; s < 2; ++s) {
            AnalysisData::Curve cu{"alpha", fmt::format("{}{}", s ? "MLS1" : "row-sum", t), {}, {}};
            for (std::size_t i = 0; i < fit.dmax.size(); ++i) {
              cu.x.push_back(fit.dmax[i]);
              cu.y.push_back((s ? fit.mls1[i] : fit.row_sum[i]) * fit.dmax[i] * fit.dmax[i]);
            }
            an.curves.push_back(std::move(cu));
          }
        }
        an.verdicts.push_back(fmt::format(
            "alpha ({} convention, support radius {} DMAX dx{}): row-sum {:.3f}, MLS1 {:.3f} "
            "(003: row-sum {}; Belytschko et al. 2000: 13.30)",
            cv, f, trimmed ? ", trimmed to the middle half of each support, even DMAX" : "",
            fit.alpha_row_sum, fit.alpha_mls1, trimmed ? "7.1, MLS1 10" : "12.46"));
      }
    }
    an.tables.push_back(std::move(alpha));
    r.cpu.assembly = t_assembly;
    r.cpu.solve = t_solve;
  }

  std::vector<PublishedValue> published() const override {
    const auto pv = [](const char* source, const char* q, double v, const char* note,
                       const char* dim) {
      Params pp;
      pp.set("dim", std::atof(dim));
      return PublishedValue{source, q, "xefg", {}, 10, v, note, pp};
    };
    std::vector<PublishedValue> out;
    for (const char* d : {"1", "2"}) {
      out.push_back(pv("003 §4.3.3", "alpha row-sum", 12.46,
                       "003's own row-sum fit of eq 30 (1D cell problem, support convention not "
                       "stated)", d));
      out.push_back(pv("Belytschko et al. 2000a via 003 §4.3.3", "alpha row-sum", 13.30,
                       "the fit 003 compares with", d));
      out.push_back(pv("003 §4.3.3", "alpha row-sum trimmed", 7.1,
                       "support trimmed to [0.25 s, 0.75 s], even DMAX", d));
      out.push_back(pv("003 §4.3.3", "alpha MLS1 trimmed", 10.0,
                       "support trimmed to [0.25 s, 0.75 s], even DMAX", d));
      out.push_back(pv("003 §5", "min dt ratio MLS2", 0.84,
                       "worst case (crack through a node); §4.3.2 says 85 % in 2D", d));
      out.push_back(pv("003 §5", "min dt ratio MLS1", 0.30, "lower end of '30-45 %'", d));
      out.push_back(pv("003 §5", "min dt ratio MLS1", 0.45, "upper end of '30-45 %'", d));
    }
    out.push_back(pv("003 §4.3.1 Fig. 10", "min dt ratio MLS1 tip", 0.30,
                     "2D, tip at relative y = 0.9 with tip enrichment", "2"));
    out.push_back(pv("003 §4.3.2", "min dt ratio MLS2 tip", 0.85,
                     "'drops to 85 percent' (2D, Figs. 13-16)", "2"));
    return out;
  }

  std::vector<Finding> findings() const override {
    const auto lowest = [](const std::vector<StudySummary>& ss, const std::string& key) {
      double v = NAN;
      for (const auto& s : ss)
        for (const auto& h : s.headlines) {
          const auto it = h.find(key);
          if (it != h.end() && (std::isnan(v) || it->second < v)) v = it->second;
        }
      return v;
    };
    return {
        {"003 §4, Figs. 3-4", "with the consistent mass the critical step does not drop to zero",
         "min dt ratio consistent > 0.1",
         [lowest](const std::vector<StudySummary>& ss) {
           const double v = lowest(ss, "min dt ratio consistent");
           if (std::isnan(v)) return Verdict{"not run", ""};
           return Verdict{v > 0.1 ? "reproduced" : "not reproduced", fmt::format("{:.3f}", v)};
         }, "consistent-nonzero"},
        {"003 §4.3.1, §5", "MLS1 drops the step to 30-45 % of the uncracked one",
         "min dt ratio MLS1 within [0.2, 0.55]",
         [lowest](const std::vector<StudySummary>& ss) {
           const double v = lowest(ss, "min dt ratio MLS1");
           if (std::isnan(v)) return Verdict{"not run", ""};
           const bool in = v >= 0.2 && v <= 0.55;
           return Verdict{in ? "reproduced" : v < 0.2 ? "not reproduced" : "partly",
                          fmt::format("{:.3f}", v)};
         }, "mls1-drop"},
        {"003 §4.3.2, §5", "MLS2 keeps at least about 84 % of the uncracked step",
         "min dt ratio MLS2 >= 0.8",
         [lowest](const std::vector<StudySummary>& ss) {
           const double v = lowest(ss, "min dt ratio MLS2");
           if (std::isnan(v)) return Verdict{"not run", ""};
           return Verdict{v >= 0.8 ? "reproduced" : v >= 0.6 ? "partly" : "not reproduced",
                          fmt::format("{:.3f}", v)};
         }, "mls2-keeps"},
    };
  }

  std::vector<std::string> published_notes() const override {
    return {
        "003 does not state the node numbering of Fig. 2, which DMAX values its curves use, the "
        "2D patch size, Poisson's ratio, plane stress or strain, nor the branch functions of "
        "eq 8; we sweep the middle interval of the bar (or patch), DMAX = dmax, dmax + "
        "dmax_step, ..., plane stress with nu = 0.3 on a 10 × 10 patch, and the four LEFM "
        "branch functions. The tip sits at relative y = tip_y inside the middle row of cells.",
        "MLS2's enriched masses follow eq 22 (the node's row-sum mass for the step, H² = 1); for "
        "branch functions we weight eq 21's mean of ψ² by N_I², so the step case is unchanged.",
        "α depends on the support convention (catalogue reading note): if DMAX·Δx is the "
        "radius, a diameter, or h of a spline in r/2h, the same support radius R gives α "
        "scaled by 1, 4 or 1/4. The table 'alpha' lists all three; the headline uses the "
        "method's `support`. Our fit follows eqs 27-30: λ_max of one interior integration "
        "cell's K_cell φ = λ M_cell φ (4 Gauss points by default), least squares in 1/DMAX² "
        "over support radii 2-8 Δx (relative least squares); the column 'lambda bar row-sum' is "
        "the whole bar's λ_max for comparison (the cell bound is larger). Our per-DMAX α rises "
        "with DMAX toward 003's values (radius convention, DMAX = 8: row sum 12.3, trimmed 6.9, "
        "MLS1 trimmed 9.2), so 003's fits are most likely dominated by large DMAX.",
        "Consistent mass: a crack through a node keeps about 13 % of the step (bounded away from "
        "zero, as 003 says), but a crack just inside the edge of an enriched node's support "
        "makes H N_I differ from ±N_I on a sliver only: M becomes (near) singular and the step "
        "goes to zero (exactly singular when no Gauss point falls in the sliver). 003 does not "
        "report this; 'min dt ratio consistent' includes it, 'dt ratio at node' is 003's case.",
        "MLS1 stays at 0.83 (1D, DMAX 2.3) and 0.60 (2D through crack) instead of 003's "
        "30-45 %, but reaches 0.33-0.40 with a tip at y = 0.9 (003: 30 %). Per-Gauss-point "
        "scaling (mls1=point) changes little. 003's text does not pin down which cells eq 16 "
        "sums over, which may explain the 1D gap.",
    };
  }

 private:
  /// λ_max (units E/(ρΔx²)) of the row-sum and MLS1 cell problems of an interior cell of a
  /// long uniform bar, and of the whole bar with row-sum lumping.
  void cell_eigenvalues(const AnalysisContext& c, const Params& mp, const std::string& conv,
                        double dmax, bool trimmed, double& row_sum, double& mls1, double& bar,
                        double& t_assembly, double& t_solve) const {
    const double a = cpu_seconds();
    row_sum = mls1 = bar = NAN;
    const double R = support_factor(conv) * dmax;  // support radius in Δx
    const int n = 2 * static_cast<int>(std::ceil(R)) + 8;
    const Domain dom = Domain::interval(0, n - 1);
    Params q = c.spec.method_params;
    q.set("dmax", dmax);
    q.set("support", conv.c_str());
    const auto m = c.catalogue.methods.create("xefg", q);
    Discretization d;
    try {
      d = m->discretize(dom, uniform_line(dom, n), 1);
    } catch (const SingularError&) {
      return;  // a support too small for the linear basis: no point on the curve
    }
    BarMaterial unit;
    unit.E = unit.rho = 1;
    const int cell = n / 2 - 1;  // between nodes cell and cell + 1
    std::vector<int> nodes;
    for (int qd = 0; qd < d.quadrature.size(); ++qd)
      if (d.quadrature.cell[qd] == cell)
        for (int k = d.trial_q.offsets[qd]; k < d.trial_q.offsets[qd + 1]; ++k)
          nodes.push_back(d.trial_q.index[k]);
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    if (trimmed) {
      // Keep a node when the middle half of its support, x_I ± R/2, covers the whole cell.
      const double tol = 1e-9;
      std::erase_if(nodes, [&](int I) {
        const double xi = d.particles.x(0, I);
        return !(xi - R / 2 <= cell + tol && xi + R / 2 >= cell + 1 - tol);
      });
    }
    const int k = static_cast<int>(nodes.size());
    std::vector<int> local(d.particles.size(), -1);
    for (int i = 0; i < k; ++i) local[nodes[i]] = i;
    Eigen::MatrixXd Mc = Eigen::MatrixXd::Zero(k, k), Kc = Eigen::MatrixXd::Zero(k, k);
    for (int qd = 0; qd < d.quadrature.size(); ++qd) {
      if (d.quadrature.cell[qd] != cell) continue;
      const double w = d.quadrature.weights[qd];
      for (int i = d.trial_q.offsets[qd]; i < d.trial_q.offsets[qd + 1]; ++i)
        for (int j = d.trial_q.offsets[qd]; j < d.trial_q.offsets[qd + 1]; ++j) {
          const int li = local[d.trial_q.index[i]], lj = local[d.trial_q.index[j]];
          if (li < 0 || lj < 0) continue;
          Mc(li, lj) += w * d.trial_q.value[i] * d.trial_q.value[j];
          Kc(li, lj) += w * d.trial_q.grad[i] * d.trial_q.grad[j];
        }
    }
    const Eigen::MatrixXd Kbar = enriched_stiffness(d, unit);
    const Eigen::MatrixXd Mbar = enriched_mass(d, unit, MassScheme::row_sum);
    const double b = cpu_seconds();
    if (k >= 2) {
      const Eigen::VectorXd rs = Mc.rowwise().sum();
      const Eigen::VectorXd dg = Mc.diagonal() * (1.0 / Mc.diagonal().sum());  // M_h = Δx = 1
      row_sum = largest_eigenvalue(Kc, Eigen::MatrixXd(rs.asDiagonal()), true);
      mls1 = largest_eigenvalue(Kc, Eigen::MatrixXd(dg.asDiagonal()), true);
    }
    bar = largest_eigenvalue(Kbar, Mbar, true);
    t_assembly += b - a;
    t_solve += cpu_seconds() - b;
  }

  Params p_;
  int dim_ = 1, n_ = 10, interval_ = 4;
  double tip_ = 0.9;
  BarMaterial mat_;
};

}  // namespace

void register_enriched_bar(ProblemRegistry& r) {
  ParamSchema s{
      ParamSpec::count("dim", 1, 1, "1: the 003 bar; 2: the square patch (003 §4.3.1)"),
      capped(ParamSpec::count("particles", 10, 4, "particles along the bar (per side of the patch; at most 2000: dense eigenproblems)"), 2000),
      ParamSpec::number("interval", -1,
                        "node interval the crack sweeps (0 .. particles-2); -1: the middle one"),
      capped(ParamSpec::count("positions", 0, 0,
                              "crack positions per sweep, node to node inclusive; 0: 21 (1D), "
                              "6 (2D); at most 10000"),
             10000),
      capped(ParamSpec::count("dmax_count", 0, 0,
                              "DMAX values swept: dmax, dmax + dmax_step, ...; 0: 3 (1D), 1 (2D); "
                              "at most 100"),
             100),
      ParamSpec::positive("dmax_step", 0.5, "step between the swept DMAX values"),
      ParamSpec::positive("E", 200e9, "Young's modulus (Pa)"),
      ParamSpec::positive("rho", 7850, "density (kg/m3)"),
      ParamSpec::number("nu", 0.3, "Poisson's ratio (2D; not stated in 003)"),
      ParamSpec::choice("plane", "stress", {"stress", "strain"}, "2D: plane stress or strain"),
      ParamSpec::number("tip_y", 0.9, "2D: relative y of the crack tip inside the middle row of "
                                      "cells (003: 0.9)"),
      ParamSpec::choice("mass", "all", {"all", "consistent", "MLS1", "MLS2"},
                        "mass schemes swept: consistent (003 eq 13), MLS1 (eqs 14-16), MLS2 "
                        "(eqs 19-22), or all three"),
      ParamSpec::choice("mls1", "cell", {"cell", "point"},
                        "MLS1's eq 16 scaling per background cell (M_h its mass) or per Gauss "
                        "point (the particles in the point's domain of influence)"),
      ParamSpec::choice("tip", "branch", {"branch", "none"},
                        "2D tip case: branch-function enrichment of the supports holding the "
                        "tip, or step enrichment only"),
  };
  r.add("enriched-bar",
        "critical time step of the extended EFG with a crack swept between two nodes, consistent "
        "mass, MLS1 and MLS2 lumping, 1D bar or 2D patch, and the eq 30 fit of alpha (003)",
        s, [](const Params& p) { return std::make_unique<EnrichedBar>(p); });
}

}  // namespace mfv
