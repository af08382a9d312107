#include "problems/fluid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "methods/core/errors.hpp"

namespace mfv::fluid {

double Water::sound_speed() const { return std::sqrt(gamma * B / rho0); }

double Water::pressure(double rho) const { return B * (std::pow(rho / rho0, gamma) - 1); }

double Water::hydrostatic_density(double depth) const {
  return rho0 * std::pow(1 + rho0 * g * std::max(depth, 0.0) / B, 1 / gamma);
}

Walls::Walls(std::vector<Wall> walls, double reach, double stiffness_per_mass)
    : walls_(std::move(walls)), reach_(reach), k_per_mass_(stiffness_per_mass) {
  if (!(reach > 0 && std::isfinite(reach)) || !(stiffness_per_mass > 0) ||
      !std::isfinite(stiffness_per_mass))
    throw InputError(fmt::format("fluid walls: reach = {} and stiffness per mass = {} must be "
                                 "positive and finite",
                                 reach, stiffness_per_mass));
  for (const Wall& w : walls_)
    if (!((w.b - w.a).norm() > 0) || !w.a.allFinite() || !w.b.allFinite())
      throw InputError("fluid walls: a wall segment has zero length or a non-finite end");
}

void Walls::add_forces(const Eigen::MatrixXd& x, const Eigen::VectorXd& mass,
                       Eigen::MatrixXd& f) const {
  for (Eigen::Index I = 0; I < x.cols(); ++I) {
    const Eigen::Vector2d p = x.col(I);
    for (const Wall& w : walls_) {
      const Eigen::Vector2d r = p - w.nearest(p);
      const double d = r.norm();
      // d = 0 (a particle on the wall line) has no normal: it cannot happen before a
      // particle has passed r0 of penetration, which the watch reports first.
      if (d >= reach_ || !(d > 0)) continue;
      f.col(I) += mass[I] * k_per_mass_ * (reach_ - d) * (r / d);
    }
  }
}

double Walls::energy(const Eigen::MatrixXd& x, const Eigen::VectorXd& mass) const {
  double e = 0;
  for (Eigen::Index I = 0; I < x.cols(); ++I)
    for (const Wall& w : walls_) {
      const double d = (x.col(I) - w.nearest(x.col(I))).norm();
      if (d < reach_) e += 0.5 * mass[I] * k_per_mass_ * (reach_ - d) * (reach_ - d);
    }
  return e;
}

DynamicsModel water_model(const Discretization& d, const MaterialRegistry& materials,
                          const Setup& setup) {
  const ParticleSet& ps = d.particles;
  if (ps.dim != 2) throw InputError("fluid problems are 2D");
  if (!materials.contains("tait"))
    throw InputError("fluid problems need the material 'tait' (001 eq 77), which is not "
                     "registered in this build");
  const Water& w = setup.water;
  Params mp;
  mp.set("rho0", w.rho0);
  mp.set("gamma", w.gamma);
  mp.set("B", w.B);
  DynamicsModel model;
  model.material = materials.create("tait", mp);
  model.density = w.rho0;
  const int n = ps.size();
  model.mass.resize(n);
  for (int I = 0; I < n; ++I)
    model.mass[I] = w.hydrostatic_density(setup.surface - ps.x(1, I)) * ps.volume[I];
  const double surface = setup.surface;
  model.initial_state = [w, surface](const Eigen::MatrixXd& points, int size, double* state) {
    // Slot 0 of `tait` is the reference density.
    for (Eigen::Index q = 0; q < points.cols(); ++q)
      state[size * q] = w.hydrostatic_density(surface - points(1, q));
  };
  const double dx = ps.spacing;
  if (!(dx > 0)) throw InputError("fluid problems need a lattice spacing");
  const Eigen::VectorXd mass = model.mass;
  const double g = w.g;
  model.particle_forces = [mass, g](double, const Eigen::MatrixXd&, Eigen::MatrixXd& f) {
    f.row(1).array() -= g * mass.transpose().array();
  };
  model.degenerate_fallback = true;
  if (setup.walls.empty()) return model;  // wall particles instead (walls=particles)
  auto walls = std::make_shared<const Walls>(setup.walls, 0.5 * dx,
                                             std::pow(w.sound_speed() / dx, 2));
  // Added into the same forces after gravity (WallTraction::off: the sums as before).
  model.wall_forces = [walls, mass](double, const Eigen::MatrixXd& x, Eigen::MatrixXd& f) {
    walls->add_forces(x, mass, f);
  };
  model.rigid_walls = setup.walls;
  return model;
}

double stored_energy(const Eigen::VectorXd& volume, const Eigen::VectorXd& pressure,
                     const Water& water) {
  const double c0 = water.sound_speed();
  return volume.dot(pressure.cwiseProduct(pressure)) / (2 * water.rho0 * c0 * c0);
}

Params transient_defaults(int frames) {
  Params p;
  p.set("av_alpha", 0.1);
  p.set("av_beta", 0.0);
  p.set("safety", 0.5);
  p.set("frames", frames);
  return p;
}

double potential_energy(const Eigen::MatrixXd& x, const Eigen::VectorXd& mass, double g) {
  return g * x.row(1).dot(mass);
}

Watch::Watch(const Eigen::VectorXd& mass, double g, double potential0, Limits limits)
    : mass_(mass), g_(g), potential0_(potential0), limits_(limits) {}

std::string Watch::check(const ExplicitDynamics& sim) {
  const Eigen::MatrixXd x = sim.particle_positions();
  const Eigen::MatrixXd v = sim.particle_velocity();
  if (!x.allFinite() || !v.allFinite()) return "the fields went non-finite";
  const double J = sim.min_jacobian();
  if (!(J > 0)) return fmt::format("a point inverted (det F = {:.3g})", J);
  const double speed = v.colwise().norm().maxCoeff();
  if (limits_.speed > 0 && speed > limits_.speed)
    return fmt::format("a particle moves at {:.3g} m/s, above {:.3g} m/s", speed, limits_.speed);
  released_ = std::max(released_, potential0_ - potential_energy(x, mass_, g_));
  const double kinetic = sim.kinetic_energy();
  const double k0 = sim.energy().initial;
  const double budget = limits_.energy_factor * (released_ + k0 + limits_.energy_floor);
  if (budget > 0 && kinetic > budget)
    return fmt::format("kinetic energy {:.3g} J/m above {:g} × the released potential energy "
                       "({:.3g} J/m)",
                       kinetic, limits_.energy_factor, released_ + k0);
  return "";
}

void Watch::sample(const ExplicitDynamics& sim) {
  const Eigen::MatrixXd x = sim.particle_positions();
  const Eigen::MatrixXd v = sim.particle_velocity();
  const EnergyBalance& e = sim.energy();
  Sample s{};
  s.t = sim.time();
  s.kinetic = e.kinetic;
  s.potential = potential_energy(x, mass_, g_);
  s.internal_work = e.internal_work;
  s.external_work = e.external_work;
  s.balance = e.balance();
  s.max_speed = v.cols() ? v.colwise().norm().maxCoeff() : 0.0;
  Eigen::VectorXd rho = sim.point_state("density");
  if (!water_points_.empty() && rho.size() > 0) {
    Eigen::VectorXd water(static_cast<Eigen::Index>(water_points_.size()));
    for (std::size_t k = 0; k < water_points_.size(); ++k) water[k] = rho[water_points_[k]];
    rho = std::move(water);
  }
  s.density_min = rho.size() ? rho.minCoeff() : std::numeric_limits<double>::quiet_NaN();
  s.density_max = rho.size() ? rho.maxCoeff() : std::numeric_limits<double>::quiet_NaN();
  released_ = std::max(released_, potential0_ - s.potential);
  samples_.push_back(s);
}

double Watch::speed_growth_rate(int window) const {
  const int n = static_cast<int>(samples_.size());
  const int first = std::max(0, n - window);
  double st = 0, sy = 0, stt = 0, sty = 0;
  int m = 0;
  for (int k = first; k < n; ++k) {
    const Sample& s = samples_[k];
    if (!(s.max_speed > 0) || !std::isfinite(s.max_speed)) continue;
    const double y = std::log(s.max_speed);
    st += s.t;
    sy += y;
    stt += s.t * s.t;
    sty += s.t * y;
    ++m;
  }
  if (m < 3) return std::numeric_limits<double>::quiet_NaN();
  const double den = m * stt - st * st;
  return den > 0 ? (m * sty - st * sy) / den : std::numeric_limits<double>::quiet_NaN();
}

double Watch::worst_energy_error() const {
  double worst = 0;
  for (const Sample& s : samples_) worst = std::max(worst, std::abs(s.balance));
  return released_ > 0 ? worst / released_ : std::numeric_limits<double>::quiet_NaN();
}

double Watch::max_density_deviation(double rho0) const {
  double worst = 0;
  for (const Sample& s : samples_)
    for (double rho : {s.density_min, s.density_max})
      if (std::isfinite(rho)) worst = std::max(worst, std::abs(rho / rho0 - 1));
  return worst;
}

}  // namespace mfv::fluid
