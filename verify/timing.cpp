#include "verify/timing.hpp"

#include <time.h>

#include <cstdlib>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

#include <fmt/format.h>

namespace mfv {

namespace {

double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

bool usable(double base, double cur) {
  return std::isfinite(base) && std::isfinite(cur) && base > 0 && cur > 0;
}

double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace

std::string fmt_ratio(double r) {
  if (!std::isfinite(r)) return "–";
  return r < 10 ? fmt::format("{:.2f}×", r) : fmt::format("{:.1f}×", r);
}

MachineFactor machine_factor(const std::vector<CaseTiming>& cases, double reference_now,
                             double reference_base) {
  MachineFactor f;
  std::vector<double> ratios;
  for (const auto& c : cases)
    if (usable(c.baseline, c.current) && c.baseline >= kFactorFloorSeconds)
      ratios.push_back(c.current / c.baseline);
  f.median_cases = static_cast<int>(ratios.size());
  if (!ratios.empty()) f.median = median_of(ratios);
  if (usable(reference_base, reference_now)) f.reference = reference_now / reference_base;
  if (f.median_cases >= kMinFactorCases) {
    f.factor = f.median;
    f.rule = fmt::format("median of {} cases", f.median_cases);
  } else if (f.reference > 0) {
    f.factor = f.reference;
    f.rule = "reference workload";
  } else {
    f.why_unknown = fmt::format(
        "{} case(s) with a baseline CPU of {:g} s or more, the median needs {}, and the "
        "baseline records no reference workload (re-record it with --update-baseline)",
        f.median_cases, kFactorFloorSeconds, kMinFactorCases);
  }
  return f;
}

std::vector<TimingVerdict> judge_timing(const std::vector<CaseTiming>& cases,
                                        const MachineFactor& f, double floor_seconds) {
  std::vector<TimingVerdict> out;
  if (!f.known() || !(f.factor > 0) || !std::isfinite(f.factor)) return out;
  for (const auto& c : cases) {
    if (!usable(c.baseline, c.current)) continue;
    TimingVerdict v{c.id, c.baseline, c.current, c.current / c.baseline, 0, false, false, ""};
    v.relative = v.ratio / f.factor;
    const double expected = f.factor * c.baseline;
    if (v.relative > kCpuRatio && c.current > expected + floor_seconds) {
      v.slower = true;
      v.message = fmt::format(
          "{}: CPU {:.3g} s against the baseline's {:.3g} s: {} the baseline, {} the run's "
          "machine factor {} ({}), above {:g}×: a timing regression",
          c.id, c.current, c.baseline, fmt_ratio(v.ratio), fmt_ratio(v.relative),
          fmt_ratio(f.factor), f.rule, kCpuRatio);
    } else if (1 / v.relative > kCpuRatio && expected > c.current + floor_seconds) {
      v.faster = true;
      v.message = fmt::format(
          "{}: CPU {:.3g} s against the baseline's {:.3g} s: {} faster than the machine factor "
          "{} predicts; if intended, run --update-baseline",
          c.id, c.current, c.baseline, fmt_ratio(1 / v.relative), fmt_ratio(f.factor));
    }
    out.push_back(std::move(v));
  }
  return out;
}

std::string timing_status(const std::vector<TimingVerdict>& v, const MachineFactor& f,
                          bool gated) {
  if (!f.known()) return fmt::format("timing: not judged ({})", f.why_unknown);
  std::vector<std::string> slow;
  for (const auto& t : v)
    if (t.slower) slow.push_back(fmt::format("{} ({})", t.id, fmt_ratio(t.relative)));
  const std::string factor = fmt::format("the run's machine factor {} ({})", fmt_ratio(f.factor), f.rule);
  if (slow.empty())
    return fmt::format("timing: {} case(s) judged, every one within {:g}× of {}", v.size(),
                       kCpuRatio, factor);
  const std::size_t shown = std::min<std::size_t>(slow.size(), 5);
  std::vector<std::string> first(slow.begin(), slow.begin() + static_cast<long>(shown));
  return fmt::format("timing: {} case(s) more than {:g}× slower than {}: {}{}; {}", slow.size(),
                     kCpuRatio, factor, fmt::join(first, ", "),
                     slow.size() > shown ? fmt::format(" and {} more", slow.size() - shown) : "",
                     gated ? "the timing gate fails the run"
                           : "not gated (--timing-gate or [suite] timing_gate = true fails on it)");
}

double reference_workload_seconds(int repeats) {
  // A fixed amount of floating-point work that touches a little memory: a 300 × 300 matrix
  // product, naive loops (no BLAS, no OpenMP, so one thread does all of it), then a loop of
  // transcendental functions. About 0.025 s on this project's machines.
  constexpr int n = 300;
  std::vector<double> a(n * n), b(n * n), c(n * n);
  for (int i = 0; i < n * n; ++i) {
    a[i] = std::sin(0.001 * i);
    b[i] = std::cos(0.002 * i);
  }
  double best = std::numeric_limits<double>::infinity();
  volatile double sink = 0;
  for (int r = 0; r < std::max(1, repeats); ++r) {
    const double t0 = thread_cpu_seconds();
    std::fill(c.begin(), c.end(), 0.0);
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < n; ++k) {
        const double aik = a[i * n + k];
        for (int j = 0; j < n; ++j) c[i * n + j] += aik * b[k * n + j];
      }
    double s = 0;
    for (int i = 0; i < 1000000; ++i) s += std::exp(-1e-6 * i) * std::sin(1e-3 * i + c[i % (n * n)]);
    sink = sink + s;
    best = std::min(best, thread_cpu_seconds() - t0);
  }
  (void)sink;
  return best;
}

MachineLoad read_machine_load() {
  MachineLoad m;
  double load[1] = {-1};
  if (::getloadavg(load, 1) == 1) m.load_average = load[0];
  std::ifstream in("/proc/stat");
  std::string line;
  if (std::getline(in, line) && line.rfind("cpu ", 0) == 0) {
    std::istringstream s(line.substr(4));
    unsigned long long v = 0;
    int field = 0;
    while (s >> v) {
      m.total += v;
      if (field == 7) m.steal = v;  // user nice system idle iowait irq softirq steal ...
      // guest and guest_nice are already counted in user and nice.
      if (field >= 7) {
        if (field == 8 || field == 9) m.total -= v;
      }
      ++field;
    }
  }
  return m;
}

double steal_fraction(const MachineLoad& start, const MachineLoad& end) {
  if (end.total <= start.total) return std::numeric_limits<double>::quiet_NaN();
  return static_cast<double>(end.steal - start.steal) /
         static_cast<double>(end.total - start.total);
}

}  // namespace mfv
