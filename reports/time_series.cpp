#include "reports/time_series.hpp"

#include <cmath>
#include <iterator>
#include <set>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <vtkCellArray.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include "reports/atomic.hpp"
#include "reports/markdown.hpp"
#include "reports/vtk.hpp"

namespace mfv {

namespace fs = std::filesystem;

namespace {

vtkIdType to_id(Eigen::Index i) { return static_cast<vtkIdType>(i); }

/// Everything that can be wrong with a frame, checked before VTK sees it, so a bad frame
/// throws with the array's name instead of writing a file ParaView cannot read.
void check_frame(const ParticleFrame& f, const fs::path& path) {
  if (!std::isfinite(f.time))
    throw std::invalid_argument(fmt::format("cannot write '{}': the frame time is {}; pass a "
                                            "finite time",
                                            path.string(), f.time));
  if (f.x.rows() < 1 || f.x.rows() > 3)
    throw std::invalid_argument(fmt::format("cannot write '{}': positions x have {} rows; pass "
                                            "a dim × N matrix with dim 1, 2 or 3",
                                            path.string(), f.x.rows()));
  std::set<std::string> names;
  for (const auto& [name, m] : f.point_data) {
    if (name.empty())
      throw std::invalid_argument(fmt::format("cannot write '{}': a point_data array has no "
                                              "name; name every array",
                                              path.string()));
    if (!names.insert(name).second)
      throw std::invalid_argument(fmt::format("cannot write '{}': point_data '{}' appears twice; "
                                              "give each array its own name",
                                              path.string(), name));
    if (m.cols() != f.x.cols())
      throw std::invalid_argument(fmt::format("cannot write '{}': point_data '{}' has {} columns "
                                              "for {} particles (x.cols()); pass one column per "
                                              "particle",
                                              path.string(), name, m.cols(), f.x.cols()));
    if (m.rows() < 1 || m.rows() > 3)
      throw std::invalid_argument(fmt::format("cannot write '{}': point_data '{}' has {} rows; "
                                              "pass 1 (scalar), 2 (vector) or 3 (3-vector or "
                                              "Voigt stress) components",
                                              path.string(), name, m.rows()));
  }
}

/// One vertex cell per particle, built from flat offset/connectivity arrays rather than a
/// cell at a time: frames of 40,000 particles are written hundreds of times in a run.
void set_vertices(vtkUnstructuredGrid* grid, const Eigen::MatrixXd& x) {
  const vtkIdType n = to_id(x.cols());
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  for (vtkIdType i = 0; i < n; ++i)
    points->SetPoint(i, x(0, i), x.rows() > 1 ? x(1, i) : 0.0, x.rows() > 2 ? x(2, i) : 0.0);
  grid->SetPoints(points);

  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(n + 1);
  connectivity->SetNumberOfValues(n);
  for (vtkIdType i = 0; i < n; ++i) {
    offsets->SetValue(i, i);
    connectivity->SetValue(i, i);
  }
  offsets->SetValue(n, n);
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, connectivity);
  grid->SetCells(VTK_VERTEX, cells);
}

void add_array(vtkUnstructuredGrid* grid, const std::string& name, const Eigen::MatrixXd& data) {
  // Voigt stresses become ParaView's symmetric tensors (XX, YY, ZZ, XY, YZ, XZ), so its
  // tensor filters (eigenvectors, glyphs) read them; other arrays of two components become
  // three (z = 0): Warp By Vector wants 3-vectors.
  const bool tensor = data.rows() == 3 && name.find("stress") != std::string::npos;
  const Eigen::MatrixXd m = tensor ? stress_tensor(data) : data;
  const int width = tensor ? 6 : m.rows() == 1 ? 1 : 3;
  vtkNew<vtkDoubleArray> a;
  a->SetName(name.c_str());
  a->SetNumberOfComponents(width);
  a->SetNumberOfTuples(to_id(m.cols()));
  for (Eigen::Index i = 0; i < m.cols(); ++i)
    for (int c = 0; c < width; ++c)
      a->SetComponent(to_id(i), c, c < m.rows() ? m(c, i) : 0.0);
  if (tensor)
    for (int c = 0; c < 6; ++c) a->SetComponentName(c, kTensorComponents[c]);
  grid->GetPointData()->AddArray(a);
}

/// The same temporary-file-then-rename as reports/vtk.cpp: VTK insists on a file name.
void write_grid(const fs::path& path, vtkUnstructuredGrid* grid) {
  PendingFile temp(path);
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetFileName(temp.path().c_str());
  writer->SetInputData(grid);
  writer->SetDataModeToAppended();
  if (writer->Write() == 0)
    throw std::runtime_error(
        fmt::format("cannot write '{}': the VTK XML writer failed ({}); check that the "
                    "directory is writable and the disk not full",
                    path.string(), vtkErrorCode::GetStringFromErrorCode(writer->GetErrorCode())));
  temp.commit();
}

}  // namespace

VtuSeriesWriter::VtuSeriesWriter(fs::path dir, std::string base)
    : dir_(std::move(dir)), base_(std::move(base)) {
  if (base_.empty() || base_.find('/') != std::string::npos)
    throw std::invalid_argument(fmt::format("VtuSeriesWriter: base name '{}' must be a non-empty "
                                            "file name without '/'; put directories in dir",
                                            base_));
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec)
    throw std::runtime_error(fmt::format("cannot create the time-series directory '{}': {}",
                                         dir_.string(), ec.message()));
}

VtuSeriesWriter::~VtuSeriesWriter() {
  if (pvd_current_) return;
  try {
    finish();
  } catch (...) {
    // A destructor must not throw; the .vtu files are on disk regardless.
  }
}

fs::path VtuSeriesWriter::pvd_path() const { return dir_ / (base_ + ".pvd"); }

void VtuSeriesWriter::write(const ParticleFrame& frame) {
  const bool replace = !entries_.empty() && frame.time == entries_.back().first;
  const std::string file =
      replace ? entries_.back().second : fmt::format("{}_{:04d}.vtu", base_, entries_.size());
  const fs::path path = dir_ / file;
  if (!entries_.empty() && frame.time < entries_.back().first)
    throw std::invalid_argument(fmt::format("cannot write '{}': frame time {} is before the "
                                            "previous frame's {}; write frames in time order",
                                            path.string(), frame.time, entries_.back().first));
  check_frame(frame, path);

  vtkNew<vtkUnstructuredGrid> grid;
  set_vertices(grid, frame.x);
  for (const auto& [name, m] : frame.point_data) add_array(grid, name, m);
  vtkNew<vtkDoubleArray> time;  // the name ParaView reads as a dataset's own time
  time->SetName("TimeValue");
  time->InsertNextValue(frame.time);
  grid->GetFieldData()->AddArray(time);
  write_grid(path, grid);

  if (!replace) entries_.emplace_back(frame.time, file);
  pvd_current_ = false;
}

void VtuSeriesWriter::finish() {
  write_pvd(pvd_path(), entries_);
  pvd_current_ = true;
}

// ---------------------------------------------------------------- time histories

void TimeHistory::add(const std::vector<double>& row) {
  if (columns.empty())
    throw std::invalid_argument("TimeHistory::add: the history has no columns; set columns "
                                "(\"time\" first) before adding rows");
  if (row.size() != columns.size())
    throw std::invalid_argument(fmt::format("TimeHistory::add: a row of {} values for {} "
                                            "columns ({}); pass one value per column",
                                            row.size(), columns.size(),
                                            fmt::join(columns, ", ")));
  rows.push_back(row);
}

const std::vector<double> TimeHistory::column(const std::string& name) const {
  std::size_t c = 0;
  while (c < columns.size() && columns[c] != name) ++c;
  if (c == columns.size())
    throw std::invalid_argument(
        fmt::format("TimeHistory: no column '{}'; valid names: {}", name,
                    columns.empty() ? std::string("(none)")
                                    : fmt::format("{}", fmt::join(columns, ", "))));
  std::vector<double> out;
  out.reserve(rows.size());
  for (const auto& row : rows) out.push_back(c < row.size() ? row[c] : std::nan(""));
  return out;
}

void write_history_csv(const fs::path& path, const TimeHistory& h) {
  if (h.columns.empty())
    throw std::invalid_argument(fmt::format("cannot write '{}': the history has no columns",
                                            path.string()));
  std::string text;
  for (std::size_t c = 0; c < h.columns.size(); ++c) {
    if (c) text += ',';
    text += csv_field(h.columns[c]);
  }
  text += '\n';
  for (std::size_t r = 0; r < h.rows.size(); ++r) {
    const auto& row = h.rows[r];
    // rows is public, so a row may have bypassed add()'s check.
    if (row.size() != h.columns.size())
      throw std::invalid_argument(fmt::format("cannot write '{}': row {} has {} values for {} "
                                              "columns; add rows with TimeHistory::add",
                                              path.string(), r, row.size(), h.columns.size()));
    for (std::size_t c = 0; c < row.size(); ++c)
      fmt::format_to(std::back_inserter(text), "{}{:.9g}", c ? "," : "", row[c]);
    text += '\n';
  }
  write_file_atomic(path, text);
}

PlotSpec history_plot(const TimeHistory& h, const std::vector<std::string>& columns,
                      const std::string& title, const std::string& ylabel,
                      const std::string& xlabel) {
  PlotSpec spec;
  spec.title = title;
  spec.xlabel = xlabel;
  spec.ylabel = ylabel;
  spec.style = "lines";  // computed curves get a marker every tenth of their samples
  spec.mark_off_scale = false;  // one run's columns are different quantities
  const std::vector<double> t = h.column("time");
  std::vector<std::string> names = columns;
  if (names.empty())
    for (const auto& c : h.columns)
      if (c != "time") names.push_back(c);
  for (const auto& name : names) {
    Series s{name, t, h.column(name)};
    if (name.starts_with("exact ") || name.ends_with(" exact") || name.starts_with("1D "))
      s.role = SeriesRole::reference;
    spec.series.push_back(std::move(s));
  }
  return spec;
}

}  // namespace mfv
