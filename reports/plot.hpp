/// SVG plots drawn by gnuplot (found on PATH at run time).
#pragma once
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>


namespace mfv {

/// Whether an executable `gnuplot` is on PATH. Looked up afresh on every call, so a test
/// or a user changing PATH is honoured.
bool gnuplot_available();

/// Distinct colours before the line styles repeat with dashes.
inline constexpr int kPaletteSize = 20;

struct Series {
  std::string label;
  std::vector<double> x, y;  ///< same length
};

struct PlotSpec {
  std::string title, xlabel, ylabel;  ///< axis labels carry their units: "dt (s)"
  bool logx = false, logy = false;
  /// A linear y axis becomes logarithmic when every plotted y is positive and they span at
  /// least kAutoLogSpan (three decades): such data is a flat line on a linear axis.
  bool auto_logy = true;
  std::vector<Series> series;
  std::string style = "linespoints";  ///< or "lines", "points", "boxes" (a bar chart, y from 0)
  /// Category labels on the x axis at these x (a bar chart's methods); empty: numeric tics.
  std::vector<std::pair<double, std::string>> xtic_labels;
  /// Reference lines ∝ x^p on a log–log plot (convergence: p = 1, 2, …), dashed grey, each
  /// labelled "∝ h^p" in the legend and anchored at the geometric mean of the series' values
  /// at the largest x; ignored unless both axes are logarithmic.
  std::vector<int> reference_slopes;
  std::string reference_variable = "h";
};

/// The y-range ratio from which auto_logy switches to a log axis.
inline constexpr double kAutoLogSpan = 1e3;

/// Draws `spec` into `svg_path` with gnuplot (720×480, sans 11, wider and taller when the
/// legend, outside the plot area on the right, has many or long entries; a fixed palette of
/// kPaletteSize distinct colours, then dashed lines); the SVG appears atomically,
/// so a failed plot never replaces a good one. Points that are not finite, or not positive
/// on a log axis, are dropped; series left empty are skipped. Text is printed literally
/// (gnuplot's enhanced-text markup is off, so "u_h" is not a subscript).
/// Returns std::nullopt on success, else a one-line reason for the report: "gnuplot not
/// found: ...", "gnuplot failed: <its error message>", "nothing to plot: ...", or why a
/// file next to `svg_path` could not be written. Never throws (except std::bad_alloc): a
/// missing plot should not cost the rest of a report.
std::optional<std::string> write_svg_plot(const std::filesystem::path& svg_path,
                                          const PlotSpec& spec);

/// The gnuplot script write_svg_plot runs for `spec` (after the same filtering); empty when
/// nothing is left to plot. For tests and for reading what a plot will show.
std::string gnuplot_script(const PlotSpec& spec);

}  // namespace mfv
