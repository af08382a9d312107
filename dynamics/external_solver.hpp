/// External solvers (issue 30): a code that is not mfv's — an SPH, peridynamics or RKPM solver
/// in any language — run on a catalogue case through a file protocol, so that its fields can
/// be measured like a plugin's. This header is the protocol's C++ side:
///
///   1. SolverSpec: `solvers/<name>.toml` (what to run, which problems, timeout, install
///      hint), read and checked by read_solver_spec();
///   2. write_case_input(): the case as protocol "mfv-external-1" into a fresh directory
///      (input.json and particles.csv; docs/external-solvers.md is the specification);
///   3. run_solver(): the command, as an argument vector (never a shell), with that directory
///      as its only extra argument and its working directory, under a timeout, stdout and
///      stderr kept in the directory;
///   4. read_case_output(): the frames the solver wrote at the requested output times, each
///      checked (present, every particle once, every value finite); anything missing or
///      non-finite is an ExternalSolverError naming it, never a zero.
///
/// Nothing here knows a problem: the transient analysis fills an ExternalCase from its
/// definition and replays the frames through the problem's own measurements.
#pragma once
#include <array>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "methods/core/params.hpp"
#include "methods/methods/method.hpp"

namespace mfv {

/// The protocol version written into input.json ("protocol") and required of the solver's
/// output (frames/index.csv's first line).
inline constexpr const char* kExternalProtocol = "mfv-external-1";

/// A failure of an external run that is the solver's or its output's (a timeout, an exit
/// code, a missing frame, a NaN): the case fails with this reason.
class ExternalSolverError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The solver is not installed (its command or its check failed to start or failed): the
/// case is "not run", with the install hint.
class ExternalSolverMissing : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// `solvers/<name>.toml`, table [solver]:
///   command      = ["python3", "{solver_dir}/adapter.py"]   (argv; {solver_dir} is the
///                                                            TOML's directory)
///   problems     = ["rod-pulse", "oscillating-plate"]       (the problems it supports)
///   timeout      = 600          (seconds, > 0, per case)
///   description  = "..."
///   install_hint = "apt install python3-pysph"
///   check        = ["python3", "-c", "import pysph"]        (optional: exit 0 = installed)
///   [solver.params]                                         (optional: the solver's own
///   clamp = "held"                                           parameters and defaults, given
///   h_over_dx = 1.3                                          as -p key=value, passed on in
///                                                            input.json's solver_params)
struct SolverSpec {
  std::string name;  ///< the file's stem; `-m external:<name>`
  std::filesystem::path file;
  std::string description;
  std::vector<std::string> command;
  std::vector<std::string> check;
  std::vector<std::string> problems;
  double timeout = 600;
  std::string install_hint;
  Params params;  ///< [solver.params]: numbers and strings with their defaults
  /// Why the file cannot be used (read_solver_specs keeps a broken file as such instead of
  /// failing every command); "" for a good one.
  std::string broken;
  bool supports(const std::string& problem) const;
};

/// Reads and checks `file`; InputError (exit 2) naming the file, the key and the fix for a
/// missing or mistyped key, an empty command, a non-positive timeout, an unknown key.
SolverSpec read_solver_spec(const std::filesystem::path& file);

/// The solver specs of `dir` (every *.toml, sorted by name); an absent dir gives none. A file
/// read_solver_spec refuses is kept with its reason in `broken`: `external:<name>` then
/// fails with it when used, and every other command works.
std::vector<SolverSpec> read_solver_specs(const std::filesystem::path& dir);

/// A prescribed velocity of one particle component until a time (the rod's impulse).
struct ExternalPrescribed {
  int particle = 0, component = 0;
  double value = 0, until = 1e300;
};

/// One case as the protocol states it. Times are in the problem's time unit.
struct ExternalCase {
  std::string problem;
  Params problem_params;  ///< resolved
  Params solver_params;   ///< the case's method parameters, passed through
  int nodes = 0;          ///< the resolution (what `-n` gave)
  int dim = 2;
  std::string unit_system, time_unit;
  Eigen::MatrixXd x;            ///< dim × N reference positions
  Eigen::VectorXd volume, mass;  ///< N
  std::vector<unsigned> sides;  ///< N: the particle's Side bits (0: interior)
  Eigen::MatrixXd initial_velocity;  ///< dim × N (empty: at rest)
  std::vector<ExternalPrescribed> prescribed;
  /// The material: its registry name and parameters (E, nu, plane ...), and the density.
  std::string material;
  Params material_params;
  double density = 1;
  double end_time = 0;
  std::vector<double> checkpoints;   ///< a subset of output_times
  std::vector<double> output_times;  ///< increasing, > 0, ≤ end_time: a frame each
};

/// Writes input.json and particles.csv into `dir`, which must exist and be empty
/// (std::runtime_error otherwise): a solver never sees an earlier run's files.
void write_case_input(const std::filesystem::path& dir, const ExternalCase& c);

/// The last `bytes` of a file, "…" in front when cut (a solver's stdout or stderr, for the
/// report and for failure messages); "" for a file that cannot be read.
std::string file_tail(const std::filesystem::path& file, std::size_t bytes = 2000);

/// How a run went (the solver's exit, its time, its output logs).
struct SolverRun {
  int exit_code = 0;
  double wall_seconds = 0;
  double cpu_seconds = 0;  ///< user + system of the solver and the children it waited for
  std::filesystem::path stdout_file, stderr_file;
};

/// Runs spec.command + {dir} in `dir` without a shell, stdout and stderr to dir/stdout.txt and
/// dir/stderr.txt, under spec.timeout (then SIGTERM to its process group and, 5 s later,
/// SIGKILL). ExternalSolverMissing when the command cannot be started or spec.check fails;
/// ExternalSolverError for a timeout or a non-zero exit, with the tail of stderr.
SolverRun run_solver(const SolverSpec& spec, const std::filesystem::path& dir);

/// Whether spec.check (or, without one, the command's program) can run here; the reason
/// when not ("python3: no such program on PATH", "check ... exited 1").
std::optional<std::string> solver_missing(const SolverSpec& spec);

/// One frame the solver wrote: the fields of every particle at one output time, in the
/// particles' order (rows by id). Columns: x (current positions), u, v (dim × N), and the
/// Cauchy stress in Voigt order (xx, yy, xy in 2D; 1 × N in 1D) when the solver wrote it.
struct ExternalFrame {
  double time = 0;
  long steps = -1;  ///< the solver's steps from t = 0 (index.csv's optional column; -1: not given)
  Eigen::MatrixXd x, u, v, stress;
};

/// Reads dir/frames/: index.csv (the protocol line, the header "k,time" or "k,time,steps",
/// then a row for each frame written)
/// and frame-<k>.csv with the header id,ux,uy,vx,vy[,sxx,syy,sxy] (1D: id,ux,vx[,sxx]).
/// Every output time must have its frame, at its time within 1e-9 relative, every particle
/// exactly once, every value finite; ExternalSolverError names the first that is not
/// ("checkpoint t = 0.0115 (frame 3) missing", "frame 2 (t = 0.01): field vx is nan at
/// particle 17", "frame 0: 120 particles, expected 121").
std::vector<ExternalFrame> read_case_output(const std::filesystem::path& dir,
                                            const ExternalCase& c);

/// The solver's own energy account, frames/energy.csv (optional): the protocol line, a header
/// naming `time`, `kinetic`, `internal_work` and optionally `external_work` (other columns are
/// ignored), then rows from t = 0 to at least the last output time, times increasing, every
/// value finite. internal_work is the work the solver's internal forces (stress, artificial
/// viscosity, ...) did since t = 0, external_work the work loads and prescribed motions did on
/// the body; the balance K + W_int − W_ext stays at its t = 0 value for a conservative scheme,
/// as mfv's own (dynamics/explicit.hpp, EnergyBalance).
struct ExternalEnergy {
  std::vector<double> time, kinetic, internal_work, external_work;
  /// kinetic, internal_work, external_work at time t, linear between the rows (t clamped to
  /// the rows' range).
  std::array<double, 3> at(double t) const;
};

/// Reads dir/frames/energy.csv: std::nullopt when the solver wrote none; ExternalSolverError
/// naming the line and the field for anything else that is not as above ("frames/energy.csv
/// line 7: field kinetic is nan", "... ends at t = 0.5, before the last output time 1").
std::optional<ExternalEnergy> read_case_energy(const std::filesystem::path& dir,
                                               const ExternalCase& c);

/// The method `external:<name>`: an external solver as a choice of `-m` and of a manifest's
/// `method`. It has no shape functions of its own: discretize() refuses (InputError naming
/// the fix) for every analysis but the transient one, which asks particle_method() for the
/// particles and the state its measurements read (SPH, whose unknowns are the particle values)
/// and runs spec() on the case (analyses/transient.cpp).
class ExternalSolverMethod final : public Method {
 public:
  ExternalSolverMethod(SolverSpec spec, std::unique_ptr<Method> particle_method, Params params)
      : spec_(std::move(spec)), particles_(std::move(particle_method)), params_(std::move(params)) {}
  Discretization discretize(const Domain& domain, ParticleSet particles, int order) const override;
  void retabulate(Discretization& d, int order) const override;
  const SolverSpec& spec() const { return spec_; }
  const Method& particle_method() const { return *particles_; }
  const Params& params() const { return params_; }

 private:
  SolverSpec spec_;
  std::unique_ptr<Method> particles_;
  Params params_;
};

/// Registers `external:<name>` for each spec; its factory builds the registry's "sph" for the
/// particles (so `methods` must hold it, and outlive the entries: a Registries object).
/// Parameters: `keep` (1: keep the case directory, named on the progress line, for
/// debugging an adapter; 0 by default).
void register_external_solvers(MethodRegistry& methods, const std::vector<SolverSpec>& specs);

/// The directories solver files are read from, in order: each of $MFV_SOLVERS
/// (colon-separated), then the installed share/mfv/solvers beside the program
/// (<prefix>/bin/mfv), else the source tree's solvers/ (a build tree). Absent ones are skipped;
/// one named twice is read once.
std::vector<std::filesystem::path> solver_dirs();

/// Every spec of solver_dirs(); a name found twice is an InputError naming both files.
std::vector<SolverSpec> find_solver_specs();

}  // namespace mfv
