/// Galerkin / least-squares-stabilized assembly of -k u'' + c u' = f in 1D (004 I eq 6.3).
#include <vector>

#include "problems/problem.hpp"

namespace mfv {

AssembledSystem assemble_scalar_1d(const Discretization& d, const ScalarForm1D& form,
                                   const std::function<double(double)>& source) {
  const int n = d.particles.size();
  const ShapeTable& tr = d.trial_q;
  const ShapeTable& te = d.test_q;
  const bool stabilized = form.tau != 0;
  std::vector<Eigen::Triplet<double>> trip;
  Eigen::VectorXd f = Eigen::VectorXd::Zero(n);
  for (int q = 0; q < tr.points(); ++q) {
    const double w = d.quadrature.weights[q];
    const double fq = source(d.quadrature.points(0, q));
    for (int a = te.offsets[q]; a < te.offsets[q + 1]; ++a) {
      const int I = te.index[a];
      const double wI = te.value[a], dwI = te.grad[a];
      // Residual operator R(v) = -k v'' + c v' applied to the test function.
      const double RwI = stabilized ? -form.diffusion * te.hess[a] + form.advection * dwI : 0;
      f[I] += w * (wI * fq + form.tau * RwI * fq);
      for (int b = tr.offsets[q]; b < tr.offsets[q + 1]; ++b) {
        const int J = tr.index[b];
        const double dNJ = tr.grad[b];
        double k = form.diffusion * dwI * dNJ + form.advection * wI * dNJ;
        if (stabilized) k += form.tau * RwI * (-form.diffusion * tr.hess[b] + form.advection * dNJ);
        trip.emplace_back(I, J, w * k);
      }
    }
  }
  AssembledSystem s;
  s.K.resize(n, n);
  s.K.setFromTriplets(trip.begin(), trip.end());
  s.f = std::move(f);
  return s;
}

}  // namespace mfv
