/// Results of one case (problem × method × resolution) and of a refinement study: what the
/// runner computes and what reports, baselines and bands read.
#pragma once
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "methods/core/params.hpp"

namespace mfv {

/// Error norms of u_h - u (004 II eq 7.2): absolute and relative to the exact solution's norm.
struct ErrorNorms {
  double l2 = 0, l2_rel = 0;            ///< ‖e‖_L2
  double h1_semi = 0, h1_semi_rel = 0;  ///< ‖e'‖_L2 (the paper's "H1 norm")
  double h1 = 0, h1_rel = 0;            ///< full H1: sqrt(‖e‖² + ‖e'‖²)
  /// Energy norm sqrt(∫ σ(e):ε(e)) (001 eqs 73–74 with the customary square root; in 1D
  /// the H1 seminorm).
  double energy = 0, energy_rel = 0;
  /// Every norm NaN: what a run reports for a norm it does not measure (a transient case has
  /// no H1 error) or a checkpoint it did not reach (a run stopped as unstable); printed
  /// "–" / "not reached", never 0.
  static ErrorNorms not_measured() {
    ErrorNorms e;
    e.l2 = e.l2_rel = e.h1_semi = e.h1_semi_rel = e.h1 = e.h1_rel = e.energy = e.energy_rel = NAN;
    return e;
  }
};

/// CPU seconds of the phases of one case.
struct Timings {
  double setup = 0;     ///< particles, neighbour search, quadrature, shape functions
  double assembly = 0;  ///< stiffness and load
  double solve = 0;     ///< boundary conditions and linear solve
  double total() const { return setup + assembly + solve; }
};

inline constexpr int kMaxConditionSize = 1200;

struct SolveInfo {
  std::string solver;     ///< e.g. "UMFPACK LU", or the fallback taken
  int unknowns = 0;
  long nonzeros = 0;      ///< of the system matrix
  long fill = 0;          ///< nonzeros of the L and U factors (direct solves)
  double rcond = NAN;     ///< UMFPACK's reciprocal condition estimate (any size; cheap)
  int iterations = 0;     ///< iterative solves
  double residual = 0;    ///< ‖A x - b‖ / ‖b‖
  /// 2-norm condition number of the solved matrix, set by run_case outside the timed solve
  /// (dense SVD, systems up to kMaxConditionSize unknowns; NaN above). Wide Gaussian windows
  /// make it huge: then the errors carry round-off and move with the summation order.
  double condition = 0;
};

/// What to run.
struct CaseSpec {
  std::string problem;
  Params problem_params;
  std::string method;
  Params method_params;  ///< as given (unresolved); the resolved set is in CaseResult
  int nodes = 0;
  double perturbation = 0;  ///< random particle offsets, fraction of the spacing
  std::string solver = "auto";  ///< see kSolverChoices (verify/solver.hpp)
};

/// Sampled fields for VTK files and plots.
struct CaseFields {
  Eigen::VectorXd x;              ///< particle positions (1D)
  Eigen::VectorXd u_h, u_exact;   ///< at the particles: u_h(x_J) (not the coefficient)
  Eigen::VectorXd du_h, du_exact;
  Eigen::VectorXd coefficient;    ///< the solved particle coefficients u_J
  Eigen::VectorXd volume;         ///< particle volumes
  Eigen::VectorXd sx, su_h, su, sdu_h, sdu;  ///< a dense sampling of the line
  /// 2D problems: particle positions (dim × N), displacement and stress (Voigt) computed and
  /// exact at the particles; the same stresses at the method's own quadrature points (stress
  /// points, Gauss points), whose first `nodal_points` are the particles.
  Eigen::MatrixXd points, disp_h, disp_exact, stress_h, stress_exact;
  Eigen::MatrixXd q_points, q_stress_h, q_stress_exact;
  std::vector<std::string> stress_names;
};

/// What a transient (explicit dynamics) case records besides errors and headline values.
struct TransientData {
  double dt = 0, dt_critical = 0, end_time = 0;
  long steps = 0, retabulations = 0;
  /// The run ended before its end time (unstable, or a problem's stop cap): peak values
  /// measured over it are lower bounds of what the full run would reach.
  bool stopped_early = false;
  /// The largest displacement component of the unknowns over the sampled steps (the report
  /// compares it with the spacing: how far an Eulerian kernel's particles moved).
  double max_displacement = 0;
  std::string dynamics;  ///< the engine's description (frame, integrator, material, viscosity)
  /// What errors.l2_rel measures, with its units, for axis labels ("relative L2 velocity
  /// error ‖v_h − v‖/‖v‖ at t = L/c (001 eq 75), dimensionless"); empty: no error measured.
  std::string main_error;
  /// Time histories: columns "time", "kinetic", "internal work", "external work",
  /// "energy balance", then the problem's probes; one row per sample.
  std::vector<std::string> history_columns;
  std::vector<std::vector<double>> history;
  /// Particle snapshots for VTK time series: positions and named arrays (components × N).
  struct Frame {
    double time = 0;
    Eigen::MatrixXd x;
    std::vector<std::pair<std::string, Eigen::MatrixXd>> data;
  };
  std::vector<Frame> frames;
  /// Set when the run was found unstable (problems/transient.hpp states the criteria): the
  /// step and time at which it was detected and why. The run stops there (a problem's own
  /// criterion may let it run on to its cap); checkpoints after it are not reached.
  struct Instability {
    long step = 0;
    double time = 0;
    std::string reason;  ///< "kinetic energy 3.1e+12 above 1e4 × the energy put in (…)"
  };
  std::optional<Instability> instability;
  /// "unstable at step k, t = …: <reason>", or "" for a stable run.
  std::string verdict() const {
    if (!instability) return "";
    return fmt::format("unstable at step {}, t = {:.6g}: {}", instability->step,
                       instability->time, instability->reason);
  }
};

/// What a stability or time-step analysis (a problem with analysis() true) records besides
/// its headline values: figures of curves, tables for CSV files and one-line verdicts.
struct AnalysisData {
  std::string setup;  ///< the analysis settings (lattice, patch, frame, prestress, mass)
  struct Figure {
    std::string id;  ///< file stem, unique within the case ("dispersion", "dt-ratio")
    std::string title, xlabel, ylabel;
    bool logy = false;
    std::string style = "lines";  ///< or "linespoints", "points"
  };
  struct Curve {
    std::string figure;  ///< the Figure::id it is drawn in
    std::string label;
    std::vector<double> x, y;
  };
  struct Table {
    std::string name;  ///< file stem of the CSV
    std::vector<std::string> columns;
    std::vector<std::vector<double>> rows;
  };
  std::vector<Figure> figures;
  std::vector<Curve> curves;
  std::vector<Table> tables;
  /// Statements about this case: "stable", "spurious mode at κ = 1.000 π/Δx (θ = 0°)".
  std::vector<std::string> verdicts;
  bool empty() const { return setup.empty() && curves.empty() && tables.empty(); }
};

struct CaseResult {
  CaseSpec spec;
  Params method_params;            ///< resolved, with defaults
  std::string method_description;  ///< human-readable composition
  double h = 0;                    ///< nominal spacing Δx
  int dim = 1, components = 1;
  int particles = 0, quadrature_points = 0, cells = 0;
  int stress_points = 0;           ///< quadrature points that are not particles (stress points)
  std::string quadrature_kind;     ///< nodal, gauss-cells, stress-points
  ErrorNorms errors;               ///< on a common fine Gauss rule, independent of the method
  ErrorNorms errors_paper;         ///< on the paper's rule (Gauss points per cell between nodes)
  std::map<std::string, double> headline;
  Timings cpu;
  SolveInfo solve;
  CaseFields fields;
  TransientData transient;  ///< transient problems only (steps > 0)
  AnalysisData analysis;    ///< analysis problems only
};

/// Convergence rates: least-squares slope of ln(error) against ln(h) (004 II eq 7.3) and the
/// slope between each pair of successive resolutions.
struct Rates {
  double l2 = 0, h1_semi = 0, energy = 0;
  std::vector<double> l2_pairwise, h1_semi_pairwise, energy_pairwise;
};

struct StudyResult {
  std::string label;               ///< "rkpm kernel=gaussian,j=1"
  std::vector<CaseResult> cases;   ///< increasing resolution
  Rates rates;                     ///< on the common rule
  Rates rates_paper;               ///< on the paper's rule
};

}  // namespace mfv
