#include "reports/plot.hpp"

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

// Okabe–Ito colours (distinguishable with colour-blindness) and filled, then open, markers;
// the two cycles have coprime lengths so colour and marker repeat together only after 56.
constexpr std::array<const char*, 8> kColours = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                                 "#E69F00", "#56B4E9", "#000000", "#999999"};
constexpr std::array<int, 7> kPointTypes = {7, 5, 9, 13, 11, 6, 4};

struct Filtered {
  std::string label;
  std::vector<std::pair<double, double>> points;
};

std::string build_script(const PlotSpec& spec, const std::vector<Filtered>& series) {
  std::string gp;
  auto line = [&gp](const std::string& s) { gp += s + '\n'; };
  line("set terminal svg size 720,480 font \"sans,11\" noenhanced background rgb 'white'");
  line("set encoding utf8");
  if (!spec.title.empty()) line("set title " + gp_quote(spec.title));
  line("set xlabel " + gp_quote(spec.xlabel));
  line("set ylabel " + gp_quote(spec.ylabel));
  if (spec.logx) line("set logscale x 10");
  if (spec.logy) line("set logscale y 10");
  line("set grid xtics ytics mxtics mytics lc rgb '#dddddd' lw 1");
  line("set key outside right top vertical Left reverse");
  for (std::size_t i = 0; i < series.size(); ++i) {
    line(fmt::format("set style line {} lc rgb '{}' lw 1.5 pt {} ps 1", i + 1,
                     kColours[i % kColours.size()], kPointTypes[i % kPointTypes.size()]));
  }
  // Data blocks keep the data inside the script: no further temporary file and no file
  // name that would need quoting in gnuplot syntax.
  for (std::size_t i = 0; i < series.size(); ++i) {
    line(fmt::format("$d{} << EOD", i));
    for (const auto& [x, y] : series[i].points) line(fmt::format("{:.17g} {:.17g}", x, y));
    line("EOD");
  }
  std::string plot = "plot ";
  for (std::size_t i = 0; i < series.size(); ++i) {
    if (i > 0) plot += ", \\\n     ";
    plot += fmt::format("$d{} using 1:2 with {} ls {} title {}", i, spec.style, i + 1,
                        gp_quote(series[i].label));
  }
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

std::optional<std::string> write_svg_plot(const fs::path& svg_path, const PlotSpec& spec) {
  if (spec.style != "linespoints" && spec.style != "lines" && spec.style != "points")
    return fmt::format("unknown plot style '{}': use linespoints, lines or points", spec.style);
  std::vector<Filtered> series;
  for (const auto& s : spec.series) {
    if (s.x.size() != s.y.size())
      return fmt::format("series '{}' has {} x and {} y values", s.label, s.x.size(), s.y.size());
    Filtered f{s.label, {}};
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      const double x = s.x[i], y = s.y[i];
      if (!std::isfinite(x) || !std::isfinite(y)) continue;
      if ((spec.logx && x <= 0) || (spec.logy && y <= 0)) continue;
      f.points.emplace_back(x, y);
    }
    if (!f.points.empty()) series.push_back(std::move(f));
  }
  if (series.empty()) return "nothing to plot: every series is empty";

  const auto gnuplot = find_on_path("gnuplot");
  if (!gnuplot) return "gnuplot not found: install the Debian package gnuplot-nox";

  try {
    PendingFile svg(svg_path, "tmp");
    PendingFile script(svg_path, "gp");
    PendingFile err(svg_path, "err");
    {
      std::ofstream out(script.path(), std::ios::binary | std::ios::trunc);
      out << build_script(spec, series);
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

PlotSpec convergence_plot(const std::string& title, const std::vector<StudyResult>& studies,
                          const std::string& ylabel,
                          const std::function<double(const CaseResult&)>& error,
                          const std::function<double(const Rates&)>& rate) {
  PlotSpec spec;
  spec.title = title;
  spec.xlabel = "h (nominal particle spacing)";
  spec.ylabel = ylabel;
  spec.logx = spec.logy = true;
  spec.style = "linespoints";
  for (const auto& study : studies) {
    Series s;
    s.label = fmt::format("{} (rate {})", study.label, fmt_rate(rate(study.rates)));
    for (const auto& c : study.cases) {
      s.x.push_back(c.h);
      s.y.push_back(error(c));
    }
    spec.series.push_back(std::move(s));
  }
  return spec;
}

PlotSpec convergence_plot(const std::string& title, const std::vector<StudyResult>& studies,
                          bool h1) {
  if (h1)
    return convergence_plot(
        title, studies, "H1 seminorm error ||u_h' - u'||",
        [](const CaseResult& c) { return c.errors.h1_semi; },
        [](const Rates& r) { return r.h1_semi; });
  return convergence_plot(
      title, studies, "L2 error ||u_h - u||", [](const CaseResult& c) { return c.errors.l2; },
      [](const Rates& r) { return r.l2; });
}

}  // namespace mfv
