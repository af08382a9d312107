#include "methods/materials/linear_elastic.hpp"

#include <fmt/format.h>

namespace mfv {

Eigen::Matrix3d LinearElastic::D() const {
  Eigen::Matrix3d d = Eigen::Matrix3d::Zero();
  if (plane_strain) {
    const double c = E / ((1 + nu) * (1 - 2 * nu));
    d << c * (1 - nu), c * nu, 0, c * nu, c * (1 - nu), 0, 0, 0, c * (1 - 2 * nu) / 2;
  } else {
    const double c = E / (1 - nu * nu);
    d << c, c * nu, 0, c * nu, c, 0, 0, 0, c * (1 - nu) / 2;
  }
  return d;
}

Eigen::MatrixXd LinearElastic::strain(const Eigen::MatrixXd& g) {
  Eigen::MatrixXd e(3, g.cols());
  e.row(0) = g.row(0);
  e.row(1) = g.row(3);
  e.row(2) = g.row(1) + g.row(2);
  return e;
}

Eigen::MatrixXd LinearElastic::stress(const Eigen::MatrixXd& g) const { return D() * strain(g); }

Eigen::VectorXd LinearElastic::energy_density(const Eigen::MatrixXd& g) const {
  const Eigen::MatrixXd e = strain(g);
  return (e.array() * (D() * e).array()).colwise().sum().transpose();
}

std::string LinearElastic::describe() const {
  return fmt::format("linear elastic, E = {:g}, nu = {:g}, plane {}", E, nu,
                     plane_strain ? "strain" : "stress");
}

}  // namespace mfv
