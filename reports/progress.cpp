#include "reports/progress.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include <unistd.h>

#include <fmt/format.h>

namespace mfv {

namespace {

using namespace std::chrono_literals;

constexpr int kBarWidth = 20;
constexpr auto kRedrawInterval = 200ms;  // at most ~5 redraws per second
// The clock is read every N update() calls; N doubles while reads come faster than
// kCheckFast and halves when slower than kCheckSlow, so a microsecond-long time step pays
// for a clock read only once in thousands of steps and a slow one is still drawn on time.
constexpr auto kCheckFast = 20ms;
constexpr auto kCheckSlow = 100ms;
constexpr long kMaxCheckEvery = 1L << 20;

bool env_set(const char* name) { return std::getenv(name) != nullptr; }

bool is_terminal(std::FILE* out) {
  const int fd = ::fileno(out);
  return fd >= 0 && ::isatty(fd) == 1;
}

/// "6 s", "2 min 05 s", "1 h 02 min" into `buf`, without allocating.
void format_duration(char* buf, std::size_t size, double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) {
    std::snprintf(buf, size, "--");
    return;
  }
  const long s = std::lround(seconds);
  if (s < 60)
    std::snprintf(buf, size, "%ld s", s);
  else if (s < 3600)
    std::snprintf(buf, size, "%ld min %02ld s", s / 60, s % 60);
  else
    std::snprintf(buf, size, "%ld h %02ld min", s / 3600, (s % 3600) / 60);
}

}  // namespace

ProgressBar::ProgressBar(std::string label, long total_steps, bool quiet, std::FILE* out,
                         bool force)
    : label_(std::move(label)), total_(total_steps), out_(out) {
  if (total_steps < 0)
    throw std::invalid_argument(fmt::format("ProgressBar '{}': total_steps is {}; pass the "
                                            "number of steps (0 or more)",
                                            label_, total_steps));
  enabled_ = out_ != nullptr && !quiet &&
             (force || (is_terminal(out_) && !env_set("CI") && !env_set("MFV_QUIET")));
}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::update(long step, double sim_time, const char* time_unit) {
  if (!enabled_ || finished_) return;
  step_ = step;
  sim_time_ = sim_time;
  if (!drawn_) {
    start_ = last_check_ = Clock::now();
    first_step_ = step;
    std::snprintf(unit_.data(), unit_.size(), "%s", time_unit ? time_unit : "");
    draw(start_, false);
    return;
  }
  if (++calls_ < check_every_) return;
  calls_ = 0;
  const auto now = Clock::now();
  const auto since_check = now - last_check_;
  last_check_ = now;
  if (since_check < kCheckFast && check_every_ < kMaxCheckEvery)
    check_every_ *= 2;
  else if (since_check > kCheckSlow && check_every_ > 1)
    check_every_ /= 2;
  if (now - last_draw_ < kRedrawInterval) return;
  std::snprintf(unit_.data(), unit_.size(), "%s", time_unit ? time_unit : "");
  draw(now, false);
}

void ProgressBar::finish() {
  if (finished_) return;
  finished_ = true;
  if (!enabled_ || !drawn_) return;
  draw(Clock::now(), true);
  std::fputc('\n', out_);
  std::fflush(out_);
}

void ProgressBar::draw(Clock::time_point now, bool final) {
  drawn_ = true;
  last_draw_ = now;
  // Integer arithmetic, so 1125/2500 is 45%, not 44% from 0.45 * 100 rounding down.
  const long clamped = std::clamp(step_, 0L, total_);
  const int percent = total_ > 0 ? static_cast<int>(clamped * 100 / total_) : 100;
  const int filled = total_ > 0 ? static_cast<int>(clamped * kBarWidth / total_) : kBarWidth;
  char bar[kBarWidth + 1];
  std::memset(bar, '#', static_cast<std::size_t>(filled));
  std::memset(bar + filled, '.', static_cast<std::size_t>(kBarWidth - filled));
  bar[kBarWidth] = '\0';

  const double elapsed = std::chrono::duration<double>(now - start_).count();
  char when[32];
  if (final) {
    std::memcpy(when, "in ", 3);
    format_duration(when + 3, sizeof when - 3, elapsed);
  } else {
    const long done = step_ - first_step_;
    const double eta = done > 0 ? elapsed * static_cast<double>(total_ - step_) / done : -1.0;
    std::memcpy(when, "ETA ", 4);
    format_duration(when + 4, sizeof when - 4, eta);
  }

  // A long label would wrap the line, and a wrapped line cannot be redrawn with '\r'.
  int n = std::snprintf(line_.data(), line_.size(),
                        "\r%.24s%s[%s] %3d%% step %ld/%ld t=%.4g%s%s %s", label_.c_str(),
                        label_.empty() ? "" : " ", bar, percent, step_, total_, sim_time_,
                        unit_[0] ? " " : "", unit_.data(), when);
  n = std::clamp(n, 0, static_cast<int>(line_.size()) - 1);
  const int length = n - 1;  // without the '\r'
  // Blank what is left of a longer previous line (the ETA shrinks from "1 min 05 s" to "9 s").
  while (n < last_length_ + 1 && n < static_cast<int>(line_.size()) - 1) line_[n++] = ' ';
  line_[n] = '\0';
  last_length_ = length;
  std::fputs(line_.data(), out_);
  std::fflush(out_);
}

}  // namespace mfv
