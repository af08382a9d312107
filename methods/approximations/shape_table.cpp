#include "methods/approximations/shape_table.hpp"

#include <stdexcept>

namespace mfv {

Eigen::VectorXd ShapeTable::interpolate(const Eigen::VectorXd& u) const {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(points());
  for (int q = 0; q < points(); ++q)
    for (int k = offsets[q]; k < offsets[q + 1]; ++k) out[q] += value[k] * u[index[k]];
  return out;
}

Eigen::VectorXd ShapeTable::interpolate_derivative(const Eigen::VectorXd& u, int d) const {
  if (order < 1) throw std::logic_error("shape table holds no first derivatives");
  Eigen::VectorXd out = Eigen::VectorXd::Zero(points());
  for (int q = 0; q < points(); ++q)
    for (int k = offsets[q]; k < offsets[q + 1]; ++k) out[q] += grad[k * dim + d] * u[index[k]];
  return out;
}

Eigen::VectorXd ShapeTable::interpolate_second_derivative(const Eigen::VectorXd& u, int d) const {
  if (order < 2) throw std::logic_error("shape table holds no second derivatives");
  Eigen::VectorXd out = Eigen::VectorXd::Zero(points());
  const int nh = nhess();
  for (int q = 0; q < points(); ++q)
    for (int k = offsets[q]; k < offsets[q + 1]; ++k)
      out[q] += hess[k * nh + d * dim + d] * u[index[k]];
  return out;
}

void ShapeTable::field(const Eigen::VectorXd& u, int nc, Eigen::MatrixXd& v,
                       Eigen::MatrixXd& g) const {
  v = Eigen::MatrixXd::Zero(nc, points());
  g = Eigen::MatrixXd::Zero(nc * dim, points());
  const bool gradients = !grad.empty();
  for (int q = 0; q < points(); ++q)
    for (int k = offsets[q]; k < offsets[q + 1]; ++k)
      for (int c = 0; c < nc; ++c) {
        const double uj = u[index[k] * nc + c];
        v(c, q) += value[k] * uj;
        if (gradients)
          for (int d = 0; d < dim; ++d) g(c * dim + d, q) += grad[k * dim + d] * uj;
      }
}

}  // namespace mfv
