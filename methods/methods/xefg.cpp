/// `xefg`: extended element-free Galerkin (003 §3): EFG (MLS, linear basis, cubic-spline
/// weight, support dmax·Δx) whose trial and test functions carry the crack enrichment of 003
/// eq 8 (step H for supports the crack cuts, branch functions for supports holding the tip),
/// integrated on Gauss cells split at the crack. Without a crack (the default) it is EFG.
#include <fmt/format.h>

#include "methods/approximations/enriched.hpp"
#include "methods/core/errors.hpp"
#include "methods/methods/register.hpp"
#include "methods/kernels/kernel_choice.hpp"

namespace mfv {

double xefg_support_factor(const std::string& convention) {
  if (convention == "diameter") return 0.5;
  if (convention == "2h") return 2.0;
  return 1.0;
}

namespace {

/// The Galerkin method of the recipe, plus the count of enrichment unknowns.
class XefgMethod final : public Method {
 public:
  XefgMethod(std::unique_ptr<Method> inner, std::shared_ptr<const EnrichedApproximation> trial)
      : inner_(std::move(inner)), trial_(std::move(trial)) {}
  FormalOrder formal_order() const override { return inner_->formal_order(); }
  Discretization discretize(const Domain& domain, ParticleSet particles,
                            int order) const override {
    if (trial_ && trial_->crack().has_tip() && domain.dim != 2)
      throw InputError(fmt::format("xefg: crack=edge (a crack with a tip) needs a 2D domain, got "
                                   "{}D; use crack=through",
                                   domain.dim));
    Discretization d = inner_->discretize(domain, std::move(particles), order);
    if (trial_) d.enriched_unknowns = static_cast<int>(trial_->enrichments(d.particles).size());
    return d;
  }
  void retabulate(Discretization& d, int order) const override {
    inner_->retabulate(d, order);
    if (trial_) d.enriched_unknowns = static_cast<int>(trial_->enrichments(d.particles).size());
  }

 private:
  std::unique_ptr<Method> inner_;
  std::shared_ptr<const EnrichedApproximation> trial_;
};

}  // namespace

void register_xefg(MethodRegistry& r, const MethodParts& parts) {
  ParamSchema s = common_galerkin_schema(4);
  for (auto& spec : kernel_choice(parts.kernels, "cubic-spline", "weight function")) s.push_back(spec);
  s.push_back(ParamSpec::positive("dmax", 2.3, "support size over particle spacing (003 DMAX)"));
  s.push_back(ParamSpec::count("basis", 1, 0, "MLS basis order (0, 1, 2)"));
  s.push_back(ParamSpec::choice("support", "radius", {"radius", "diameter", "2h"},
                                "what dmax·Δx is: the support radius, its diameter, or h of a "
                                "spline in r/2h (radius 2·dmax·Δx)"));
  s.push_back(ParamSpec::choice("crack", "none", {"none", "through", "edge"},
                                "none: plain EFG; through: a crack point (1D) or a vertical line "
                                "x = crack_x across the domain (2D); edge: a vertical crack from "
                                "the bottom up to the tip y = crack_tip (2D)"));
  s.push_back(ParamSpec::number("crack_x", 0.0, "crack position (1D) or abscissa (2D)"));
  s.push_back(ParamSpec::number("crack_tip", 0.0, "y of the crack tip (crack=edge)"));
  s.push_back(ParamSpec::choice("tip", "branch", {"branch", "none"},
                                "crack=edge: branch-function enrichment of the supports holding "
                                "the tip (003 eq 8, third term), or none"));
  r.add("xefg",
        "extended EFG: MLS with step (and tip) crack enrichment, crack-split Gauss cells "
        "(003 eqs 5-11)",
        s, [parts](const Params& p) -> std::unique_ptr<Method> {
          if (p.integer("basis") > 2)
            throw InputError("parameter 'basis' of method 'xefg' must be 0, 1 or 2");
          GalerkinRecipe g;
          std::shared_ptr<const Approximation> mls = parts.approximations.create(
              "mls", with_kernel(forward(p, {{"basis", "basis"}}), p));
          const auto W = make_kernel(parts.kernels, p);
          const double support = W->support();
          std::shared_ptr<const IntegrationScheme> cells =
              parts.integrations.create("gauss-cells", forward(p, {{"quad", "n"}}));
          g.dilation_over_spacing =
              dilation_for_radius(*W, xefg_support_factor(p.text("support")) * p.number("dmax"));
          g.essential = essential_from(p);
          g.penalty = p.number("penalty");
          const std::string base =
              fmt::format("MLS basis {} with {} weight, dmax={} ({}), {}x Gauss cells, bc={}",
                          p.integer("basis"), p.text("kernel"), p.number("dmax"),
                          p.text("support"), p.integer("quad"), p.text("bc"));
          std::shared_ptr<const EnrichedApproximation> enriched;
          if (p.text("crack") == "none") {
            g.trial = mls;
            g.integration = cells;
            g.description = base;
          } else {
            Crack c;
            c.position = p.number("crack_x");
            if (p.text("crack") == "edge") {
              c.dim = 2;
              c.tip = p.number("crack_tip");
              c.branch = p.text("tip") == "branch";
            }  // a through crack is x = crack_x in 1D and 2D alike
            enriched = std::make_shared<EnrichedApproximation>(mls, c, support);
            g.trial = enriched;
            g.integration = std::make_shared<CrackCellScheme>(c, p.integer("quad"), cells);
            g.description =
                p.text("crack") == "edge"
                    ? fmt::format("{}; crack x={} up to y={}, step enrichment{}", base, c.position,
                                  c.tip, c.branch ? " and branch functions at the tip" : "")
                    : fmt::format("{}; crack at x={}, step enrichment", base, c.position);
          }
          g.formal = {2, 1, "MLS linear basis, Gauss cells (split at the crack): a smooth solution "
                            "away from the crack (Belytschko, Lu & Gu 1994)"};
          return std::make_unique<XefgMethod>(make_galerkin_method(std::move(g)), enriched);
        });
}

}  // namespace mfv
