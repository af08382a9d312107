/// Markdown helpers for reports: aligned tables and number formatting that reads well raw.
#pragma once
#include <string>
#include <vector>

namespace mfv {

/// A GitHub-flavoured Markdown table whose columns are padded so the raw text lines up too
/// (widths count UTF-8 code points, so "–" and "×" take one column).
class MarkdownTable {
 public:
  /// `align` holds 'l', 'r' or 'c' per column; empty means all left. Throws
  /// std::invalid_argument if its size differs from the header's or a letter is unknown.
  explicit MarkdownTable(std::vector<std::string> header, std::vector<char> align = {});

  /// Cells are escaped ('|' becomes "\|", line breaks become spaces). Throws
  /// std::invalid_argument if the number of cells differs from the header's.
  void add_row(std::vector<std::string> cells);

  std::size_t rows() const { return rows_.size(); }

  /// Header, delimiter row and rows, each line ending in '\n'.
  std::string str() const;

 private:
  std::vector<std::string> header_;
  std::vector<char> align_;
  std::vector<std::vector<std::string>> rows_;
};

/// Scientific notation with `digits` after the point: "1.234e-03". NaN gives "–" (en dash,
/// "no value"), infinities "inf" / "-inf".
std::string fmt_sci(double v, int digits = 3);

/// Fixed notation with `decimals` after the point: "0.25". NaN gives "–".
std::string fmt_fix(double v, int decimals);

/// A convergence rate with 2 decimals: "2.01". NaN (too few resolutions) gives "–".
std::string fmt_rate(double v);

/// Rates joined by ", " ("1.96, 1.99, 2.00"); "–" for none.
std::string fmt_rates(const std::vector<double>& v);

/// A duration for people: "0.012 s", "3.4 s", "2 min 05 s", "1 h 02 min". Negative or NaN
/// gives "–".
std::string fmt_seconds(double s);

/// The current UTC time in a strftime format, e.g. "%Y-%m-%d %H:%M:%S UTC" for reports or
/// "%Y-%m-%dT%H:%M:%SZ" (ISO 8601) for files machines read.
std::string utc_now(const char* strftime_format);

/// A CSV field with RFC 4180 quoting, only where needed, so plain names stay plain for awk
/// and gnuplot.
std::string csv_field(const std::string& s);

}  // namespace mfv
