#include "reports/plot.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>

#include "reports/atomic.hpp"
#include "reports/markdown.hpp"

namespace mfv {

namespace fs = std::filesystem;

namespace {

/// The first executable `name` on PATH, searched as execvp does (an empty entry is the
/// current directory; an unset PATH means the system default), but without a shell.
std::optional<fs::path> find_on_path(const std::string& name) {
  std::string search;
  if (const char* env = std::getenv("PATH")) {
    search = env;
  } else {
    search = "/bin:/usr/bin";
  }
  std::size_t begin = 0;
  while (begin <= search.size()) {
    std::size_t end = search.find(':', begin);
    if (end == std::string::npos) end = search.size();
    const std::string dir = search.substr(begin, end - begin);
    const fs::path candidate = fs::path(dir.empty() ? "." : dir) / name;
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec) && ::access(candidate.c_str(), X_OK) == 0)
      return candidate;
    begin = end + 1;
  }
  return std::nullopt;
}

/// A gnuplot single-quoted string: backslashes are literal there and '' is a quote, so no
/// user text can end the string early. Line breaks would end the command, so they go.
std::string gp_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') {
      out += "''";
    } else if (c == '\n' || c == '\r') {
      out += ' ';
    } else {
      out += c;
    }
  }
  return out + "'";
}

// Okabe–Ito colours (distinguishable with colour-blindness) first, then further distinct
// hues (no greys: grey is the reference lines'); filled, then open, markers. The marker
// cycle (7) is coprime with the palette (20); past the palette the lines are dashed.
constexpr std::array<const char*, kPaletteSize> kColours = {
    "#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#882255",
    "#8C564B", "#7F3C8D", "#66A61E", "#E7298A", "#1F3A93", "#A6761D", "#17BECF",
    "#BCBD22", "#9E0142", "#5E4FA2", "#F46D43", "#4D4D00", "#FB9A99"};
constexpr std::array<int, 7> kPointTypes = {7, 5, 9, 13, 11, 6, 4};

struct Filtered {
  std::string label;
  SeriesRole role = SeriesRole::computed;
  std::vector<std::pair<double, double>> points;
  std::vector<double> hi;  ///< band: the upper edge at each point
  bool off_scale = false;
};

/// "h²": a power in Unicode superscripts (the terminal prints text literally).
std::string power_text(const std::string& variable, int p) {
  static const std::array<const char*, 10> sup = {"⁰", "¹", "²", "³", "⁴",
                                                  "⁵", "⁶", "⁷", "⁸", "⁹"};
  std::string digits;
  for (char c : std::to_string(std::abs(p))) digits += sup[c - '0'];
  return variable + (p < 0 ? "⁻" : "") + digits;
}

/// The largest |y| of a series' finite points (both edges of a band); 0 when none.
double peak_magnitude(const Series& s) {
  double peak = 0;
  for (std::size_t i = 0; i < s.y.size() && i < s.x.size(); ++i) {
    if (!std::isfinite(s.x[i])) continue;
    if (std::isfinite(s.y[i])) peak = std::max(peak, std::abs(s.y[i]));
    if (i < s.y_hi.size() && std::isfinite(s.y_hi[i])) peak = std::max(peak, std::abs(s.y_hi[i]));
  }
  return peak;
}

/// Which series are off scale: sort the computed curves' peaks |y| and find the lowest
/// gap where a peak exceeds kOffScaleFactor times the one below it (and the references'
/// peak); the curves above it are off scale. Without a reference they must be fewer than
/// half the curves, so two curves of different size (kinetic energy and its balance) are
/// never taken for a blow-up; with one, the reference sets the scale.
std::vector<bool> off_scale_series(const PlotSpec& spec) {
  std::vector<bool> off(spec.series.size(), false);
  std::vector<double> peaks;
  double reference = 0;
  for (const auto& s : spec.series) {
    const double peak = peak_magnitude(s);
    if (s.role == SeriesRole::computed) {
      peaks.push_back(peak);
    } else {
      reference = std::max(reference, peak);
    }
  }
  std::sort(peaks.begin(), peaks.end());
  const std::size_t n = peaks.size();
  double threshold = INFINITY;
  for (std::size_t j = reference > 0 ? 0 : n / 2 + 1; j < n; ++j) {
    const double below = std::max(j > 0 ? peaks[j - 1] : 0.0, reference);
    if (below > 0 && peaks[j] > kOffScaleFactor * below) {
      threshold = peaks[j];
      break;
    }
  }
  for (std::size_t i = 0; i < spec.series.size(); ++i)
    off[i] = spec.series[i].role == SeriesRole::computed && peak_magnitude(spec.series[i]) >= threshold;
  return off;
}

/// Whether the y axis is logarithmic: asked for, or (auto_logy) every y positive and the
/// values of the curves on scale spanning kAutoLogSpan or more.
bool use_logy(const PlotSpec& spec, const std::vector<bool>& off) {
  if (spec.logy) return true;
  if (!spec.auto_logy) return false;
  double lo = INFINITY, hi = 0;
  for (std::size_t k = 0; k < spec.series.size(); ++k) {
    const Series& s = spec.series[k];
    for (std::size_t i = 0; i < s.y.size() && i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      if (s.y[i] <= 0) return false;
      if (off[k]) continue;
      lo = std::min(lo, s.y[i]);
      hi = std::max(hi, s.y[i]);
    }
  }
  return hi > 0 && hi / lo >= kAutoLogSpan;
}

/// The series with the points a plot can show (finite; positive on a log axis).
std::vector<Filtered> filtered(const PlotSpec& spec, bool logy, const std::vector<bool>& off) {
  std::vector<Filtered> series;
  for (std::size_t k = 0; k < spec.series.size(); ++k) {
    const Series& s = spec.series[k];
    Filtered f{s.label, s.role, {}, {}, off[k]};
    const bool band = s.role == SeriesRole::band;
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      const double x = s.x[i], y = s.y[i];
      const double hi = band ? (i < s.y_hi.size() ? s.y_hi[i] : NAN) : y;
      if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(hi)) continue;
      if ((spec.logx && x <= 0) || (logy && (y <= 0 || hi <= 0))) continue;
      f.points.emplace_back(x, y);
      if (band) f.hi.push_back(hi);
    }
    if (!f.points.empty()) series.push_back(std::move(f));
  }
  return series;
}

/// Labelled tics for a log axis over [lo, hi] that holds fewer than two powers of ten
/// (gnuplot labels only those, so such an axis would show no number): 1, 2, 5 × 10^k, or
/// every 1 … 9 × 10^k when that gives fewer than three. Empty: gnuplot's own are fine.
std::string log_tics(double lo, double hi) {
  if (!(lo > 0) || !(hi > lo)) return "";
  const int k0 = static_cast<int>(std::floor(std::log10(lo))) - 1;
  const int k1 = static_cast<int>(std::ceil(std::log10(hi))) + 1;
  int decades = 0;
  for (int k = k0; k <= k1; ++k)
    if (std::pow(10.0, k) >= lo && std::pow(10.0, k) <= hi) ++decades;
  if (decades >= 2) return "";
  auto pick = [&](std::initializer_list<double> mantissas) {
    std::vector<double> v;
    for (int k = k0; k <= k1; ++k)
      for (double m : mantissas) {
        const double t = m * std::pow(10.0, k);
        if (t >= lo && t <= hi) v.push_back(t);
      }
    return v;
  };
  std::vector<double> tics = pick({1, 2, 5});
  if (tics.size() < 3) tics = pick({1, 1.5, 2, 3, 4, 5, 6, 7, 8, 9});
  if (tics.empty()) return "";
  std::string list;
  for (double t : tics) list += fmt::format("{}'{:g}' {:.17g}", list.empty() ? "" : ", ", t, t);
  return "(" + list + ")";
}

std::string build_script(const PlotSpec& spec, const std::vector<Filtered>& series, bool logy) {
  std::string gp;
  auto line = [&gp](const std::string& s) { gp += s + '\n'; };
  // Legend entries: an off-scale curve says so, with the peak that put it there.
  std::vector<std::string> labels;
  for (const auto& s : series) {
    std::string label = s.label;
    if (s.off_scale) {
      double peak = 0;
      for (const auto& [x, y] : s.points) peak = std::max(peak, std::abs(y));
      label += fmt::format(" (off scale: peak |y| {:.3g})", peak);
    }
    labels.push_back(std::move(label));
  }
  // The legend sits outside the plot on the right: make room for long and many entries.
  std::size_t longest = 0;
  for (const auto& l : labels) longest = std::max(longest, l.size());
  const int width = std::max(720, 760 + 7 * static_cast<int>(longest));
  const int height = std::max(480, 120 + 20 * static_cast<int>(series.size() + 3));
  line(fmt::format("set terminal svg size {},{} font \"sans,11\" noenhanced background rgb "
                   "'white'",
                   width, height));
  line("set encoding utf8");
  if (!spec.title.empty()) line("set title " + gp_quote(spec.title));
  line("set xlabel " + gp_quote(spec.xlabel));
  line("set ylabel " + gp_quote(spec.ylabel));
  if (spec.logx) {
    // Autoscaling a log axis rounds out to whole decades; keep the data's own range.
    double xmin = INFINITY, xmax = 0;
    for (const auto& s : series)
      for (const auto& [x, y] : s.points) {
        xmin = std::min(xmin, x);
        xmax = std::max(xmax, x);
      }
    line("set logscale x 10");
    if (xmin < xmax) {
      line(fmt::format("set xrange [{:.17g}:{:.17g}]", xmin / 1.2, xmax * 1.2));
      if (const std::string tics = log_tics(xmin / 1.2, xmax * 1.2); !tics.empty())
        line("set xtics " + tics);
    }
  }
  if (logy) line("set logscale y 10");
  if (logy) line("set format y '%.0e'");
  // Off-scale curves: fit y to the rest (bands and references included) and clip.
  if (std::any_of(series.begin(), series.end(), [](const Filtered& s) { return s.off_scale; })) {
    double lo = INFINITY, hi = -INFINITY;
    for (const auto& s : series) {
      if (s.off_scale) continue;
      for (std::size_t i = 0; i < s.points.size(); ++i) {
        lo = std::min(lo, s.points[i].second);
        hi = std::max(hi, i < s.hi.size() ? s.hi[i] : s.points[i].second);
      }
    }
    if (spec.style == "boxes" && !logy) lo = std::min(lo, 0.0);
    if (lo <= hi) {
      if (logy) {
        lo /= 1.5;
        hi *= 1.5;
        if (const std::string tics = log_tics(lo, hi); !tics.empty()) line("set ytics " + tics);
      } else {
        const double pad = hi > lo ? 0.05 * (hi - lo) : std::max(std::abs(hi), 1.0) * 0.05;
        if (!(spec.style == "boxes" && lo == 0)) lo -= pad;
        hi += pad;
      }
      line(fmt::format("set yrange [{:.17g}:{:.17g}]", lo, hi));
      line("set clip two");
    }
  }
  if (!spec.xtic_labels.empty()) {
    std::string tics;
    for (const auto& [x, label] : spec.xtic_labels)
      tics += fmt::format("{}{} {:.17g}", tics.empty() ? "" : ", ", gp_quote(label), x);
    line("set xtics (" + tics + ")");
    line(fmt::format("set xrange [{:.17g}:{:.17g}]", spec.xtic_labels.front().first - 0.75,
                     spec.xtic_labels.back().first + 0.75));
  }
  if (spec.style == "boxes") {
    // Bars side by side: each series offsets its x (the caller), all grow from y = 0.
    line("set style fill solid 0.75 border -1");
    line("set boxwidth 0.3 absolute");
    if (!logy && !std::any_of(series.begin(), series.end(),
                              [](const Filtered& s) { return s.off_scale; }))
      line("set yrange [0:*]");
  }
  line("set grid xtics ytics mxtics mytics lc rgb '#dddddd' lw 1");
  line("set key outside right top vertical Left reverse");
  // Computed curves take the palette in order; references are black with their own dashes.
  std::size_t computed = 0, references = 0;
  std::vector<std::string> styles;
  for (std::size_t i = 0; i < series.size(); ++i) {
    const Filtered& s = series[i];
    switch (s.role) {
      case SeriesRole::band:
        styles.push_back("with filledcurves fc rgb '#999999' fs transparent solid 0.3 noborder");
        break;
      case SeriesRole::reference:
        styles.push_back(fmt::format("with lines lc rgb '#000000' lw 2 dt {}", references % 4 + 1));
        ++references;
        break;
      case SeriesRole::data:
        styles.push_back("with points lc rgb '#000000' pt 6 ps 1.3");
        break;
      case SeriesRole::computed: {
        line(fmt::format("set style line {} lc rgb '{}' lw 1.5 pt {} ps 1 dt {}", i + 1,
                         kColours[computed % kColours.size()],
                         kPointTypes[computed % kPointTypes.size()],
                         computed / kColours.size() + 1));
        ++computed;
        // Computed curves carry markers so that they never look like a reference; on a dense
        // curve (a history, a profile) a marker every tenth of the points.
        if (spec.style == "lines")
          styles.push_back(fmt::format("with linespoints ls {} pi {}", i + 1,
                                       std::max<std::size_t>(1, s.points.size() / 10)));
        else
          styles.push_back(fmt::format("with {} ls {}", spec.style, i + 1));
        break;
      }
    }
  }
  // Data blocks keep the data inside the script: no further temporary file and no file
  // name that would need quoting in gnuplot syntax.
  for (std::size_t i = 0; i < series.size(); ++i) {
    line(fmt::format("$d{} << EOD", i));
    for (std::size_t j = 0; j < series[i].points.size(); ++j) {
      const auto [x, y] = series[i].points[j];
      if (series[i].role == SeriesRole::band)
        line(fmt::format("{:.17g} {:.17g} {:.17g}", x, y, series[i].hi[j]));
      else
        line(fmt::format("{:.17g} {:.17g}", x, y));
    }
    line("EOD");
  }
  // Reference slopes through the geometric mean of each computed series' value at its
  // largest x.
  std::vector<std::string> slopes;
  if (spec.logx && logy && !spec.reference_slopes.empty()) {
    double xmin = INFINITY, xmax = 0, log_sum = 0;
    int anchors = 0;
    for (const auto& s : series)
      for (const auto& [x, y] : s.points) {
        xmin = std::min(xmin, x);
        xmax = std::max(xmax, x);
      }
    for (const auto& s : series) {
      if (s.role != SeriesRole::computed || s.off_scale) continue;
      const auto top = std::max_element(s.points.begin(), s.points.end());
      log_sum += std::log(top->second);
      ++anchors;
    }
    if (xmin < xmax && anchors > 0) {
      const double anchor = std::exp(log_sum / anchors);
      for (std::size_t k = 0; k < spec.reference_slopes.size(); ++k) {
        const int p = spec.reference_slopes[k];
        line(fmt::format("$r{} << EOD", k));
        line(fmt::format("{:.17g} {:.17g}", xmin, anchor * std::pow(xmin / xmax, p)));
        line(fmt::format("{:.17g} {:.17g}", xmax, anchor));
        line("EOD");
        slopes.push_back(fmt::format(
            "$r{} using 1:2 with lines lc rgb '#777777' lw 1 dt {} title {}", k, k + 2,
            gp_quote("∝ " + power_text(spec.reference_variable, p) + " (reference)")));
      }
    }
  }
  // Bands first (underneath), then the curves in the caller's order.
  std::vector<std::string> items;
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t i = 0; i < series.size(); ++i) {
      if ((series[i].role == SeriesRole::band) != (pass == 0)) continue;
      items.push_back(fmt::format("$d{} using {} {} title {}", i,
                                  series[i].role == SeriesRole::band ? "1:2:3" : "1:2",
                                  styles[i], gp_quote(labels[i])));
    }
  for (const auto& r : slopes) items.push_back(r);
  std::string plot = "plot ";
  for (std::size_t i = 0; i < items.size(); ++i)
    plot += (i > 0 ? ", \\\n     " : "") + items[i];
  line(plot);
  return gp;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The informative line of gnuplot's stderr: its error lines read
/// `"<script>" line 7: <message>`, preceded by an echo of the command and a caret, and
/// warnings come first; the script's temporary name is noise in a report, so it goes.
std::string gnuplot_error(const std::string& err, const fs::path& script) {
  const std::string prefix = "\"" + script.string() + "\" ";
  std::string first_nonblank, first_error;
  std::istringstream lines(err);
  for (std::string l; std::getline(lines, l);) {
    if (l.starts_with(prefix)) l.erase(0, prefix.size());
    if (l.find_first_not_of(" \t^") == std::string::npos) continue;
    if (first_nonblank.empty()) first_nonblank = l;
    if (first_error.empty() && l.starts_with("line ") && l.find("warning:") == std::string::npos)
      first_error = l;
  }
  return first_error.empty() ? first_nonblank : first_error;
}

/// Runs gnuplot on `script` with stdout into `out` and stderr into `err`, through
/// posix_spawn rather than a shell, so no path needs shell quoting. Returns the failure.
std::optional<std::string> run_gnuplot(const fs::path& gnuplot, const fs::path& script,
                                       const fs::path& out, const fs::path& err) {
  posix_spawn_file_actions_t actions;
  if (posix_spawn_file_actions_init(&actions) != 0) return "cannot prepare to start gnuplot";
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out.c_str(), O_WRONLY | O_TRUNC, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err.c_str(), O_WRONLY | O_TRUNC, 0);
  // -d: ignore the user's ~/.gnuplot, so every machine draws the same plot.
  std::string prog = gnuplot.string(), defaults = "-d", file = script.string();
  char* argv[] = {prog.data(), defaults.data(), file.data(), nullptr};
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, prog.c_str(), &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0)
    return fmt::format("gnuplot failed: cannot start {}: {}", prog,
                       std::generic_category().message(rc));
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR)
      return fmt::format("gnuplot failed: {}", std::generic_category().message(errno));
  }
  const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  std::string message = gnuplot_error(read_text(err), script);
  if (ok) {
    if (read_text(out).find("</svg>") != std::string::npos) return std::nullopt;
    return "gnuplot failed: it wrote no complete SVG" + (message.empty() ? "" : ": " + message);
  }
  if (!message.empty()) return "gnuplot failed: " + message;
  if (WIFSIGNALED(status)) return fmt::format("gnuplot failed: killed by signal {}", WTERMSIG(status));
  return fmt::format("gnuplot failed: exit status {}", WEXITSTATUS(status));
}

}  // namespace

bool gnuplot_available() { return find_on_path("gnuplot").has_value(); }

std::string gnuplot_script(const PlotSpec& spec) {
  // Off scale only on a linear axis: decide the axis without the candidates first (a blow-up
  // alone must not turn the axis logarithmic), and keep them when it is logarithmic anyway.
  std::vector<bool> off = spec.mark_off_scale && !spec.logy
                              ? off_scale_series(spec)
                              : std::vector<bool>(spec.series.size(), false);
  const bool logy = use_logy(spec, off);
  if (logy) std::fill(off.begin(), off.end(), false);
  const auto series = filtered(spec, logy, off);
  return series.empty() ? std::string() : build_script(spec, series, logy);
}

std::vector<PlotSpec> split_plot(const PlotSpec& spec, std::size_t max_curves) {
  if (max_curves == 0) throw std::invalid_argument("split_plot: max_curves must be at least 1");
  std::vector<std::size_t> computed;
  for (std::size_t i = 0; i < spec.series.size(); ++i)
    if (spec.series[i].role == SeriesRole::computed) computed.push_back(i);
  if (computed.size() <= max_curves) return {spec};
  const std::size_t parts = (computed.size() + max_curves - 1) / max_curves;
  std::vector<PlotSpec> out;
  std::size_t next = 0;
  for (std::size_t p = 0; p < parts; ++p) {
    // Nearly equal parts: the first (n mod parts) take one more.
    const std::size_t take = computed.size() / parts + (p < computed.size() % parts ? 1 : 0);
    PlotSpec part = spec;
    part.series.clear();
    for (const auto& s : spec.series)
      if (s.role != SeriesRole::computed) part.series.push_back(s);
    for (std::size_t k = 0; k < take; ++k) part.series.push_back(spec.series[computed[next++]]);
    part.title = fmt::format("{}{}(part {} of {})", spec.title, spec.title.empty() ? "" : " ",
                             p + 1, parts);
    out.push_back(std::move(part));
  }
  return out;
}

std::optional<std::string> write_svg_plot(const fs::path& svg_path, const PlotSpec& spec) {
  if (spec.style != "linespoints" && spec.style != "lines" && spec.style != "points" &&
      spec.style != "boxes")
    return fmt::format("unknown plot style '{}': use linespoints, lines, points or boxes",
                       spec.style);
  for (const auto& s : spec.series) {
    if (s.x.size() != s.y.size())
      return fmt::format("series '{}' has {} x and {} y values", s.label, s.x.size(), s.y.size());
    if (s.role == SeriesRole::band && s.y_hi.size() != s.x.size())
      return fmt::format("band '{}' has {} x and {} upper values", s.label, s.x.size(),
                         s.y_hi.size());
  }
  const std::string text = gnuplot_script(spec);
  if (text.empty()) return "nothing to plot: every series is empty";

  const auto gnuplot = find_on_path("gnuplot");
  if (!gnuplot) return "gnuplot not found: install the Debian package gnuplot-nox";

  try {
    PendingFile svg(svg_path, "tmp");
    PendingFile script(svg_path, "gp");
    PendingFile err(svg_path, "err");
    {
      std::ofstream out(script.path(), std::ios::binary | std::ios::trunc);
      out << text;
      out.close();
      if (!out) return fmt::format("cannot write the gnuplot script for '{}'", svg_path.string());
    }
    if (auto failure = run_gnuplot(*gnuplot, script.path(), svg.path(), err.path()))
      return failure;
    svg.commit();
    return std::nullopt;
  } catch (const std::runtime_error& e) {
    return std::string(e.what());
  }
}

}  // namespace mfv
