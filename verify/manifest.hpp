/// The verification manifest: the checked-in TOML list of cases and their expected bands.
#pragma once
// Format (suites/example.toml is a complete example):
//
//   [suite]                                   # optional table
//   name = "default"                          # default: the manifest's file name without .toml
//   description = "nightly 1D verification"
//   baseline = "baseline/default.toml"        # relative to the manifest's directory;
//                                             # omitted: no baseline, no drift checks
//   drift_tolerance = 0.05                    # relative; > 0; a number that moves more is flagged
//   drift_floor = 1e-12                       # absolute, >= 0: errors below it are round-off
//   timing_gate = false                       # true: a timing regression (a case far slower
//                                             # than the run's machine factor, verify/timing.hpp)
//                                             # fails the run; default: reported only
//   timing_floor_seconds = 2                  # >= 0: a case must also be this many seconds
//                                             # beyond its scaled baseline to be judged slower
//   ledger = "ledger.toml"                    # relative to the manifest's directory: the
//                                             # reproduction ledger (verify/ledger.hpp) whose
//                                             # verdicts open the report; omitted: none
//   plugins = ["lib/libmine.so"]              # plugin libraries (apps/plugin.hpp) loaded
//                                             # before the catalogue is built, relative to the
//                                             # manifest's directory: their kernels, methods,
//                                             # problems and analyses are names in the cases
//
//   [[case]]                                  # one per case, at least one
//   id = "laplace-tanh/fem"                   # required, unique, no white space (a CTest name)
//   problem = "laplace-tanh"                  # required
//   problem_params = { s = 10 }               # optional
//   analysis = "static-solve"                 # optional: the problem's first declared
//   method = "fem"                            # required
//   method_params = { quad = 10 }             # optional
//   nodes = [21, 41, 81, 161]                 # required: increasing integers >= 2
//   full_nodes = [21, 41, 81, 161, 241]       # optional, used with --full (default: nodes)
//   perturbation = 0.0                        # optional, >= 0
//   full_only = true                          # optional: runs only with --full (a paper-size
//                                             # run, or a check too costly for the nightly):
//                                             # no CTest test, no baseline, bands apply
//   labels = ["fast"]                         # optional extra CTest labels
//   drift_tolerance = 0.5                     # optional, > 0: overrides the suite's for this
//                                             # case (ill-conditioned systems whose errors
//                                             # carry round-off)
//   expect = "unstable"                       # optional, "stable" (default) or "unstable":
//                                             # transient runs only. A run that blows up (see
//                                             # analyses/transient.hpp: non-finite fields,
//                                             # kinetic energy above 1e4 × the energy put in,
//                                             # or the problem's own criterion) fails the case
//                                             # with "unstable at step k, t = …" unless the case
//                                             # expects it; a case that expects instability
//                                             # fails at every resolution that stays stable.
//   [case.bands]                              # optional; each band is [low, high], low <= high
//   l2_rate = [1.9, 2.1]                      # least-squares rates over the resolutions
//   h1_rate = [0.9, 1.1]
//   l2_finest = [0.0, 2e-3]                   # errors at the finest (last) of `nodes`, also
//                                             # with --full when full_nodes contains it
//   h1_finest = [0.0, 0.3]
//   l2_rel_finest = [0.0, 1e-2]
//   h1_rel_finest = [0.0, 1e-1]
//   headline = { "peak du/dx at x=3" = [9.7, 9.9] }  # problem headline quantities, finest
//
// Unknown keys anywhere are errors rather than being ignored, so that a typo such as
// `l2_rte` cannot silently drop a check. Parameter values: integers and floats become numbers,
// strings stay text, booleans become the text "true"/"false". A band bound may be `-inf` (low)
// or `inf` (high) for a one-sided band; nan, a low of inf or a high of -inf is an error. A
// measured value that is not finite is outside every band. "h1" means the H1 seminorm ‖e'‖ throughout, as in the paper.
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "methods/core/params.hpp"
#include "analyses/case.hpp"

namespace mfv {

/// An admissible interval [low, high]; `line` is where it is written in the manifest so
/// that a violation can point at the number to edit.
struct Band {
  double low = 0, high = 0;
  int line = 0;
};

struct ManifestCase {
  std::string id, problem, method;
  Params problem_params, method_params;
  /// The analysis that runs the case; empty: the problem's default (its first declared).
  std::string analysis;
  std::vector<int> nodes, full_nodes;
  double perturbation = 0;
  std::vector<std::string> labels;
  std::optional<double> drift_tolerance;       ///< overrides Manifest::drift_tolerance
  bool expect_unstable = false;                ///< `expect = "unstable"`
  bool full_only = false;                      ///< runs only with --full, never in the baseline
  std::map<std::string, Band> bands;           ///< keyed by a name from band_metrics()
  std::map<std::string, Band> headline_bands;  ///< keyed by the problem's headline name
  int line = 0;                                ///< line of the case's [[case]] header
};

struct Manifest {
  std::filesystem::path path;      ///< as given to load_manifest (used in messages)
  std::string name, description;
  std::filesystem::path baseline;  ///< resolved against the manifest's directory; empty: none
  std::filesystem::path ledger;    ///< likewise: the reproduction ledger; empty: none
  /// [suite] plugins: libraries loaded before the catalogue is built (apps/plugin.hpp),
  /// resolved against the manifest's directory, in file order.
  std::vector<std::filesystem::path> plugins;
  double drift_tolerance = 0.05, drift_floor = 1e-12;
  /// [suite] timing_gate: a timing regression fails the run (verify/timing.hpp).
  bool timing_gate = false;
  /// [suite] timing_floor_seconds (verify/timing.hpp's floor).
  double timing_floor_seconds = 2;
  std::vector<ManifestCase> cases;  ///< in file order

  /// The case with this id; InputError naming the near ids ("did you mean") otherwise.
  const ManifestCase& find(const std::string& id) const;
  /// The cases `pattern` names: an id, or a shell glob over the ids (`*`, `?`, `[…]`, as
  /// fnmatch(3); "rod-pulse/*", "*-eulerian*"), in manifest order. InputError when nothing
  /// matches, with the near ids ("did you mean") and the count of cases, never all of them.
  std::vector<const ManifestCase*> select(const std::string& pattern) const;
};

/// The band metric names accepted in [case.bands] (besides `headline`), in report order.
const std::vector<std::string>& band_metrics();

/// Reads and checks a manifest. Throws InputError "<file>:<line>: <what>; <how to fix>".
Manifest load_manifest(const std::filesystem::path& path);

/// The resolutions to run: full_nodes with --full, nodes otherwise.
std::vector<int> resolutions(const ManifestCase& c, bool full);

struct BandViolation {
  std::string case_id;
  std::string metric;  ///< a band_metrics() name or "headline:<name>"
  double value = 0;    ///< NaN when the quantity is missing or undefined
  Band band;
  std::string message;  ///< one sentence naming case, metric, value, band and manifest line
};

/// Every band of `c` that the study misses. Rates come from s.rates (common rule), the
/// _finest metrics and headlines from the case of `s` at the last of c.nodes (the last case
/// of `s` if there is none, e.g. a --full study without it). NaN always violates.
/// `manifest_file` is the name printed with the band's line.
std::vector<BandViolation> check_bands(const ManifestCase& c, const StudyResult& s,
                                       const std::string& manifest_file);

/// The stability of a transient study against the case's `expect`: one message per
/// resolution that blew up when stability was expected ("<id>: 121 nodes: unstable at step 9,
/// t = 0.0018: …"), or that stayed stable under `expect = "unstable"`. Each is a failure.
/// A study without transient runs gives nothing, unless it expects instability (then the
/// message says that `expect` applies to transient problems only).
std::vector<std::string> check_stability(const ManifestCase& c, const StudyResult& s);

namespace detail {
/// The largest manifest, baseline or ledger read (16 MiB: the checked-in ones are < 200 kB).
inline constexpr std::size_t kMaxTextFileBytes = std::size_t{16} << 20;
/// The whole content of a regular text file of at most kMaxTextFileBytes; throws InputError
/// "cannot read <what> <path>: <why>; <hint>" for a missing or unreadable file, a directory,
/// a FIFO (never waited on), a device or socket, and a file larger than the bound. Shared by
/// the manifest, baseline and ledger readers.
std::string read_text_file(const std::filesystem::path& path, const std::string& what,
                           const std::string& hint);
}  // namespace detail

}  // namespace mfv
