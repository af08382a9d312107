/// Method registry type, the parts a method is composed from, and the entry point of the built-in
/// methods (the list is in register_all.cpp).
#pragma once
#include "methods/approximations/register.hpp"
#include "methods/integration/integration.hpp"
#include "methods/methods/method.hpp"

namespace mfv {

/// The registries a method is composed from.
struct MethodParts {
  const KernelRegistry& kernels;
  const ApproximationRegistry& approximations;
  const IntegrationRegistry& integrations;
};

/// Registers every built-in method (the list: methods/methods/register_all.cpp).
void register_all_methods(MethodRegistry& r, const MethodParts& parts);

/// Fills trial_q and test_q of a collocation method from the plain SPH table at the particles;
/// `degenerate` (null: throw) as the particle gradient functions take it. The SPH table is
/// scratch: `tables` may take its storage (swap it into trial_q and transform it in place).
using CollocationTables =
    std::function<void(ShapeTable& sph, const ParticleSet&, Discretization&, int threads,
                       DegenerateMarks* degenerate)>;
/// A collocation particle method (SPH, RLM): nodal rule, the SPH kernel table at the
/// particles turned into gradient tables by `tables`, particle values as unknowns and a
/// linear MLS fit of them as the field between particles.
std::unique_ptr<Method> make_collocation_method(const MethodParts& parts, const Params& p,
                                                const std::string& name,
                                                const CollocationTables& tables);

/// Dilation a = scale · 2^j · Δx of the RKPM windows, by the rule a paper states:
/// eq7.4: a = 2^{j+0.5} σ with Δx/(σ√π) = 1/√2 (Gaussian) or a = 2^{j+0.5} Δx (cubic window);
/// derived (Gaussian): a = 2^j Δx/π, the band edge 1/a at the Nyquist wavenumber for j = 0;
/// fit (Gaussian): a = 0.3297·2^j Δx fitted to Table 1; eq6.10: a0 = 2^j Δx √(2/π); custom:
/// the given scale.
double rkpm_dilation_scale(const Params& p, double kernel_support = 1.0);

/// How xefg's `support` convention scales dmax (the catalogue's reading note on 003 eq 30):
/// the support radius is dmax·Δx ("radius"; the spline's argument is r/d_m), dmax·Δx/2
/// ("diameter") or 2·dmax·Δx (the spline's argument is r/2h with h = dmax·Δx, "2h").
double xefg_support_factor(const std::string& convention);
/// rkpm's window parameters: the kernel (any registered one), j, rule and scale.
ParamSchema rkpm_window_schema(const KernelRegistry& kernels);

}  // namespace mfv
