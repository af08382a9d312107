#include "problems/funnel_measures.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <fmt/format.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>
#include <gsl/gsl_odeiv2.h>

#include "methods/core/errors.hpp"

namespace mfv::funnel {

double Geometry::width(double y) const { return outlet + 2 * std::clamp(y, 0.0, cone); }

double Geometry::area(double h) const {
  if (!(h > 0)) return 0;
  if (h <= cone) return outlet * h + h * h;
  return outlet * cone + cone * cone + width(cone) * (h - cone);
}

double Geometry::level_of_area(double a) const {
  if (!(a > 0)) return 0;
  const double a_cone = area(cone);
  // In the cone A = D h + h², the positive root; above it A grows linearly.
  if (a <= a_cone) return 0.5 * (std::sqrt(outlet * outlet + 4 * a) - outlet);
  return cone + (a - a_cone) / width(cone);
}

double Geometry::inertance(double h) const {
  if (!(h > 0)) return 0;
  const double in_cone = std::min(h, cone);
  // ∫ dy / (D + 2y) = ½ ln((D + 2y) / D) over the cone, then (h − cone) / w above it.
  double i = 0.5 * std::log((outlet + 2 * in_cone) / outlet);
  if (h > cone) i += (h - cone) / width(cone);
  return i;
}

namespace {

/// sin(2βε/π) cot ε, the integrand after α = π/2 − ε; its limit at ε = 0 is 2β/π.
double cc_integrand(double eps, void* params) {
  const double beta = *static_cast<const double*>(params);
  if (!(eps > 1e-12)) return 2 * beta / M_PI;
  return std::sin(2 * beta * eps / M_PI) * std::cos(eps) / std::sin(eps);
}

/// GSL's default handler aborts; errors here become exceptions at the call.
struct GslQuiet {
  gsl_error_handler_t* old = gsl_set_error_handler_off();
  ~GslQuiet() { gsl_set_error_handler(old); }
};

struct OdeParams {
  const Torricelli* t;
};

int torricelli_rhs(double, const double y[], double dydt[], void* params) {
  const Torricelli& p = *static_cast<const OdeParams*>(params)->t;
  const double h = std::max(y[0], 0.0);
  const double D = p.geometry.outlet, w = p.geometry.width(h);
  if (!p.startup) {
    dydt[0] = -p.cc * D * std::sqrt(2 * p.g * h) / w;
    return GSL_SUCCESS;
  }
  const double v = y[1];
  dydt[0] = -p.cc * D * v / w;
  const double inertance = p.geometry.inertance(h);
  dydt[1] = inertance > 0 ? (p.g * h - 0.5 * v * v) / (p.cc * D * inertance) : 0.0;
  return GSL_SUCCESS;
}

}  // namespace

double contraction_coefficient(double beta) {
  if (!(beta > 0 && beta <= M_PI))
    throw InputError(fmt::format("contraction coefficient: the wall angle β = {} rad must be in "
                                 "(0, π] (π/2: a flat wall, π: Borda's mouthpiece)",
                                 beta));
  GslQuiet quiet;
  gsl_integration_workspace* w = gsl_integration_workspace_alloc(200);
  gsl_function f{&cc_integrand, &beta};
  double result = 0, error = 0;
  const int status = gsl_integration_qags(&f, 0, M_PI / 2, 0, 1e-12, 200, w, &result, &error);
  gsl_integration_workspace_free(w);
  if (status != GSL_SUCCESS)
    throw std::runtime_error(fmt::format("contraction coefficient: GSL QAGS failed at β = {} "
                                         "({})",
                                         beta, gsl_strerror(status)));
  return 1 / (1 + 2 / M_PI * result);
}

std::vector<double> Torricelli::levels(const std::vector<double>& times) const {
  if (!(cc > 0 && cc <= 1) || !(h0 > 0) || !(g > 0) || !std::isfinite(h0) || !std::isfinite(g))
    throw InputError(fmt::format("Torricelli: C_c = {} must be in (0, 1], h0 = {} and g = {} "
                                 "positive and finite",
                                 cc, h0, g));
  GslQuiet quiet;
  OdeParams params{this};
  const std::size_t dim = startup ? 2 : 1;
  gsl_odeiv2_system sys{&torricelli_rhs, nullptr, dim, &params};
  gsl_odeiv2_driver* driver =
      gsl_odeiv2_driver_alloc_y_new(&sys, gsl_odeiv2_step_rk8pd, 1e-6, 1e-12, 1e-10);
  double y[2] = {h0, 0.0};
  double t = 0;
  std::vector<double> out;
  out.reserve(times.size());
  bool emptied = false;
  for (double ti : times) {
    if (!(ti >= t)) {
      gsl_odeiv2_driver_free(driver);
      throw InputError("Torricelli: the times must be ascending and non-negative");
    }
    // The level law is not Lipschitz at h = 0 (√h): once the level is within round-off of
    // the outlet the funnel has emptied and stays empty.
    if (!emptied && ti > t) {
      const int status = gsl_odeiv2_driver_apply(driver, &t, ti, y);
      if (status != GSL_SUCCESS || !(y[0] > 1e-9 * h0)) emptied = true;
    }
    out.push_back(emptied ? 0.0 : y[0]);
  }
  gsl_odeiv2_driver_free(driver);
  return out;
}

std::vector<double> Torricelli::drained(const std::vector<double>& times) const {
  const double a0 = geometry.area(h0);
  std::vector<double> f = levels(times);
  for (double& h : f) h = 1 - geometry.area(h) / a0;
  return f;
}

double Torricelli::time_to_drain(double fraction, double horizon) const {
  if (!(fraction > 0 && fraction < 1) || !(horizon > 0) || !std::isfinite(horizon))
    throw InputError(fmt::format("Torricelli: fraction = {} must be in (0, 1) and horizon = {} "
                                 "positive and finite",
                                 fraction, horizon));
  auto drained_at = [&](double t) { return drained({t}).front(); };
  if (drained_at(horizon) < fraction) return std::numeric_limits<double>::quiet_NaN();
  double lo = 0, hi = horizon;
  while (hi - lo > 1e-9) {
    const double mid = 0.5 * (lo + hi);
    (drained_at(mid) < fraction ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double drained_fraction(const Eigen::MatrixXd& x, const Eigen::VectorXd& mass) {
  double below = 0, total = 0;
  for (Eigen::Index I = 0; I < x.cols(); ++I) {
    total += mass[I];
    if (x(1, I) < 0) below += mass[I];
  }
  return total > 0 ? below / total : 0.0;
}

double level_from_drained(const Geometry& g, double h0, double drained) {
  return g.level_of_area((1 - std::clamp(drained, 0.0, 1.0)) * g.area(h0));
}

double first_crossing(const std::vector<double>& t, const std::vector<double>& f, double target) {
  const std::size_t n = std::min(t.size(), f.size());
  for (std::size_t k = 0; k < n; ++k) {
    if (!(f[k] >= target)) continue;
    if (k == 0 || !(f[k] > f[k - 1])) return t[k];
    return t[k - 1] + (target - f[k - 1]) / (f[k] - f[k - 1]) * (t[k] - t[k - 1]);
  }
  return std::numeric_limits<double>::quiet_NaN();
}

std::vector<std::array<Eigen::Vector2d, 2>> wall_segments(const Geometry& g) {
  const double a = 0.5 * g.outlet, b = a + g.cone;
  return {{Eigen::Vector2d(-a, 0), Eigen::Vector2d(-b, g.cone)},
          {Eigen::Vector2d(-b, g.cone), Eigen::Vector2d(-b, g.top)},
          {Eigen::Vector2d(a, 0), Eigen::Vector2d(b, g.cone)},
          {Eigen::Vector2d(b, g.cone), Eigen::Vector2d(b, g.top)}};
}

namespace {
double distance_to_segment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                           const Eigen::Vector2d& b) {
  const Eigen::Vector2d s = b - a;
  const double t = std::clamp((p - a).dot(s) / s.squaredNorm(), 0.0, 1.0);
  return (p - a - t * s).norm();
}
}  // namespace

bool inside(const Geometry& g, const Eigen::Vector2d& x) {
  return x.y() > 0 && x.y() < g.top && std::abs(x.x()) < 0.5 * g.width(x.y());
}

ParticleSet funnel_lattice(const Geometry& g, double h0, double dx, long max_particles,
                           int wall_layers) {
  if (wall_layers < 0 || wall_layers > 10)
    throw InputError(fmt::format("funnel lattice: wall_layers = {} must be in [0, 10] (0: no "
                                 "wall particles; 3 is the hydrostatic column's)",
                                 wall_layers));
  if (!(dx > 0) || !std::isfinite(dx) || !(g.outlet / dx >= 2))
    throw InputError(fmt::format("funnel lattice: spacing {} m must be positive, finite and at "
                                 "most half the outlet width {} m",
                                 dx, g.outlet));
  if (!(h0 >= dx) || !(h0 <= g.top - dx) || !std::isfinite(h0))
    throw InputError(fmt::format("funnel lattice: water level {} m must be between one spacing "
                                 "({} m) and one spacing below the walls' top ({} m)",
                                 h0, dx, g.top));
  const double estimate = g.area(h0) / (dx * dx);
  if (!(estimate <= static_cast<double>(max_particles)))
    throw InputError(fmt::format("funnel lattice: spacing {} m gives about {:.3g} particles, "
                                 "more than {}; use a coarser spacing",
                                 dx, estimate, max_particles));
  const auto walls = wall_segments(g);
  const double half_width = 0.5 * g.width(g.cone);
  const int columns = static_cast<int>(std::floor(half_width / dx));  // per side
  const int rows = static_cast<int>(std::ceil(h0 / dx - 0.5 - 1e-9));
  std::map<std::pair<int, int>, int> index;  // (i, j) → particle; i from −columns
  std::vector<Eigen::Vector2d> kept;
  const double reach = 0.5 * dx * (1 - 1e-9);
  for (int j = 0; j < rows; ++j)
    for (int i = -columns; i < columns; ++i) {
      const Eigen::Vector2d p((i + 0.5) * dx, (j + 0.5) * dx);
      if (std::abs(p.x()) > half_width) continue;
      bool clear = true;
      for (const auto& w : walls) clear = clear && distance_to_segment(p, w[0], w[1]) >= reach;
      // Inside: between the walls (a particle outside the funnel may be far from them).
      if (!clear || std::abs(p.x()) >= 0.5 * g.width(p.y())) continue;
      index[{i, j}] = static_cast<int>(kept.size());
      kept.push_back(p);
    }
  if (wall_layers > 0) {
    // The wall band: lattice sites outside the funnel within wall_layers spacings of a wall.
    const int wall_rows = static_cast<int>(std::ceil(g.top / dx - 0.5 - 1e-9));
    const int reach_columns = columns + wall_layers + 1;
    const double band = wall_layers * dx;
    for (int j = 0; j < wall_rows; ++j)
      for (int i = -reach_columns; i < reach_columns; ++i) {
        const Eigen::Vector2d p((i + 0.5) * dx, (j + 0.5) * dx);
        if (std::abs(p.x()) < 0.5 * g.width(p.y())) continue;  // inside the funnel
        double d = std::numeric_limits<double>::infinity();
        for (const auto& w : walls) d = std::min(d, distance_to_segment(p, w[0], w[1]));
        if (d < reach || d >= band) continue;
        index[{i, j}] = static_cast<int>(kept.size());
        kept.push_back(p);
      }
  }
  const int n = static_cast<int>(kept.size());
  ParticleSet ps;
  ps.dim = 2;
  ps.x.resize(2, n);
  for (int I = 0; I < n; ++I) ps.x.col(I) = kept[I];
  ps.volume = Eigen::VectorXd::Constant(n, dx * dx);
  ps.dilation = Eigen::VectorXd::Constant(n, dx);
  ps.spacing = dx;
  ps.placement = Placement::inset;
  ps.sides.assign(n, 0u);
  auto sp = std::make_shared<StressPoints>();
  std::vector<Eigen::Vector2d> centres;
  sp->particle_volume = ps.volume;
  for (const auto& [ij, I0] : index) {
    const auto [i, j] = ij;
    const auto a = index.find({i + 1, j}), b = index.find({i + 1, j + 1}),
               c = index.find({i, j + 1});
    if (a == index.end() || b == index.end() || c == index.end()) continue;
    const std::array<int, 4> q{I0, a->second, b->second, c->second};
    ps.quads.push_back(q);
    centres.emplace_back((i + 1.0) * dx, (j + 1.0) * dx);
    for (int J : q) sp->particle_volume[J] -= 0.125 * dx * dx;
  }
  sp->x.resize(2, static_cast<Eigen::Index>(centres.size()));
  for (std::size_t k = 0; k < centres.size(); ++k) sp->x.col(static_cast<Eigen::Index>(k)) = centres[k];
  sp->volume = Eigen::VectorXd::Constant(sp->x.cols(), 0.5 * dx * dx);
  ps.stress_points = std::move(sp);
  return ps;
}

}  // namespace mfv::funnel
