#include "apps/commands.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "verify/runner.hpp"

namespace mfv {

namespace {

template <class R>
void list_registry(const R& r, std::ostream& out) {
  out << fmt::format("{}s:\n", r.kind());
  for (const auto& name : r.keys()) {
    const auto& e = r.entry(name);
    out << fmt::format("  {:<20} {}\n", name, e.description);
    for (const auto& p : e.schema) {
      std::string range;
      if (!p.choices.empty()) range = fmt::format(" {{{}}}", fmt::join(p.choices, "|"));
      else if (p.min) range = fmt::format(" ({} {})", p.min_exclusive ? ">" : ">=", *p.min);
      out << fmt::format("      {}={}{}  {}\n", p.name, format_value(p.default_value), range,
                         p.description);
    }
  }
}

}  // namespace

void command_list(const Catalogue& c, std::ostream& out) {
  list_registry(c.kernels, out);
  list_registry(c.approximations, out);
  list_registry(c.integrations, out);
  list_registry(c.methods, out);
  list_registry(c.problems, out);
}

void command_run(const Catalogue& c, const RunOptions& o, std::ostream& out) {
  CaseSpec spec;
  spec.problem = o.problem;
  spec.method = o.method;
  spec.method_params = Params::parse(o.method_params);
  spec.problem_params = Params::parse(o.problem_params);
  spec.nodes = o.nodes;
  spec.perturbation = o.perturbation;
  const CaseResult r = run_case(c, spec);
  out << fmt::format("problem   {} {}\n", spec.problem, spec.problem_params.to_string());
  out << fmt::format("method    {} ({})\n", spec.method, r.method_description);
  out << fmt::format("nodes     {}  (dx = {:.6g}, {} quadrature points)\n", r.particles, r.h,
                     r.quadrature_points);
  out << fmt::format("L2 error  {:.6e}  (relative {:.6e})\n", r.errors.l2, r.errors.l2_rel);
  out << fmt::format("H1 semi   {:.6e}  (relative {:.6e})\n", r.errors.h1_semi, r.errors.h1_semi_rel);
  out << fmt::format("H1 full   {:.6e}  (relative {:.6e})\n", r.errors.h1, r.errors.h1_rel);
  out << fmt::format("paper-rule L2 {:.6e}, H1 semi {:.6e}\n", r.errors_paper.l2,
                     r.errors_paper.h1_semi);
  for (const auto& [k, v] : r.headline) out << fmt::format("{:<22} {:.6f}\n", k, v);
  out << fmt::format("CPU       setup {:.4f} s, assembly {:.4f} s, solve {:.4f} s\n", r.cpu.setup,
                     r.cpu.assembly, r.cpu.solve);
  out << fmt::format("solver    {}: {} unknowns, {} nonzeros, residual {:.1e}\n", r.solve.solver,
                     r.solve.unknowns, r.solve.nonzeros, r.solve.residual);
}

}  // namespace mfv
