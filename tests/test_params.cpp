/// Parameter machinery of the methods layer: list parameters, deprecated aliases, declared
/// forwarding to child plugins, and the dilation from a support radius, on the methods'
/// own registries (no catalogue, no problem).
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "methods/core/errors.hpp"
#include "methods/core/params.hpp"
#include "methods/methods/register.hpp"

namespace mfv {
namespace {

/// The built-in kernels, approximations, integration schemes and methods, composed as the
/// catalogue composes them.
struct MethodsOnly {
  MethodsOnly() {
    register_all_kernels(kernels);
    register_all_approximations(approximations, kernels);
    register_all_integrations(integrations);
    register_all_methods(methods, MethodParts{kernels, approximations, integrations});
  }
  MethodsOnly(const MethodsOnly&) = delete;
  MethodsOnly& operator=(const MethodsOnly&) = delete;
  KernelRegistry kernels{"kernel"};
  ApproximationRegistry approximations{"approximation"};
  IntegrationRegistry integrations{"integration scheme"};
  MethodRegistry methods{"method"};
};

const MethodsOnly& registries() {
  static const MethodsOnly r;
  return r;
}

const ParamSchema kAngles{ParamSpec::numbers("angles", {0.0, 90.0}, "wave directions, degrees")};

Params given(const std::string& key, ParamValue v) {
  Params p;
  p.set(key, std::move(v));
  return p;
}

std::vector<double> angles_of(const Params& p) {
  return p.resolve(kAngles, "problem 'test'").numbers("angles");
}

/// The InputError message of resolving `p` against `schema` (empty when it resolves).
std::string refusal(const Params& p, const ParamSchema& schema = kAngles) {
  try {
    p.resolve(schema, "problem 'test'");
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(ListParameter, ParsesColonsCommasOneNumberAndLists) {
  EXPECT_EQ(angles_of(Params::parse("angles=0:45")), (std::vector<double>{0, 45}));
  EXPECT_EQ(angles_of(given("angles", "0, 30 ,45")), (std::vector<double>{0, 30, 45}));
  EXPECT_EQ(angles_of(given("angles", "-22.5:1e1")), (std::vector<double>{-22.5, 10}));
  EXPECT_EQ(angles_of(Params::parse("angles=45")), (std::vector<double>{45}));
  EXPECT_EQ(angles_of(given("angles", std::vector<double>{15, 75})),
            (std::vector<double>{15, 75}));
  EXPECT_EQ(angles_of(Params{}), (std::vector<double>{0, 90}));  // the default
}

TEST(ListParameter, PrintsAsColonSeparatedText) {
  // The form Params::parse reads back, so ids built from to_string keep their old spelling.
  const Params p = Params::parse("angles=0:30:45").resolve(kAngles, "problem 'test'");
  EXPECT_EQ(p.to_string(), "angles=0:30:45");
  EXPECT_EQ(angles_of(Params::parse(p.to_string())), p.numbers("angles"));
}

TEST(ListParameter, RefusesBadElementsNamingTheParameterAndTheFix) {
  struct Bad {
    std::string text;
    std::string says;
  };
  for (const Bad& b : {Bad{"0:x", "element 2"}, Bad{"0::45", "element 2 of '0::45' is empty"},
                       Bad{"45:", "element 2"}, Bad{"", "empty list"}, Bad{" ", "empty list"},
                       Bad{"nan", "not a finite number"}, Bad{"0:inf", "element 2"},
                       Bad{"0:-inf", "not a finite number"}, Bad{"0;45", "element 1"}}) {
    const std::string msg = refusal(given("angles", b.text));
    EXPECT_TRUE(contains(msg, "'angles'")) << b.text << ": " << msg;
    EXPECT_TRUE(contains(msg, b.says)) << b.text << ": " << msg;
    EXPECT_TRUE(contains(msg, "angles=0:30:45")) << b.text << ": " << msg;  // the fix
  }
  EXPECT_TRUE(contains(refusal(given("angles", std::numeric_limits<double>::quiet_NaN())),
                       "not a finite number"));
  EXPECT_TRUE(contains(refusal(given("angles", std::vector<double>{})), "empty list"));
  EXPECT_TRUE(contains(refusal(given("angles", std::vector<double>{1, HUGE_VAL})), "element 2"));
}

TEST(ListParameter, ChecksBoundsElementByElement) {
  ParamSpec spec = ParamSpec::numbers("sigmas", {0.1}, "prestress over modulus");
  spec.min = 0;
  spec.max = 1;
  const ParamSchema schema{spec};
  EXPECT_EQ(refusal(given("sigmas", "0:0.5:1"), schema), "");
  const std::string low = refusal(given("sigmas", "0.5:-0.1"), schema);
  EXPECT_TRUE(contains(low, "element 2")) << low;
  EXPECT_TRUE(contains(low, ">= 0")) << low;
  EXPECT_TRUE(contains(refusal(given("sigmas", "2"), schema), "<= 1"));
}

// Issue 26: a nonzero number outside [1e-100, 1e100] in magnitude (a denormal load) is refused
// with the fix; zero and ordinary values pass, in numbers and lists alike.
TEST(NumberParameter, RefusesMagnitudesThatLeaveTheRangeOfADouble) {
  const ParamSchema one{ParamSpec::number("F0", 1, "load")};
  EXPECT_EQ(refusal(given("F0", 0.0), one), "");
  EXPECT_EQ(refusal(given("F0", -2.5e7), one), "");
  for (double bad : {1e-300, -1e-120, 1e150}) {
    const std::string why = refusal(given("F0", bad), one);
    EXPECT_TRUE(contains(why, "parameter 'F0'")) << why;
    EXPECT_TRUE(contains(why, "rescale it")) << why;
  }
  const ParamSchema list{ParamSpec::numbers("sigmas", {0.1}, "prestress")};
  EXPECT_TRUE(contains(refusal(given("sigmas", "0.5:1e-200"), list), "element 2"));
}

TEST(ListParameter, AccessorsKeepTheKindsApart) {
  const ParamSchema schema{kAngles[0], ParamSpec::number("sigma", 0.1, "prestress")};
  const Params p = Params::parse("angles=0:45,sigma=0.2").resolve(schema, "problem 'test'");
  EXPECT_THROW(p.number("angles"), InputError);
  EXPECT_THROW(p.text("angles"), InputError);
  EXPECT_THROW(p.numbers("sigma"), InputError);
  EXPECT_THROW(p.numbers("missing"), InputError);
  // A list given where a number is declared is refused, naming what was given.
  EXPECT_TRUE(contains(refusal(given("sigma", std::vector<double>{1, 2}), schema), "a list '1:2'"));
  // Free text takes a list as its printed form, as it takes a number.
  const ParamSchema text{ParamSpec::choice("label", "x", {}, "free text")};
  EXPECT_EQ(given("label", std::vector<double>{0, 45}).resolve(text, "t").text("label"), "0:45");
  EXPECT_THROW(ParamSpec::numbers("angles", {}, "no default"), std::logic_error);
}

const ParamSchema kQuad{aliased(ParamSpec::count("quad", 0, 0, "Gauss points"), "nq"),
                        ParamSpec::positive("dmax", 2.4, "support")};

TEST(DeprecatedAlias, OldNameParsesAndResolvesToTheCanonicalName) {
  const Params p = Params::parse("nq=3").resolve(kQuad, "method 'test'");
  EXPECT_EQ(p.integer("quad"), 3);
  EXPECT_FALSE(p.has("nq"));
  EXPECT_EQ(p.to_string(), Params::parse("quad=3").resolve(kQuad, "method 'test'").to_string());
}

TEST(DeprecatedAlias, BothNamesGivenIsRefused) {
  const std::string msg = refusal(Params::parse("quad=3,nq=4"), kQuad);
  EXPECT_TRUE(contains(msg, "given twice")) << msg;
  EXPECT_TRUE(contains(msg, "'nq'")) << msg;
  EXPECT_TRUE(contains(msg, "give only quad=3")) << msg;
  // The alias is checked as the parameter is: range, and unknown names still listed.
  EXPECT_TRUE(contains(refusal(Params::parse("nq=-1"), kQuad), "'quad'"));
  const std::string unknown = refusal(Params::parse("nquad=3"), kQuad);
  EXPECT_TRUE(contains(unknown, "valid parameters: quad, dmax")) << unknown;
}

TEST(DeprecatedAlias, AnAliasThatIsAnotherParametersNameIsAProgrammingError) {
  const ParamSchema clash{aliased(ParamSpec::count("quad", 0, 0, "Gauss points"), "dmax"),
                          ParamSpec::positive("dmax", 2.4, "support")};
  EXPECT_THROW(Params{}.resolve(clash, "method 'test'"), std::logic_error);
}

TEST(DeprecatedAlias, EfgCiTakesNqAsQuad) {
  const auto& m = registries().methods;
  EXPECT_EQ(m.resolve("efg-ci", Params::parse("nq=3")).integer("quad"), 3);
  EXPECT_EQ(m.resolve("efg-ci", {}).integer("quad"), 0);  // 001 eq 66 by default
  EXPECT_THROW(m.resolve("efg-ci", Params::parse("nq=3,quad=3")), InputError);
  // The old and the new name build the same 2D rule: 3 × 3 points in each of 4 × 2 cells.
  const Domain rect = Domain::rectangle(0, 0, 2, 1);
  const ParticleSet p = rectangle_lattice(rect, 5, 3, Placement::boundary);
  const auto rule = [&](const char* params) {
    return m.create("efg-ci", Params::parse(params))->discretize(rect, p, 1).quadrature;
  };
  const IntegrationRule old_name = rule("nq=3"), new_name = rule("quad=3");
  EXPECT_EQ(new_name.size(), 4 * 2 * 9);
  EXPECT_EQ(old_name.points, new_name.points);
  EXPECT_EQ(old_name.weights, new_name.weights);
  EXPECT_NE(rule("quad=2").size(), new_name.size());
}

TEST(Forwarding, CopiesDeclaredKeysUnderTheChildsNames) {
  Params parent;
  parent.set("quad", 4.0);
  parent.set("kernel", "gaussian");
  parent.set("angles", std::vector<double>{0, 45});
  parent.set("unrelated", 1.0);
  const Params child = forward(parent, {{"quad", "n"}, {"kernel", "kernel"}, {"angles", "theta"}});
  EXPECT_EQ(child.values().size(), 3u);
  EXPECT_EQ(child.number("n"), 4.0);
  EXPECT_EQ(child.text("kernel"), "gaussian");
  EXPECT_EQ(child.numbers("theta"), (std::vector<double>{0, 45}));
  EXPECT_FALSE(child.has("unrelated"));
  EXPECT_TRUE(forward(parent, {}).values().empty());
  EXPECT_THROW(forward(parent, {{"nq", "nq"}}), std::logic_error);
}

TEST(Forwarding, MethodsHandTheirQuadratureToTheIntegrationScheme) {
  // A Galerkin method's `quad` reaches gauss-cells' `n`: the method's rule is the scheme's.
  const auto& r = registries();
  const Domain line = Domain::interval(0, 1);
  const ParticleSet p = uniform_line(line, 11);
  for (const char* method : {"efg", "fem", "rkpm", "sph-galerkin", "wavelet", "xefg"}) {
    const IntegrationRule own =
        r.methods.create(method, Params::parse("quad=3"))->discretize(line, p, 1).quadrature;
    const IntegrationRule cells =
        r.integrations.create("gauss-cells", Params::parse("n=3"))->rule(line, p);
    EXPECT_EQ(own.size(), 10 * 3) << method;
    EXPECT_EQ(own.points, cells.points) << method;
    EXPECT_EQ(own.weights, cells.weights) << method;
  }
}

TEST(Dilation, SupportRadiusOverTheKernelsSupport) {
  const auto& r = registries();
  for (const std::string& name : r.kernels.keys()) {
    const auto W = r.kernels.create(name);
    const double a = dilation_for_radius(*W, 2.4);
    EXPECT_NEAR(a * W->support(), 2.4, 1e-14) << name;  // W vanishes from r = 2.4 on
  }
  // efg's particles carry a = dmax·Δx / support: the cubic window's support radius is dmax·Δx.
  const Domain line = Domain::interval(0, 1);
  const ParticleSet p = uniform_line(line, 11);
  const auto W = r.kernels.create("cubic-window");
  const Discretization d =
      r.methods.create("efg", Params::parse("dmax=2.5"))->discretize(line, p, 1);
  EXPECT_DOUBLE_EQ(d.particles.dilation[0], dilation_for_radius(*W, 2.5) * p.spacing);
  EXPECT_DOUBLE_EQ(d.particles.dilation[0] * W->support(), 2.5 * p.spacing);
}

}  // namespace
}  // namespace mfv
