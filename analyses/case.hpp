/// Results of one case (problem × method × analysis × resolution) and of a refinement study:
/// what every analysis fills in common (errors, headline values, CPU times) and, behind
/// CaseResult::data<T>(), each analysis's own result type.
#pragma once
#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>
#include <typeinfo>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "methods/core/params.hpp"
#include "problems/error_norms.hpp"
#include "problems/profile.hpp"

namespace mfv {

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
  /// Iterative solves that report it (PETSc): why the iteration stopped, e.g.
  /// "CONVERGED_RTOL" (KSPConvergedReasons); empty otherwise.
  std::string converged;
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
  /// The analysis that runs the case (analyses/analysis.hpp); empty: the problem's default,
  /// the first of Problem::analyses().
  std::string analysis;
};

/// The base of each analysis's own result type (StaticSolveData, TransientData, FigureData,
/// or a new analysis's): CaseResult holds one behind data<T>().
struct AnalysisResult {
  virtual ~AnalysisResult() = default;
};

/// Sampled fields for VTK files and plots (static solves).
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

/// What the static-solve analysis records besides errors and headline values: the linear
/// solve and the sampled fields.
struct StaticSolveData : AnalysisResult {
  SolveInfo solve;
  CaseFields fields;
};

/// What the transient analysis (explicit dynamics) records besides errors and headline values.
struct TransientData : AnalysisResult {
  double dt = 0, dt_critical = 0, end_time = 0;
  long steps = 0, retabulations = 0;
  long neighbour_rebuilds = 0;  ///< Eulerian: fresh neighbour searches among the retabulations
  /// Eulerian with DynamicsModel::degenerate_fallback: the most points on the fallback at any
  /// recomputation (0: every support kept its correction).
  long degenerate_peak = 0;
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
  /// The problem's time unit and unit system (TransientDefinition), for the plots' axes.
  std::string time_unit = "s", unit_system = "SI: m, s, kg, Pa";
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
  /// The problem's curves over space (TransientMeasures::Profile), plotted across studies.
  std::vector<Profile> profiles;
  /// Set when the run was found unstable (analyses/transient.hpp states the criteria): the
  /// step and time at which it was detected and why. The run stops there (a problem's own
  /// criterion may let it run on to its cap); checkpoints after it are not reached.
  struct Instability {
    long step = 0;
    double time = 0;
    std::string reason;  ///< "kinetic energy 3.1e+12 above 1e4 × the energy put in (…)"
  };
  std::optional<Instability> instability;
  /// A run by an external solver (issue 30, dynamics/external_solver.hpp), replayed through
  /// the problem's measurements: which solver, its command line, its wall and CPU seconds
  /// (children's rusage), the frames read back, and the tails of its stdout and stderr that
  /// the report keeps. Absent: mfv's own engine ran.
  struct External {
    std::string solver, command;
    double wall_seconds = 0, cpu_seconds = 0;
    int frames = 0;
    long solver_steps = -1;  ///< the solver's own steps to its last frame (-1: not stated)
    std::string stdout_tail, stderr_tail;
  };
  std::optional<External> external;
  /// "unstable at step k, t = …: <reason>", or "" for a stable run.
  std::string verdict() const {
    if (!instability) return "";
    return fmt::format("unstable at step {}, t = {:.6g}: {}", instability->step,
                       instability->time, instability->reason);
  }
};

/// What the stability and time-step analyses (dispersion, time-step, stretch-map, crack-sweep)
/// record besides their headline values: figures of curves, tables for CSV files and one-line
/// verdicts.
struct FigureData : AnalysisResult {
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
  std::string analysis;            ///< the analysis that ran it (spec.analysis resolved)
  Params problem_params;           ///< resolved, with defaults (the analysis's keys apart)
  Params method_params;            ///< resolved, with defaults
  Params analysis_params;          ///< resolved, with the problem's and the analysis's defaults
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
  /// The analysis's own result; data<T>() reaches it with its type.
  std::shared_ptr<AnalysisResult> detail;

  /// The analysis's result as T, made empty on first use by a case that holds none yet (an
  /// analysis filling it, a test building a case by hand); std::logic_error if the case holds
  /// another type (a report section of one analysis handed a case of another).
  template <class T>
  T& data() {
    if (!detail) return emplace<T>();
    if (auto* p = dynamic_cast<T*>(detail.get())) return *p;
    throw std::logic_error(fmt::format("case {} × {}: its analysis '{}' has no {} result",
                                       spec.problem, spec.method, analysis, typeid(T).name()));
  }
  /// The analysis's result as T (an empty one for a case that holds none: built by hand);
  /// std::logic_error if the case holds another type.
  template <class T>
  const T& data() const {
    static const T empty{};
    if (!detail) return empty;
    if (const auto* p = dynamic_cast<const T*>(detail.get())) return *p;
    throw std::logic_error(fmt::format("case {} × {}: its analysis '{}' has no {} result",
                                       spec.problem, spec.method, analysis, typeid(T).name()));
  }
  /// The analysis's result as T, or nullptr.
  template <class T>
  const T* find() const {
    return dynamic_cast<const T*>(detail.get());
  }
  /// Sets a fresh result of type T and returns it.
  template <class T>
  T& emplace() {
    auto p = std::make_shared<T>();
    T& ref = *p;
    detail = std::move(p);
    return ref;
  }
};

/// Convergence rates of a study keyed by error column ("L2", "H1-semi", "energy"), as
/// deal.II's ConvergenceTable keys them: the least-squares slope of ln(error) against ln(h)
/// (004 II eq 7.3) and the slopes between successive resolutions, computed by a
/// reports/convergence_table.hpp table of the study's errors (study_rates). A column that is
/// not there reads NaN and no pairwise rates.
struct Rates {
  std::map<std::string, double> fitted;
  std::map<std::string, std::vector<double>> pairwise;
  double rate(const std::string& column) const {
    const auto it = fitted.find(column);
    return it == fitted.end() ? NAN : it->second;
  }
  const std::vector<double>& pairwise_of(const std::string& column) const {
    static const std::vector<double> none;
    const auto it = pairwise.find(column);
    return it == pairwise.end() ? none : it->second;
  }
};

/// The error columns of a study's rates: the norms of ErrorNorms by name.
inline constexpr const char* kRateL2 = "L2";
inline constexpr const char* kRateH1Semi = "H1-semi";
inline constexpr const char* kRateEnergy = "energy";

struct StudyResult {
  std::string label;               ///< "rkpm kernel=gaussian,j=1"
  std::vector<CaseResult> cases;   ///< increasing resolution
  Rates rates;                     ///< on the common rule
  Rates rates_paper;               ///< on the paper's rule
};

}  // namespace mfv
