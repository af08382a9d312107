/// Worked example of docs/architecture.md: a new analysis in one file. `volume-check`
/// discretizes a problem's particles with the case's method and compares the particle
/// volumes' sum with the domain's measure (what every quadrature and lumped mass relies on).
/// It applies to any problem on particles (ParticleProblem) that declares it, has its own
/// parameter schema (a tolerance), its own result type, its own page and its own verdict. In-
/// tree, the file goes in analyses/ and `X(volume_check)` in MFV_ANALYSES of
/// analyses/register_all.cpp; the tests pass it as an extension.
#include <cmath>

#include <fmt/format.h>

#include "analyses/analysis.hpp"
#include "analyses/report_section.hpp"
#include "reports/markdown.hpp"

namespace mfv {
namespace {

/// What a volume check records besides its headline values.
struct VolumeCheckData : AnalysisResult {
  double sum = 0, measure = 0;
  bool passed = false;
};

class VolumeCheck final : public Analysis {
 public:
  explicit VolumeCheck(const Params& p) : tolerance_(p.number("tolerance")) {}

  bool accepts(const Problem& problem) const override {
    return dynamic_cast<const ParticleProblem*>(&problem) != nullptr;
  }

  void run(const AnalysisContext& c, CaseResult& r) const override {
    const auto& problem = definition_of<ParticleProblem>(c, "volume-check", "particles");
    const Discretization d = discretize_case(problem, c, r);
    auto& out = r.emplace<VolumeCheckData>();
    const Domain dom = problem.domain();
    out.sum = d.particles.volume.sum();
    out.measure = dom.measure();
    out.passed = std::abs(out.sum - out.measure) <= tolerance_ * out.measure;
    r.headline["volume sum / measure"] = out.sum / out.measure;
  }

  std::string page(const Registries&, const ReportSection& section, const std::string& title,
                   const std::filesystem::path&, bool) const override {
    return fmt::format("# {}\n\n{}", title, table(section));
  }

  std::string summary(const Problem&, const ReportSection& section) const override {
    return table(section);
  }

  std::string page_contents(bool) const override { return "every case's volume sum"; }
  MeasuredErrors measured_errors() const override {
    return {{}, false, "a volume check computes no field error"};
  }

  int print_case(const CaseResult& r, std::ostream& out) const override {
    const auto& v = r.data<VolumeCheckData>();
    out << fmt::format("volumes   sum {:.12g}, domain measure {:.12g}: {}\n", v.sum, v.measure,
                       v.passed ? "passed" : "failed");
    return v.passed ? 0 : 1;
  }

 private:
  static std::string table(const ReportSection& section) {
    MarkdownTable t({"study", "nodes", "Σ V / measure", "verdict"}, {'l', 'r', 'r', 'l'});
    for (const auto& s : section.studies)
      for (const auto& c : s.cases) {
        const auto& v = c.data<VolumeCheckData>();
        t.add_row({s.label, std::to_string(c.spec.nodes), fmt::format("{:.12f}", v.sum / v.measure),
                   v.passed ? "passed" : "failed"});
      }
    return t.str() + "\n";
  }

  double tolerance_;
};

}  // namespace

void register_volume_check(AnalysisRegistry& r) {
  r.add("volume-check", "the particle volumes' sum against the domain's measure (example)",
        {ParamSpec::positive("tolerance", 1e-12, "relative tolerance of the sum")},
        [](const Params& p) { return std::make_unique<VolumeCheck>(p); });
}

}  // namespace mfv
