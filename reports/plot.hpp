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

/// What a curve is, which decides how it is drawn, so exact and computed never look alike:
/// - computed: a colour of the palette, with markers (on dense curves every few points);
/// - reference: a closed form or exact solution, a black line without markers;
/// - data: published or measured points (a paper's table), black open circles;
/// - band: a reference that is a range, a grey shaded area between y and y_hi.
/// A reference, data or band series is drawn once and in every part of a split plot.
enum class SeriesRole { computed, reference, data, band };

struct Series {
  std::string label;
  std::vector<double> x, y;  ///< same length
  SeriesRole role = SeriesRole::computed;
  std::vector<double> y_hi = {};  ///< band only: the upper edge (y is the lower), same length as x
};

/// The most computed curves one plot shows: split_plot puts the rest in further parts.
inline constexpr std::size_t kMaxCurves = 8;

/// Off-scale curves: sorted by their largest |y|, the curves above the first gap of more than
/// kOffScaleFactor (from the curve below, and from every reference) are off scale, if they
/// are fewer than half (any number when a reference sets the scale). The axis is fitted to
/// the others, the curve is clipped at its edge and its legend entry says "off scale" with
/// its peak, so one blown-up run does not squeeze the rest into a strip. Linear y axes only
/// (a logarithmic one shows every size) and only with PlotSpec::mark_off_scale.
inline constexpr double kOffScaleFactor = 20;

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
  /// Mark a blown-up curve off scale (kOffScaleFactor) on a linear y axis. Off where the
  /// curves are different quantities (a run's probes), whose sizes differ by nature.
  bool mark_off_scale = true;
};

/// The y-range ratio from which auto_logy switches to a log axis.
inline constexpr double kAutoLogSpan = 1e3;

/// `spec` as plots of at most `max_curves` computed curves each, in order and of nearly equal
/// size, each with every reference, data and band series and a title ending "(part k of n)";
/// `spec` itself when it has at most `max_curves`. Throws std::invalid_argument for 0.
std::vector<PlotSpec> split_plot(const PlotSpec& spec, std::size_t max_curves = kMaxCurves);

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
