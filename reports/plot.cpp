#include "reports/plot.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
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
    "#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000",
    "#8C564B", "#7F3C8D", "#66A61E", "#E7298A", "#1F3A93", "#A6761D", "#17BECF",
    "#BCBD22", "#9E0142", "#5E4FA2", "#F46D43", "#4D4D00", "#FB9A99"};
constexpr std::array<int, 7> kPointTypes = {7, 5, 9, 13, 11, 6, 4};

struct Filtered {
  std::string label;
  std::vector<std::pair<double, double>> points;
};

/// "h²": a power in Unicode superscripts (the terminal prints text literally).
std::string power_text(const std::string& variable, int p) {
  static const std::array<const char*, 10> sup = {"⁰", "¹", "²", "³", "⁴",
                                                  "⁵", "⁶", "⁷", "⁸", "⁹"};
  std::string digits;
  for (char c : std::to_string(std::abs(p))) digits += sup[c - '0'];
  return variable + (p < 0 ? "⁻" : "") + digits;
}

/// Whether the y axis is logarithmic: asked for, or (auto_logy) every y positive and the
/// values spanning kAutoLogSpan or more.
bool use_logy(const PlotSpec& spec) {
  if (spec.logy) return true;
  if (!spec.auto_logy) return false;
  double lo = INFINITY, hi = 0;
  for (const auto& s : spec.series)
    for (std::size_t i = 0; i < s.y.size() && i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      if (s.y[i] <= 0) return false;
      lo = std::min(lo, s.y[i]);
      hi = std::max(hi, s.y[i]);
    }
  return hi > 0 && hi / lo >= kAutoLogSpan;
}

/// The series with the points a plot can show (finite; positive on a log axis).
std::vector<Filtered> filtered(const PlotSpec& spec, bool logy) {
  std::vector<Filtered> series;
  for (const auto& s : spec.series) {
    Filtered f{s.label, {}};
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      const double x = s.x[i], y = s.y[i];
      if (!std::isfinite(x) || !std::isfinite(y)) continue;
      if ((spec.logx && x <= 0) || (logy && y <= 0)) continue;
      f.points.emplace_back(x, y);
    }
    if (!f.points.empty()) series.push_back(std::move(f));
  }
  return series;
}

std::string build_script(const PlotSpec& spec, const std::vector<Filtered>& series, bool logy) {
  std::string gp;
  auto line = [&gp](const std::string& s) { gp += s + '\n'; };
  // The legend sits outside the plot on the right: make room for long and many entries.
  std::size_t longest = 0;
  for (const auto& s : series) longest = std::max(longest, s.label.size());
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
    if (xmin < xmax) line(fmt::format("set xrange [{:.17g}:{:.17g}]", xmin / 1.2, xmax * 1.2));
  }
  if (logy) line("set logscale y 10");
  if (logy) line("set format y '%.0e'");
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
    if (!logy) line("set yrange [0:*]");
  }
  line("set grid xtics ytics mxtics mytics lc rgb '#dddddd' lw 1");
  line("set key outside right top vertical Left reverse");
  for (std::size_t i = 0; i < series.size(); ++i) {
    line(fmt::format("set style line {} lc rgb '{}' lw 1.5 pt {} ps 1 dt {}", i + 1,
                     kColours[i % kColours.size()], kPointTypes[i % kPointTypes.size()],
                     i / kColours.size() + 1));
  }
  // Data blocks keep the data inside the script: no further temporary file and no file
  // name that would need quoting in gnuplot syntax.
  for (std::size_t i = 0; i < series.size(); ++i) {
    line(fmt::format("$d{} << EOD", i));
    for (const auto& [x, y] : series[i].points) line(fmt::format("{:.17g} {:.17g}", x, y));
    line("EOD");
  }
  // Reference slopes through the geometric mean of each series' value at its largest x.
  std::vector<std::string> references;
  if (spec.logx && logy && !spec.reference_slopes.empty()) {
    double xmin = INFINITY, xmax = 0, log_sum = 0;
    for (const auto& s : series)
      for (const auto& [x, y] : s.points) {
        xmin = std::min(xmin, x);
        xmax = std::max(xmax, x);
      }
    for (const auto& s : series) {
      const auto top = std::max_element(s.points.begin(), s.points.end());
      log_sum += std::log(top->second);
    }
    const double anchor = std::exp(log_sum / series.size());
    if (xmin < xmax)
      for (std::size_t k = 0; k < spec.reference_slopes.size(); ++k) {
        const int p = spec.reference_slopes[k];
        line(fmt::format("$r{} << EOD", k));
        line(fmt::format("{:.17g} {:.17g}", xmin, anchor * std::pow(xmin / xmax, p)));
        line(fmt::format("{:.17g} {:.17g}", xmax, anchor));
        line("EOD");
        references.push_back(fmt::format(
            "$r{} using 1:2 with lines lc rgb '#777777' lw 1 dt {} title {}", k, k + 2,
            gp_quote("∝ " + power_text(spec.reference_variable, p) + " (reference)")));
      }
  }
  std::string plot = "plot ";
  for (std::size_t i = 0; i < series.size(); ++i) {
    if (i > 0) plot += ", \\\n     ";
    plot += fmt::format("$d{} using 1:2 with {} ls {} title {}", i, spec.style, i + 1,
                        gp_quote(series[i].label));
  }
  for (const auto& r : references) plot += ", \\\n     " + r;
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
  const bool logy = use_logy(spec);
  const auto series = filtered(spec, logy);
  return series.empty() ? std::string() : build_script(spec, series, logy);
}

std::optional<std::string> write_svg_plot(const fs::path& svg_path, const PlotSpec& spec) {
  if (spec.style != "linespoints" && spec.style != "lines" && spec.style != "points" &&
      spec.style != "boxes")
    return fmt::format("unknown plot style '{}': use linespoints, lines, points or boxes",
                       spec.style);
  for (const auto& s : spec.series)
    if (s.x.size() != s.y.size())
      return fmt::format("series '{}' has {} x and {} y values", s.label, s.x.size(), s.y.size());
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
