/// `sph`: Galerkin with the uncorrected SPH kernel estimate (004 II Fig. 3): no consistency
/// correction, so the gradient is wrong near boundaries.
#include "methods/methods/register.hpp"

namespace mfv {

void register_sph(MethodRegistry& r, const MethodParts& parts) {
  ParamSchema s = common_galerkin_schema(10);
  s.push_back(ParamSpec::choice("kernel", "gaussian", parts.kernels.keys(), "kernel W"));
  s.push_back(ParamSpec::positive("h", 1 / (0.5 * std::sqrt(M_PI)),
                                  "dilation over spacing, a = h dx (004 II Fig. 3 uses "
                                  "sigma = dx/(0.1 sqrt(pi)) and dx/(0.5 sqrt(pi)))"));
  r.add("sph", "Galerkin with the plain SPH kernel estimate (no correction)", s,
        [parts](const Params& p) {
          GalerkinRecipe g;
          Params a;
          a.set("kernel", p.text("kernel").c_str());
          g.trial = parts.approximations.create("sph", a);
          Params q;
          q.set("n", p.number("quad"));
          g.integration = parts.integrations.create("gauss-cells", q);
          g.dilation_over_spacing = p.number("h");
          g.essential = essential_from(p);
          g.penalty = p.number("penalty");
          g.description = fmt::format("SPH {} kernel, a={:.4g} dx, bc={}", p.text("kernel"),
                                      p.number("h"), p.text("bc"));
          return make_galerkin_method(std::move(g));
        });
}

}  // namespace mfv
