/// The parameters of `j2-viscoplastic`, Needleman's (1989) rate-dependent J2 model that 001
/// §9.4 uses for the compressed plate, each with the source it was found in (or "our choice"):
/// the material's defaults, and the table the plate problem and its report print.
///
/// The model (j2_viscoplastic.cpp): τ^∇J = C : (D − Dᵖ) (001 eq 76), Dᵖ = (3 ε̄̇ / 2σ̄) τ',
/// ε̄̇ = ε̇0 [σ̄ / g(ε̄)]^{1/m}, and one of two softening laws g(ε̄), floored at g_r > 0:
///   rational: g = σ0 ξ (1 + ε̄/ε0)^N / (1 + (ε̄/ε1)²)        (Peirce, Shih & Needleman 1984,
///             as implemented in Peridigm's "Viscoplastic Needleman" model — the default)
///   linear:   g = σ0 ξ (1 + ε̄/ε0)^N for ε̄ ≤ ε1, g(ε1) + h1 (ε̄ − ε1) beyond (h1 ≤ 0)
/// with ε0 = σ0/E and ξ a seeded per-point factor in [1 − a, 1 + a] (the imperfection).
///
/// | name         | value     | unit  | source                                                |
/// |--------------|-----------|-------|-------------------------------------------------------|
/// | E            | 211e9     | Pa    | Peridigm verification input (see kPeridigmInput)      |
/// | nu           | 0.3       | –     | our choice, not found (Peridigm's 1D test uses 0)     |
/// | density      | 7800      | kg/m³ | Peridigm verification input                           |
/// | sigma0       | 460e6     | Pa    | Peridigm verification input                           |
/// | eps0         | 0.00218   | –     | Peridigm verification input (= sigma0/E)              |
/// | N            | 0.1       | –     | Peridigm verification input                           |
/// | m            | 0.01      | –     | Peridigm verification input                           |
/// | rate0        | 1e-3      | 1/s   | Peridigm verification input                           |
/// | eps1         | 0.436     | –     | Peridigm verification input (= 200 eps0)              |
/// | softening    | rational  | –     | Peridigm viscoplastic_needleman_correspondence.cxx    |
/// | h1           | -2.11e9   | Pa    | our choice, not found (= -E/100; linear law only)     |
/// | residual     | 4.6e6     | Pa    | our choice, not found (= sigma0/100)                  |
/// | imperfection | 0         | –     | our choice, not found (001 Fig. 14 missing)           |
///
/// None of these values was found in Needleman (1989) or Belytschko, Chiang & Plaskacz (1994)
/// themselves: the only source found is Peridigm (a code, not a paper), whose model cites
/// Peirce, Shih & Needleman (1984). Whether Needleman (1989) softens by the rational or by a
/// linear law was not confirmed; both are implemented.
#pragma once
#include <string>
#include <string_view>
#include <vector>

namespace mfv {

/// One parameter value with its unit and where it comes from.
struct SourcedParameter {
  std::string name;    ///< the material's (or problem's, for density) parameter name
  double value;        ///< in the unit below
  std::string unit;    ///< "Pa", "1/s", "kg/m^3", "-" (dimensionless)
  std::string source;  ///< where the value was found, or "our choice, not found"
};

/// The parameter table of the Needleman (1989) viscoplastic model as far as it was found.
struct Needleman1989Parameters {
  /// Every entry above except `softening` (a choice, named by softening_law and its source).
  std::vector<SourcedParameter> entries;
  std::string softening_law;     ///< "rational" (the default of j2-viscoplastic)
  std::string softening_source;  ///< where that form was found
  /// The value of entry `name`; std::out_of_range when there is none.
  double value(std::string_view name) const;
};

/// The table above, as data.
Needleman1989Parameters needleman_1989_parameters();

}  // namespace mfv
