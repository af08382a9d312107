/// The GRK critical time step of 004 III eq 5.2.5 ("analytic" column of its §5.2 table),
/// defined in problems/time_step.cpp and shared by the `time-step` and `grk-bar` problems.
#pragma once

namespace mfv {

/// 004 III eqs 5.2.3–5.2.5 for the Gaussian window r⁻¹Φ((x−y)/r) = e^{−(x−y)²/r²}/(r√π)
/// (eq 2.5.1) on nodes dx apart, element length l = dx, bar wave speed c:
///   λ_max = (2c²/l²) r² dx Σ,   Δt = 2/√λ_max = √2 (l/c) (r² dx Σ)^{−1/2}    (5.2.3–5.2.5)
/// Eq 5.2.5 is printed with the r² of eq 5.2.3 lost; we keep it. Σ = Σ_i [D Φ' + D' Φ]_i² Δx_i
/// is read as its interior continuous limit (eq 5.2.7: D = 1, D' = 0, the sum an integral):
///   Σ = ∫ (∂_x r⁻¹Φ)² dy = 1/(√(2π) r³)   ⇒   Δt = √2 (l/c) (√(2π) r/dx)^{1/2}.
/// With r = 2^j dx √(2/π) (eq 2.5.2) this is 2^{(j+2)/2} l/c. NaN unless r, dx, c are
/// positive and finite.
double grk_critical_step_eq525(double r, double dx, double c);

}  // namespace mfv
