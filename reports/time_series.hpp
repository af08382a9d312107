/// Output of time-dependent runs: ParaView particle time series, time-history CSVs and plots.
#pragma once
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "reports/plot.hpp"

namespace mfv {

/// One snapshot of particle data for a VTK time series.
struct ParticleFrame {
  double time = 0;
  /// dim × N current positions, dim 1, 2 or 3; written as 3D points (y = z = 0 in 1D, z = 0
  /// in 2D).
  Eigen::MatrixXd x;
  /// (name, components × N) with 1 to 3 rows. One row is a scalar; two rows are a vector
  /// padded with z = 0 to three components so ParaView can warp by it; three rows are kept
  /// as they are, except an array whose name contains "stress": that is Voigt xx, yy, xy and
  /// is written as a 6-component symmetric tensor (XX, YY, ZZ, XY, YZ, XZ, named;
  /// reports/vtk.hpp stress_tensor).
  std::vector<std::pair<std::string, Eigen::MatrixXd>> point_data;
};

/// Writes a ParaView time series: `<dir>/<base>_NNNN.vtu` (a vtkUnstructuredGrid of one
/// VTK_VERTEX cell per particle, with field data "TimeValue" so a file opened on its own
/// knows its time) and `<dir>/<base>.pvd` listing them with their times. Every file is
/// written atomically (temporary file, then rename), so a crash never leaves a half file.
/// `dir` is created if missing. Not thread-safe.
class VtuSeriesWriter {
 public:
  /// Throws std::invalid_argument if `base` is empty or contains a '/', std::runtime_error
  /// naming `dir` if it cannot be created.
  VtuSeriesWriter(std::filesystem::path dir, std::string base);
  VtuSeriesWriter(const VtuSeriesWriter&) = delete;
  VtuSeriesWriter& operator=(const VtuSeriesWriter&) = delete;
  /// Writes the .pvd if frames were written since the last finish(), so a run that dies
  /// by an exception still leaves a series ParaView can open (errors are swallowed here).
  ~VtuSeriesWriter();

  /// Writes the next file. A frame at the same time as the previous one replaces it (an
  /// engine that writes every k steps and at the end may hit the same time twice); an
  /// earlier time throws std::invalid_argument. Also throws std::invalid_argument naming
  /// the path and the array for an x with 0 or more than 3 rows, a point_data array whose
  /// column count differs from x.cols(), one with 0 or more than 3 rows, an empty or
  /// repeated name, or a time that is not finite; std::runtime_error naming the path if
  /// VTK cannot write it. Nothing is written when it throws.
  void write(const ParticleFrame& frame);

  /// Writes `<dir>/<base>.pvd` listing every frame so far; safe to call repeatedly (each
  /// call rewrites it atomically), e.g. after every frame to watch a run in ParaView.
  void finish();

  /// (time, file name relative to dir) of every frame written, in order.
  const std::vector<std::pair<double, std::string>>& entries() const { return entries_; }

  const std::filesystem::path& dir() const { return dir_; }
  std::filesystem::path pvd_path() const;

 private:
  std::filesystem::path dir_;
  std::string base_;
  std::vector<std::pair<double, std::string>> entries_;
  bool pvd_current_ = true;  ///< the .pvd on disk lists every entry (nothing to list yet)
};

/// Time histories: named columns sampled at times (energy balance, probe velocities).
/// An aggregate: `TimeHistory h{{"time", "kinetic", "internal"}, {}};`.
struct TimeHistory {
  std::vector<std::string> columns;  ///< the first column is "time"
  std::vector<std::vector<double>> rows;

  /// Appends a row; throws std::invalid_argument if its size differs from columns.size()
  /// (or there are no columns yet).
  void add(const std::vector<double>& row);

  /// The values of column `name`, one per row; throws std::invalid_argument listing the
  /// valid names if there is no such column.
  const std::vector<double> column(const std::string& name) const;
};

/// Writes `h` as CSV: a header line of the column names (quoted if they contain a comma or
/// a quote), then one line per row with values as %.9g (enough to tell doubles apart in a
/// plot, not to round-trip them). Atomic. Throws std::invalid_argument naming the path if
/// a row's size differs from the columns', std::runtime_error if the file cannot be written.
void write_history_csv(const std::filesystem::path& path, const TimeHistory& h);

/// A line plot of `columns` against the "time" column (every other column if `columns` is
/// empty), one series per column labelled by its name; x label `xlabel` (give its unit).
/// A column named as a reference ("exact …", "… exact", "1D …": a closed form or a 1D
/// reference solution) is drawn as one (SeriesRole::reference).
/// Throws std::invalid_argument (from TimeHistory::column) for an unknown name. Draw it with
/// write_svg_plot.
PlotSpec history_plot(const TimeHistory& h, const std::vector<std::string>& columns,
                      const std::string& title, const std::string& ylabel,
                      const std::string& xlabel = "time t (s)");

}  // namespace mfv
