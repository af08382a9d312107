#include "reports/vtk.hpp"

#include <map>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkFieldData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataWriter.h>

#include "reports/atomic.hpp"

namespace mfv {

namespace fs = std::filesystem;

namespace {

vtkIdType to_id(Eigen::Index i) { return static_cast<vtkIdType>(i); }

/// Points on the x axis: the cases are 1D, and ParaView still wants three coordinates.
void set_points(vtkPolyData* pd, const Eigen::VectorXd& x) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(to_id(x.size()));
  for (Eigen::Index i = 0; i < x.size(); ++i) points->SetPoint(to_id(i), x[i], 0.0, 0.0);
  pd->SetPoints(points);
}

/// Adds `v` as point data `name` if it has one value per point; an empty vector (a field
/// the case did not compute) is skipped, any other length is a caller's bug.
void add_point_array(vtkPolyData* pd, const char* name, const Eigen::VectorXd& v,
                     const fs::path& path) {
  if (v.size() == 0) return;
  if (to_id(v.size()) != pd->GetNumberOfPoints())
    throw std::invalid_argument(fmt::format("cannot write '{}': field '{}' has {} values for {} points",
                                            path.string(), name, v.size(),
                                            pd->GetNumberOfPoints()));
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfComponents(1);
  a->SetNumberOfTuples(to_id(v.size()));
  for (Eigen::Index i = 0; i < v.size(); ++i) a->SetValue(to_id(i), v[i]);
  pd->GetPointData()->AddArray(a);
}

/// The difference of two fields, or nothing if either is missing.
Eigen::VectorXd difference(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  if (a.size() == 0 || b.size() == 0) return {};
  if (a.size() != b.size()) return {};  // not reached: both were checked when added
  return a - b;
}

/// VTK insists on a file name of its own, so it writes a temporary file that is renamed
/// over `path` only once Write() has succeeded.
void write_polydata(const fs::path& path, vtkPolyData* pd) {
  PendingFile temp(path);
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetFileName(temp.path().c_str());
  writer->SetInputData(pd);
  writer->SetDataModeToAppended();
  if (writer->Write() == 0)
    throw std::runtime_error(
        fmt::format("cannot write '{}': the VTK XML writer failed ({})", path.string(),
                    vtkErrorCode::GetStringFromErrorCode(writer->GetErrorCode())));
  temp.commit();
}

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

/// Points (x, y, 0) from a dim × n matrix.
void set_points_2d(vtkPolyData* pd, const Eigen::MatrixXd& x) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(to_id(x.cols()));
  for (Eigen::Index i = 0; i < x.cols(); ++i)
    points->SetPoint(to_id(i), x(0, i), x.rows() > 1 ? x(1, i) : 0.0, 0.0);
  pd->SetPoints(points);
  vtkNew<vtkCellArray> verts;
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    const vtkIdType id = to_id(i);
    verts->InsertNextCell(1, &id);
  }
  pd->SetVerts(verts);
}

/// Adds the columns of `m` (rows = components, padded to `width`) as a vector array.
void add_vector_array(vtkPolyData* pd, const char* name, const Eigen::MatrixXd& m, int width,
                      const fs::path& path) {
  if (m.size() == 0) return;
  if (to_id(m.cols()) != pd->GetNumberOfPoints())
    throw std::invalid_argument(fmt::format("cannot write '{}': field '{}' has {} columns for {} "
                                            "points",
                                            path.string(), name, m.cols(),
                                            pd->GetNumberOfPoints()));
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfComponents(width);
  a->SetNumberOfTuples(to_id(m.cols()));
  for (Eigen::Index i = 0; i < m.cols(); ++i)
    for (int c = 0; c < width; ++c)
      a->SetComponent(to_id(i), c, c < m.rows() ? m(c, i) : 0.0);
  pd->GetPointData()->AddArray(a);
}

/// Adds Voigt stresses as a symmetric tensor with ParaView's component names.
void add_tensor_array(vtkPolyData* pd, const char* name, const Eigen::MatrixXd& voigt,
                      const fs::path& path) {
  if (voigt.size() == 0) return;
  if (voigt.rows() != 3)
    throw std::invalid_argument(fmt::format("cannot write '{}': stress '{}' has {} rows, not the "
                                            "3 of Voigt xx, yy, xy",
                                            path.string(), name, voigt.rows()));
  add_vector_array(pd, name, stress_tensor(voigt), 6, path);
  vtkDataArray* a = pd->GetPointData()->GetArray(name);
  for (int c = 0; c < 6; ++c) a->SetComponentName(c, kTensorComponents[c]);
}

/// `name`, `name`_exact and `name`_error (computed - exact): 3-vectors, or with `tensor`
/// symmetric tensors.
void add_with_error(vtkPolyData* pd, const std::string& name, const Eigen::MatrixXd& computed,
                    const Eigen::MatrixXd& exact, const fs::path& path, bool tensor = false) {
  if (tensor) {
    add_tensor_array(pd, name.c_str(), computed, path);
    add_tensor_array(pd, (name + "_exact").c_str(), exact, path);
    if (computed.size() > 0 && computed.rows() == exact.rows() && computed.cols() == exact.cols())
      add_tensor_array(pd, (name + "_error").c_str(), computed - exact, path);
    return;
  }
  add_vector_array(pd, name.c_str(), computed, 3, path);
  add_vector_array(pd, (name + "_exact").c_str(), exact, 3, path);
  add_vector_array(pd, (name + "_error").c_str(), computed - exact, 3, path);
}

}  // namespace

Eigen::MatrixXd stress_tensor(const Eigen::MatrixXd& voigt) {
  if (voigt.rows() != 3)
    throw std::invalid_argument(fmt::format("stress_tensor: {} rows, not the 3 of Voigt xx, yy, xy",
                                            voigt.rows()));
  Eigen::MatrixXd t = Eigen::MatrixXd::Zero(6, voigt.cols());
  t.row(0) = voigt.row(0);  // XX
  t.row(1) = voigt.row(1);  // YY
  t.row(3) = voigt.row(2);  // XY
  return t;
}


struct VtpFile::Data {
  vtkSmartPointer<vtkPolyData> pd = vtkSmartPointer<vtkPolyData>::New();
  std::filesystem::path path;
};

VtpFile::VtpFile(const Eigen::MatrixXd& points, Topology topology, std::filesystem::path path)
    : data_(std::make_unique<Data>()) {
  data_->path = std::move(path);
  vtkPolyData* pd = data_->pd;
  const std::filesystem::path& file = data_->path;
  if (topology == Topology::polyline) {
    if (points.rows() != 1)
      throw std::invalid_argument(fmt::format("cannot write '{}': a polyline takes 1 × n points, not {} rows", file.string(), points.rows()));
    const Eigen::VectorXd x = points.row(0).transpose();
    set_points(pd, x);
    std::vector<vtkIdType> ids(static_cast<std::size_t>(x.size()));
    for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<vtkIdType>(i);
    vtkNew<vtkCellArray> lines;
    lines->InsertNextCell(to_id(x.size()), ids.data());  // one polyline
    pd->SetLines(lines);
  } else if (points.rows() == 1) {
    set_points(pd, points.row(0).transpose());
    vtkNew<vtkCellArray> verts;
    for (Eigen::Index i = 0; i < points.cols(); ++i) {
      const vtkIdType id = to_id(i);
      verts->InsertNextCell(1, &id);
    }
    pd->SetVerts(verts);
  } else {
    set_points_2d(pd, points);
  }
}

VtpFile::~VtpFile() = default;

void VtpFile::scalars(const std::string& name, const Eigen::VectorXd& v) {
  add_point_array(data_->pd, name.c_str(), v, data_->path);
}

void VtpFile::difference(const std::string& name, const Eigen::VectorXd& a,
                         const Eigen::VectorXd& b) {
  add_point_array(data_->pd, name.c_str(), mfv::difference(a, b), data_->path);
}

void VtpFile::vectors(const std::string& name, const Eigen::MatrixXd& m) {
  add_vector_array(data_->pd, name.c_str(), m, 3, data_->path);
}

void VtpFile::tensors(const std::string& name, const Eigen::MatrixXd& voigt) {
  add_tensor_array(data_->pd, name.c_str(), voigt, data_->path);
}

void VtpFile::with_error(const std::string& name, const Eigen::MatrixXd& computed,
                         const Eigen::MatrixXd& exact, bool tensor) {
  add_with_error(data_->pd, name, computed, exact, data_->path, tensor);
}

void VtpFile::active_scalars(const std::string& name) {
  data_->pd->GetPointData()->SetActiveScalars(name.c_str());
}

void VtpFile::field(const std::string& name, double value) {
  vtkNew<vtkDoubleArray> a;
  a->SetName(name.c_str());
  a->InsertNextValue(value);
  data_->pd->GetFieldData()->AddArray(a);
}

void VtpFile::field(const std::string& name, int value) {
  vtkNew<vtkIntArray> a;
  a->SetName(name.c_str());
  a->InsertNextValue(value);
  data_->pd->GetFieldData()->AddArray(a);
}

void VtpFile::write() { write_polydata(data_->path, data_->pd); }

void write_pvd(const fs::path& path, const std::vector<std::pair<double, std::string>>& entries) {
  std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n";
  std::map<double, int> parts;  // next part number per timestep
  for (const auto& [timestep, file] : entries) {
    const int part = parts[timestep]++;
    xml += fmt::format("    <DataSet timestep=\"{}\" group=\"\" part=\"{}\" file=\"{}\"/>\n",
                       timestep, part, xml_escape(file));
  }
  xml += "  </Collection>\n</VTKFile>\n";
  write_file_atomic(path, xml);
}

}  // namespace mfv
