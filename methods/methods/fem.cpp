/// `fem`: linear finite elements (two-node, 1D), the baseline of 004 Tables 1 and 6.1.
#include "methods/methods/register.hpp"

namespace mfv {

void register_fem(MethodRegistry& r, const MethodParts& parts) {
  r.add("fem", "linear finite elements on the particles as nodes, Gauss quadrature per element",
        common_galerkin_schema(10), [parts](const Params& p) {
          GalerkinRecipe g;
          g.trial = parts.approximations.create("linear-fe");
          g.integration = parts.integrations.create("gauss-cells", forward(p, {{"quad", "n"}}));
          g.essential = essential_from(p);
          g.penalty = p.number("penalty");
          g.description = fmt::format("linear elements, {}-point Gauss per element, bc={}",
                                      p.integer("quad"), p.text("bc"));
          g.formal = {2, 1, "linear elements: Cea's lemma and the Aubin-Nitsche duality"};
          return make_galerkin_method(std::move(g));
        });
}

}  // namespace mfv
