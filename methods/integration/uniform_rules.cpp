/// Uniform tensor Gauss rules on boxes, independent of any method (the common error norms).
#include "methods/integration/integration.hpp"

namespace mfv {

IntegrationRule uniform_gauss_rule_2d(const Domain& box, int cx, int cy, int n) {
  IntegrationRule r;
  r.kind = "gauss-cells";
  r.cells = cx * cy;
  r.points.resize(2, static_cast<Eigen::Index>(cx) * cy * n * n);
  r.weights.resize(r.points.cols());
  std::vector<double> gx, wx, gy, wy;
  const double hx = (box.upper[0] - box.lower[0]) / cx, hy = (box.upper[1] - box.lower[1]) / cy;
  Eigen::Index q = 0;
  for (int j = 0; j < cy; ++j) {
    gauss_legendre(n, box.lower[1] + j * hy, box.lower[1] + (j + 1) * hy, gy, wy);
    for (int i = 0; i < cx; ++i) {
      gauss_legendre(n, box.lower[0] + i * hx, box.lower[0] + (i + 1) * hx, gx, wx);
      for (int b = 0; b < n; ++b)
        for (int a = 0; a < n; ++a, ++q) {
          r.points.col(q) << gx[a], gy[b];
          r.weights[q] = wx[a] * wy[b];
          r.cell.push_back(i + cx * j);
        }
    }
  }
  return r;
}

}  // namespace mfv
