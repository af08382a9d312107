/// CPU time judged against the machine that runs it (issue 42).
///
/// A baseline's CPU seconds were measured on one machine; the next machine of the same kind
/// may run every case 2× slower behind the same CPU name (a slower host, another tenant, steal
/// time). A uniform slowdown is the machine, never a regression. So each run measures how fast
/// this machine is against the baseline's, the *machine factor*, and judges every case's CPU
/// against the baseline scaled by it:
///
///   r_i = cpu_i / cpu_i^base,   f = median_i r_i  (cases with cpu^base >= kFactorFloorSeconds)
///   case i is a timing regression when  r_i / f > kCpuRatio  and  cpu_i > f cpu_i^base + floor
///   (floor: kCpuFloorSeconds, or the manifest's [suite] timing_floor_seconds).
///
/// The rule for f, in order:
///  1. the run's own median ratio over its cases, when at least kMinFactorCases have a
///     baseline CPU time of kFactorFloorSeconds or more: it measures the very mix of work the
///     run did, under the load the run saw, and one slow case cannot move a median;
///  2. otherwise (a run of one or a few cases, e.g. a CTest regression test) the ratio of a
///     fixed reference workload (reference_workload_seconds) to the one the baseline recorded;
///  3. otherwise no factor: timing is not judged, and the report says why.
/// Both ratios are reported when both exist, so that a reader sees they agree.
///
/// Timing is its own status, apart from accuracy: it fails the exit code only under a timing
/// gate (`--timing-gate`, or `timing_gate = true` in the manifest's [suite]).
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace mfv {

/// A case is a timing regression when more than this many times slower than the baseline
/// scaled by the machine factor (and kCpuFloorSeconds more). Generous on purpose: one case's
/// CPU seconds spread by about ±10 % over runs on a quiet machine (issue 28), and a real
/// slowdown is a factor.
inline constexpr double kCpuRatio = 3;
inline constexpr double kCpuFloorSeconds = 2;
/// Cases whose baseline CPU is below this are left out of the median (their seconds are
/// noise and start-up), and the median needs at least kMinFactorCases of the rest.
inline constexpr double kFactorFloorSeconds = 0.2;
inline constexpr int kMinFactorCases = 8;

/// One case's CPU seconds now and in the baseline (NaN: not recorded or not run).
struct CaseTiming {
  std::string id;
  double baseline = 0, current = 0;
};

/// How much slower (> 1) or faster (< 1) this machine runs than the baseline's, and how that
/// was measured.
struct MachineFactor {
  double factor = 1;          ///< the one used; meaningful only when known()
  std::string rule;           ///< "median of 389 cases", "reference workload", "" (none)
  double median = 0;          ///< the run's median ratio (0: not enough cases)
  int median_cases = 0;       ///< cases the median is over
  double reference = 0;       ///< reference workload ratio (0: not measured on both sides)
  std::string why_unknown;    ///< when !known(): why no factor could be measured
  bool known() const { return !rule.empty(); }
};

/// The rule above. `reference_now` and `reference_base` are the reference workload's CPU
/// seconds here and in the baseline (0 or NaN: not measured).
MachineFactor machine_factor(const std::vector<CaseTiming>& cases, double reference_now,
                             double reference_base);

/// A case's timing, judged against the factor.
struct TimingVerdict {
  std::string id;
  double baseline = 0, current = 0;
  double ratio = 0;       ///< current / baseline
  double relative = 0;    ///< ratio / factor: how much slower than the rest of the run
  bool slower = false;    ///< a timing regression
  bool faster = false;    ///< as many times faster: a note asking for --update-baseline
  std::string message;
};

/// Every case with a finite positive baseline and current CPU, judged; those neither slower
/// nor faster are returned too (with both flags false, message empty). Nothing is judged when
/// the factor is unknown. `floor_seconds`: how many seconds beyond the scaled baseline a case
/// must also be off (a short case's seconds are noise; [suite] timing_floor_seconds).
std::vector<TimingVerdict> judge_timing(const std::vector<CaseTiming>& cases,
                                        const MachineFactor& f,
                                        double floor_seconds = kCpuFloorSeconds);

/// The run's timing status in one line: "timing: every case within 3× of the machine factor
/// 2.21 (median of 389 cases)", "timing: 1 case 8.0× slower than the run's machine factor
/// 2.2: <id>", "timing: not judged (<why>)". `gated` adds whether it fails the run.
std::string timing_status(const std::vector<TimingVerdict>& v, const MachineFactor& f,
                          bool gated);

/// A fixed reference workload, the same on every commit (dense LU solves and transcendental
/// loops in one thread, nothing of mfv's numerics, so a change to a method never moves it):
/// its thread CPU seconds, the minimum of `repeats` runs (the least disturbed one).
double reference_workload_seconds(int repeats = 3);

/// How loaded the machine was: the 1-minute load average and the fraction of CPU time stolen
/// by the hypervisor (/proc/stat "steal") between two readings.
struct MachineLoad {
  double load_average = -1;  ///< -1: unknown
  /// /proc/stat cpu totals at the reading (jiffies); steal fraction is computed between two.
  unsigned long long total = 0, steal = 0;
};
MachineLoad read_machine_load();
/// Δsteal / Δtotal between two readings; NaN when /proc/stat was not readable.
double steal_fraction(const MachineLoad& start, const MachineLoad& end);

/// "3.04×": two decimals below 10, so that 3.04 never prints as "3.0×, above 3×".
std::string fmt_ratio(double r);

}  // namespace mfv
