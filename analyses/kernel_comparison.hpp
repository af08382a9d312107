/// The report's kernel comparison (kernels.md, issue 29 item 5): the same problem and method
/// run with different kernels, side by side, so a reader sees what the choice of W does
/// without collecting rows from every problem page.
#pragma once
#include <string>
#include <vector>

#include "analyses/report_section.hpp"
#include "reports/convergence_table.hpp"

namespace mfv {

/// One comparison: a problem section and a method, with the studies that differ only in the
/// kernel and its support (`kernel`, `dmax`, `radius`, `kernel-<name>`), at least two kernels.
struct KernelComparison {
  std::string problem;  ///< the section's problem and its parameters ("rod-pulse frames=0")
  std::string method;   ///< the method and the parameters the studies share
  TextTable table;      ///< a row per study, best error first
};

/// Every comparison the sections hold, in section order.
std::vector<KernelComparison> kernel_comparisons(const std::vector<ReportSection>& sections);

/// The page of `comparisons` (kernel_comparisons): an explanation, then each table; empty
/// when there is none.
std::string kernel_comparison_page(const std::vector<KernelComparison>& comparisons);

}  // namespace mfv
