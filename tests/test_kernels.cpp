/// Kernel conformance, run over every registered kernel: normalization against the declared
/// integral, derivatives against finite differences, positivity and monotone decay.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "methods/integration/integration.hpp"
#include "methods/kernels/kernel_admission.hpp"
#include "methods/kernels/kernel_choice.hpp"
#include "test_support.hpp"

namespace mfv {
namespace {

class KernelConformance : public ::testing::TestWithParam<std::string> {
 protected:
  std::unique_ptr<Kernel> kernel() const { return test_catalogue().kernels.create(GetParam()); }
};

/// ∫ over R^dim of W(|x|) by Gauss rules on many cells of [0, support].
double radial_integral(const Kernel& k, int dim) {
  const double rs = k.support();
  const int cells = 400;
  std::vector<double> x, w;
  double sum = 0;
  for (int c = 0; c < cells; ++c) {
    gauss_legendre(8, rs * c / cells, rs * (c + 1) / cells, x, w);
    for (std::size_t i = 0; i < x.size(); ++i) {
      const double jac = dim == 1 ? 2.0 : dim == 2 ? 2 * M_PI * x[i] : 4 * M_PI * x[i] * x[i];
      sum += w[i] * jac * k.value(x[i]);
    }
  }
  return sum;
}

TEST_P(KernelConformance, IntegralMatchesDeclaredNormalization) {
  const auto k = kernel();
  for (int dim = 1; dim <= 3; ++dim)
    EXPECT_NEAR(radial_integral(*k, dim), k->integral(dim), 1e-6 * k->integral(dim))
        << "dimension " << dim;
}

TEST_P(KernelConformance, DerivativesMatchFiniteDifferences) {
  const auto k = kernel();
  const double rs = k->support();
  for (double f : {0.07, 0.23, 0.31, 0.47, 0.61, 0.77, 0.89}) {
    const double s = f * rs, e = 1e-6 * rs;
    double w, dw, d2w, wp, wm, dwp, dwm, t;
    k->evaluate({&s, 1}, {&w, 1}, {&dw, 1}, {&d2w, 1});
    const double sp = s + e, sm = s - e;
    k->evaluate({&sp, 1}, {&wp, 1}, {&dwp, 1}, {&t, 1});
    k->evaluate({&sm, 1}, {&wm, 1}, {&dwm, 1}, {&t, 1});
    const double scale = std::abs(k->value(0)) / rs;
    EXPECT_NEAR(dw, (wp - wm) / (2 * e), 1e-6 * scale + 1e-6 * std::abs(dw)) << "s = " << s;
    EXPECT_NEAR(d2w, (dwp - dwm) / (2 * e), 1e-5 * scale / rs + 1e-5 * std::abs(d2w))
        << "s = " << s;
  }
}

TEST_P(KernelConformance, PositiveAndDecreasingInsideSupport) {
  const auto k = kernel();
  double prev = k->value(0);
  EXPECT_GT(prev, 0);
  for (int i = 1; i < 200; ++i) {
    const double w = k->value(k->support() * i / 200.0);
    EXPECT_GE(w, 0);
    EXPECT_LE(w, prev + 1e-15);
    prev = w;
  }
  EXPECT_EQ(k->value(k->support() * 1.01), 0.0);
}

TEST_P(KernelConformance, ADimensionParameterNormalizesToOneInThatDimension) {
  // A kernel that declares `dim` promises C normalizing it in that dimension (001 eq 15's
  // cubic-spline constants; Wendland's and the quintic spline's in their headers).
  const Params defaults = test_catalogue().kernels.resolve(GetParam(), {});
  if (!defaults.has("dim")) GTEST_SKIP() << GetParam() << " declares no dimension";
  for (int dim = 1; dim <= 3; ++dim) {
    Params p;
    p.set("dim", dim);
    const auto k = test_catalogue().kernels.create(GetParam(), p);
    EXPECT_NEAR(k->integral(dim), 1.0, 1e-13) << "dimension " << dim;
    EXPECT_NEAR(radial_integral(*k, dim), 1.0, 1e-6) << "dimension " << dim;
  }
}

TEST_P(KernelConformance, AdmittedByEveryMethod) {
  // The check make_kernel applies (methods/kernels/kernel_admission.hpp) passes every shipped
  // kernel at its defaults.
  EXPECT_EQ(kernel_property_failure(*kernel()), "");
}

INSTANTIATE_TEST_SUITE_P(AllKernels, KernelConformance,
                         ::testing::ValuesIn(test_catalogue().kernels.keys()));

TEST(Kernels, NormalizedCubicSplineConstants) {
  // 001 eq 15: C = 2/3, 10/(7π), 1/π make the spline integrate to one in 1, 2, 3 D.
  for (int dim = 1; dim <= 3; ++dim) {
    Params p;
    p.set("dim", dim);
    const auto k = test_catalogue().kernels.create("cubic-spline", p);
    EXPECT_NEAR(k->integral(dim), 1.0, 1e-14);
    EXPECT_NEAR(radial_integral(*k, dim), 1.0, 1e-6);
  }
}

TEST(Kernels, WendlandAndQuinticValuesAtTheCentre) {
  // W(0) = C: Dehnen & Aly's 2D constants 7/π, 9/π, 78/(7π) for support H = 2 are 7/(4π),
  // 9/(4π), 78/(28π); the quintic spline's 2D C is 7/(478π), times the bracket's 3⁵ − 6·2⁵ + 15.
  Params two;
  two.set("dim", 2);
  const auto& k = test_catalogue().kernels;
  EXPECT_NEAR(k.create("wendland-c2", two)->value(0), 7 / (4 * M_PI), 1e-15);
  EXPECT_NEAR(k.create("wendland-c4", two)->value(0), 9 / (4 * M_PI), 1e-15);
  EXPECT_NEAR(k.create("wendland-c6", two)->value(0), 78 / (28 * M_PI), 1e-15);
  EXPECT_NEAR(k.create("quintic-spline", two)->value(0), 7 / (478 * M_PI) * 66, 1e-15);
  Params four;
  four.set("dim", 4);
  EXPECT_THROW(k.create("wendland-c2", four), InputError);
}

/// A cubic spline with a negative lobe past s = 1.5, or with a derivative off by a factor 2:
/// kernels a plugin could register, which every method must refuse (issue 46).
class FaultyKernel final : public KernelFormula<FaultyKernel> {
 public:
  explicit FaultyKernel(bool negative) : negative_(negative) {}
  void formula(double s, double& w, double& dw, double& d2w) const {
    const double q = 2 - s;
    w = q * q * q / 6 - (negative_ && s > 1.5 ? 0.05 : 0);
    dw = -q * q / 2 * (negative_ ? 1 : 2);
    d2w = q;
  }
  double support() const { return 2; }
  double integral(int) const { return 1; }

 private:
  bool negative_;
};

TEST(KernelAdmission, MethodsRefuseAKernelThatFailsConformanceNamingTheCheck) {
  KernelRegistry r("kernel");
  register_all_kernels(r);
  r.add("negative-lobe", "W < 0 on part of its support", {},
        [](const Params&) { return std::make_unique<FaultyKernel>(true); });
  r.add("wrong-derivative", "dW/ds twice the derivative of W", {},
        [](const Params&) { return std::make_unique<FaultyKernel>(false); });
  auto refusal = [&](const std::string& name) {
    Params p;
    p.set("kernel", name);
    try {
      make_kernel(r, p);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refusal("negative-lobe").find("not positive"), std::string::npos)
      << refusal("negative-lobe");
  EXPECT_NE(refusal("negative-lobe").find("'negative-lobe'"), std::string::npos);
  EXPECT_NE(refusal("wrong-derivative").find("derivative is not W's"), std::string::npos)
      << refusal("wrong-derivative");
  EXPECT_EQ(refusal("cubic-spline"), "accepted");
  // Through a method: efg takes its kernel by make_kernel, so the refusal reaches the user.
  Extensions faulty;
  faulty.kernels.push_back([](KernelRegistry& k) {
    k.add("negative-lobe", "W < 0 on part of its support", {},
          [](const Params&) { return std::make_unique<FaultyKernel>(true); });
  });
  const Catalogue plugins(faulty);
  Params mp;
  mp.set("kernel", "negative-lobe");
  EXPECT_THROW(plugins.methods.create("efg", mp), InputError);
}

}  // namespace
}  // namespace mfv
