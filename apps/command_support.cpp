#include "apps/command_support.hpp"
#include "apps/commands.hpp"

#include <cctype>
#include <chrono>
#include <thread>

#include <fmt/format.h>

#include "analyses/external_comparison.hpp"
#include "analyses/kernel_comparison.hpp"
#include "reports/convergence_table.hpp"
#include "reports/markdown.hpp"

namespace mfv::cli {

unsigned cores() {
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : n;
}

double wall_seconds() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}


/// Per study a convergence table (as deal.II's ConvergenceTable prints): one row per
/// resolution with each error and its pairwise rate, then the least-squares rate.
void print_rate_table(const Registries& c, const std::vector<StudyResult>& studies,
                      std::ostream& out) {
  for (const auto& s : studies) out << convergence_table(c, s) << "\n";
  out << "h: particle spacing in the problem's length unit; errors relative to the exact "
         "solution's norm on the common rule; rate: slope of ln(error) against ln(h) between "
         "successive resolutions, least squares: over all (004 II eq 7.3); CPU: setup + "
         "assembly + solve.\n";
}

/// Report header lines shared by compare and verify.
std::string machine_line(double wall, double cpu) {
  return fmt::format("Run {}, {} cores, wall {}, CPU {}.", utc_now(kReportTime), cores(),
                     fmt_seconds(wall), fmt_seconds(cpu));
}


namespace {

/// GitHub's anchor of a Markdown heading: lower case, punctuation dropped, spaces to '-'.
std::string heading_anchor(const std::string& heading) {
  std::string out;
  for (unsigned char ch : heading) {
    if (ch >= 0x80 || std::isalnum(ch) || ch == '-' || ch == '_')
      out += static_cast<char>(std::tolower(ch));
    else if (ch == ' ')
      out += '-';
  }
  return out;
}

/// Every study's convergence table as CSV and LaTeX (booktabs) under tables/<problem>/:
/// h, the particle count, the relative L2, H1-seminorm and (2D) energy errors on the common
/// rule with their pairwise and least-squares rates, and CPU seconds. Returns the index's
/// line about them ("" when no study has two resolutions).
std::string write_convergence_tables(const std::filesystem::path& dir,
                                     const std::vector<ReportSection>& sections) {
  int written = 0;
  for (const auto& section : sections)
    for (const auto& s : section.studies) {
      if (s.cases.size() < 2) continue;  // one resolution has no rate to tabulate
      ConvergenceTable t("h");
      const bool vector = s.cases.front().components > 1;
      for (const auto& c : s.cases) {
        t.add_row({{"h", c.h},
                   {"particles", static_cast<double>(c.particles)},
                   {"L2 relative", c.errors.l2_rel},
                   {"H1-seminorm relative", c.errors.h1_semi_rel}});
        if (vector) t.add_value("energy relative", c.errors.energy_rel);
        t.add_value("CPU s", c.cpu.total());
      }
      t.omit_from_rates("particles");
      t.omit_from_rates("CPU s");
      t.set_format("particles", [](double v) { return fmt::format("{:.0f}", v); });
      t.evaluate_all_rates();
      const std::filesystem::path sub =
          make_report_subdir(dir, std::filesystem::path("tables") / slug(section.problem)) /
          slug(s.label.empty() ? "study" : s.label);
      write_file_atomic(sub.string() + ".csv", t.csv());
      write_file_atomic(sub.string() + ".tex", t.tex());
      ++written;
    }
  return written == 0 ? ""
                      : fmt::format("Convergence tables of the {} studies with two or more "
                                    "resolutions, as CSV and LaTeX (`booktabs`): `tables/`.\n\n",
                                    written);
}

}  // namespace

/// Writes index.md (the head, then each section's summary), the files beside it (name →
/// content, e.g. results.json) and the sections' own files into the staging directory (made,
/// checked and locked before the computation) and swaps it in for the target. A kProblemsToc marker in the head becomes a list of links to the
/// sections' first "## " headings.
void write_report(const Catalogue& c, StagedDirectory& staged, const std::string& head,
                  std::vector<ReportSection> sections, bool vtk, bool vtk_finest_only,
                  const std::vector<std::pair<std::string, std::string>>& files) {
  std::string body, toc;
  for (auto& s : sections) {
    s.vtk_finest_only = vtk_finest_only;
    const std::string md = write_problem_section(c, s, staged.path(), vtk);
    const auto at = md.rfind("## ", 0) == 0 ? 0 : md.find("\n## ");
    if (at != std::string::npos) {
      const auto start = at == 0 ? 3 : at + 4;
      const std::string title = md.substr(start, md.find('\n', start) - start);
      toc += fmt::format("  - [{}](#{})\n", title, heading_anchor(title));
    }
    body += md;
  }
  std::string md = head;
  if (const auto marker = md.find(kProblemsToc); marker != std::string::npos)
    md.replace(marker, std::string(kProblemsToc).size(), toc);
  md += write_convergence_tables(staged.path(), sections);
  // The same problem and method under different kernels, side by side (issue 29).
  if (const auto comparisons = kernel_comparisons(sections); !comparisons.empty()) {
    write_file_atomic(staged.path() / "kernels.md", kernel_comparison_page(comparisons));
    md += fmt::format("**Kernels compared**: [kernels.md](kernels.md), {} table(s) of the same "
                      "problem and method under different kernels.\n\n",
                      comparisons.size());
  }
  // External solvers beside mfv's methods, across problems (issue 30).
  if (const TextTable ext = external_comparison(sections); !ext.rows.empty()) {
    write_file_atomic(staged.path() / "external.md", external_comparison_page(ext));
    md += fmt::format("**External solvers beside mfv**: [external.md](external.md), {} row(s): "
                      "each problem an external solver ran, every method at its resolutions.\n\n",
                      ext.rows.size());
  }
  md += body;
  for (const auto& [name, content] : files) write_file_atomic(staged.path() / name, content);
  write_file_atomic(staged.path() / "index.md", md);
  staged.commit();
}

/// The report's staging directory, made before the computation so that a target mfv may not
/// replace, an unwritable parent or a second writer fails at once (InputError, exit 2).
std::unique_ptr<StagedDirectory> stage_report(const std::filesystem::path& dir, bool force,
                                              const std::string& suite) {
  return std::make_unique<StagedDirectory>(dir, StagedDirectory::Options{force, suite});
}

bool written_by_mfv_verify(const std::string& head) {
  return head.rfind("# generated by `mfv verify", 0) == 0;
}
bool written_by_manifest_ctest(const std::string& head) {
  return head.rfind("# generated by mfv manifest-ctest", 0) == 0;
}
bool is_vtk_xml(const std::string& head) { return head.find("<VTKFile") != std::string::npos; }

RunInfo run_info(const Catalogue& c, const std::string& kind, double wall, double cpu) {
  return RunInfo{kind, utc_now(kReportTime), cores(), wall, cpu, c.plugins};
}

StudyProgress progress_printer(std::ostream& progress, const std::string& prefix) {
  return [&progress, prefix](int i, int n, int nodes) {
    progress << fmt::format("{} resolution {}/{}: {} nodes\n", prefix, i + 1, n, nodes)
             << std::flush;
  };
}

}  // namespace mfv::cli
