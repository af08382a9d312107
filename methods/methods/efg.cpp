/// `efg`: element-free Galerkin, MLS with linear basis (001 §3.5), background-cell Gauss or
/// nodal integration; support radius dmax·Δx.
#include "methods/methods/register.hpp"

#include "methods/kernels/kernel_choice.hpp"

namespace mfv {

void register_efg(MethodRegistry& r, const MethodParts& parts) {
  ParamSchema s = common_galerkin_schema(10);
  for (auto& spec : kernel_choice(parts.kernels, "cubic-window", "weight function")) s.push_back(spec);
  s.push_back(ParamSpec::positive("dmax", 2.0,
                                  "support radius over particle spacing (a = dmax dx / support of "
                                  "W); 2.0 is the EFG of the 004 comparisons (laplace-tanh, "
                                  "advection-diffusion) whose baselines were measured with it, "
                                  "where efg-ni/efg-ci keep 001's particle-method 2.4"));
  s.push_back(ParamSpec::count("basis", 1, 0, "MLS basis order (0, 1, 2)"));
  s.push_back(ParamSpec::choice("integration", "gauss-cells", {"gauss-cells", "nodal", "stress-points"},
                                "where the weak form is integrated"));
  r.add("efg", "element-free Galerkin: MLS shape functions (001 eqs 37-43)", s,
        [parts](const Params& p) {
          GalerkinRecipe g;
          g.trial = parts.approximations.create("mls", with_kernel(forward(p, {{"basis", "basis"}}), p));
          // Only Gauss cells have points per cell; nodal and stress-point rules take none.
          const std::string& integration = p.text("integration");
          g.integration = parts.integrations.create(
              integration, integration == "gauss-cells" ? forward(p, {{"quad", "n"}}) : Params{});
          g.dilation_over_spacing =
              dilation_for_radius(*make_kernel(parts.kernels, p), p.number("dmax"));
          g.essential = essential_from(p);
          g.penalty = p.number("penalty");
          g.description = fmt::format("MLS basis {} with {} weight, dmax={}, {}, bc={}",
                                      p.integer("basis"), p.text("kernel"), p.number("dmax"),
                                      p.text("integration"), p.text("bc"));
          const int b = p.integer("basis");
          g.formal = integration == "gauss-cells"
                         ? FormalOrder{b + 1.0, static_cast<double>(b),
                                       fmt::format("MLS basis of order {}, Gauss cells "
                                                   "(Belytschko, Lu & Gu 1994)", b)}
                         : FormalOrder{NAN, NAN, fmt::format("{} sums miss the divergence "
                                                             "identity near the boundary (Chen "
                                                             "et al. 2001)", integration)};
          return make_galerkin_method(std::move(g));
        });
}

}  // namespace mfv

namespace mfv {

namespace {

void register_efg_variant(MethodRegistry& r, const MethodParts& parts, const std::string& name,
                          const std::string& integration) {
  ParamSchema s = particle_method_schema(parts.kernels, true);
  // `quad` as in efg and the other Galerkin methods; `nq`, this method's first name for it,
  // still parses. The default differs from efg's 10: 001 §5.3 sizes 2D cells by eq 66.
  if (integration == "gauss-cells")
    s.push_back(aliased(capped(ParamSpec::count("quad", 0, 0,
                                                "Gauss points per 2D cell and direction; 0: n_Q "
                                                "= ceil(sqrt(m)) + 2 with m particles in the "
                                                "cell (001 eq 66); 1D cells take 10 (at most "
                                                "64; deprecated name: nq)"),
                               64),
                        "nq"));
  if (integration == "gauss-cells")
    s.push_back(capped(ParamSpec::count("cells", 0, 0,
                                        "2D: a uniform background grid of this many cells along "
                                        "x, rows for nearly square cells, each with eq 66's "
                                        "points for the particles it holds (0: the lattice "
                                        "cells; at most 10^6)"),
                       1000000));
  r.add(name,
        fmt::format("element-free Galerkin, MLS linear basis (001 eqs 37-43), {} (001 Table 1 "
                    "row EFG {})",
                    integration == "nodal" ? "nodal integration" : "Gauss cells",
                    integration == "nodal" ? "ni" : "ci"),
        s, [parts, integration](const Params& p) {
          GalerkinRecipe g;
          g.trial = parts.approximations.create("mls", with_kernel({}, p));
          g.integration = parts.integrations.create(
              integration, integration == "gauss-cells"
                               ? forward(p, {{"quad", "nq"}, {"cells", "cells"}})
                               : Params{});
          set_particle_dilation(p, parts.kernels, g.dilation_over_spacing, g.dilation);
          g.essential = essential_from(p);
          g.penalty = p.number("penalty");
          g.description = fmt::format(
              "EFG: MLS linear, {} kernel, support {}, {}, bc={}", p.text("kernel"),
              support_text(p),
              integration == "nodal" ? "nodal integration"
              : (p.integer("quad") > 0 ? fmt::format("{0}x{0} Gauss per cell", p.integer("quad"))
                                       : std::string("Gauss cells with n_Q = sqrt(m)+2")) +
                    (p.integer("cells") > 0
                         ? fmt::format(" on a grid of {} cells along x", p.integer("cells"))
                         : std::string()),
              p.text("bc"));
          g.formal = formal_order_of(
              p, true, true, integration == "gauss-cells",
              integration == "gauss-cells"
                  ? "MLS linear basis, Gauss cells (Belytschko, Lu & Gu 1994)"
                  : "nodal sums miss the divergence identity near the boundary (Chen et al. "
                    "2001); vci=linear or quadratic declares 2 / 1");
          return vci_if_asked(p, make_galerkin_method(std::move(g)));
        });
}

}  // namespace

void register_efg_ni(MethodRegistry& r, const MethodParts& parts) {
  register_efg_variant(r, parts, "efg-ni", "nodal");
}

void register_efg_ci(MethodRegistry& r, const MethodParts& parts) {
  register_efg_variant(r, parts, "efg-ci", "gauss-cells");
}

}  // namespace mfv
