/// What the stability and time-step analyses (dispersion, time-step, stretch-map,
/// crack-sweep) share: their result is figures, CSV tables and verdicts (FigureData), and
/// their page lists every case's verdicts and measured values beside the published ones.
#pragma once
#include <filesystem>
#include <string>

#include "analyses/analysis.hpp"

namespace mfv {

class FigureAnalysis : public Analysis {
 public:
  std::string page(const Registries& plugins, const ReportSection& section,
                   const std::string& title, const std::filesystem::path& dir,
                   bool vtk) const override;
  std::string summary(const Problem& problem, const ReportSection& section) const override;
  std::string page_contents(bool vtk) const override;
  /// None: a figure analysis computes no field error (its headline values are what it
  /// measures).
  MeasuredErrors measured_errors() const override {
    return {{}, false, "an analysis computes no field error"};
  }
  /// The setup, each verdict, the headline values and the CPU seconds.
  int print_case(const CaseResult& r, std::ostream& out) const override;
};

}  // namespace mfv
