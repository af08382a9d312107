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

/// Case-wide values, so a file opened on its own still says which resolution it shows.
void add_field_data(vtkPolyData* pd, const CaseResult& r) {
  vtkNew<vtkDoubleArray> h;
  h->SetName("h");
  h->InsertNextValue(r.h);
  pd->GetFieldData()->AddArray(h);
  vtkNew<vtkIntArray> nodes;
  nodes->SetName("nodes");
  nodes->InsertNextValue(r.spec.nodes);
  pd->GetFieldData()->AddArray(nodes);
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

void write_particles_vtp(const fs::path& path, const CaseResult& r) {
  const CaseFields& f = r.fields;
  if (f.points.size() == 0)
    throw std::invalid_argument(fmt::format("cannot write '{}': the case has no 2D particle "
                                            "fields",
                                            path.string()));
  vtkNew<vtkPolyData> pd;
  set_points_2d(pd, f.points);
  add_with_error(pd, "displacement", f.disp_h, f.disp_exact, path);
  add_with_error(pd, "stress", f.stress_h, f.stress_exact, path, true);
  add_point_array(pd, "volume", f.volume, path);
  add_field_data(pd, r);
  write_polydata(path, pd);
}

void write_quadrature_vtp(const fs::path& path, const CaseResult& r) {
  const CaseFields& f = r.fields;
  if (f.q_points.size() == 0)
    throw std::invalid_argument(fmt::format("cannot write '{}': the case has no quadrature "
                                            "fields",
                                            path.string()));
  vtkNew<vtkPolyData> pd;
  set_points_2d(pd, f.q_points);
  add_with_error(pd, "stress", f.q_stress_h, f.q_stress_exact, path, true);
  Eigen::VectorXd is_particle = Eigen::VectorXd::Zero(f.q_points.cols());
  const Eigen::Index np =
      r.quadrature_kind == "gauss-cells" ? 0 : std::min<Eigen::Index>(r.particles, f.q_points.cols());
  is_particle.head(np).setOnes();
  add_point_array(pd, "is_particle", is_particle, path);
  add_field_data(pd, r);
  write_polydata(path, pd);
}

void write_case_vtp(const fs::path& path, const CaseResult& r) {
  const auto& f = r.fields;
  vtkNew<vtkPolyData> pd;
  set_points(pd, f.x);
  vtkNew<vtkCellArray> verts;
  for (Eigen::Index i = 0; i < f.x.size(); ++i) {
    const vtkIdType id = to_id(i);
    verts->InsertNextCell(1, &id);
  }
  pd->SetVerts(verts);
  add_point_array(pd, "u_h", f.u_h, path);
  add_point_array(pd, "u_exact", f.u_exact, path);
  add_point_array(pd, "error", difference(f.u_h, f.u_exact), path);
  add_point_array(pd, "du_h", f.du_h, path);
  add_point_array(pd, "du_exact", f.du_exact, path);
  add_point_array(pd, "du_error", difference(f.du_h, f.du_exact), path);
  add_point_array(pd, "coefficient", f.coefficient, path);
  add_point_array(pd, "volume", f.volume, path);
  if (f.u_h.size() != 0) pd->GetPointData()->SetActiveScalars("u_h");
  add_field_data(pd, r);
  write_polydata(path, pd);
}

void write_line_vtp(const fs::path& path, const CaseResult& r) {
  const auto& f = r.fields;
  if (f.sx.size() < 2)
    throw std::invalid_argument(fmt::format(
        "cannot write '{}': the case has no dense sampling (sx has {} points)", path.string(),
        f.sx.size()));
  vtkNew<vtkPolyData> pd;
  set_points(pd, f.sx);
  std::vector<vtkIdType> ids(static_cast<std::size_t>(f.sx.size()));
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<vtkIdType>(i);
  vtkNew<vtkCellArray> lines;
  lines->InsertNextCell(to_id(f.sx.size()), ids.data());  // one polyline
  pd->SetLines(lines);
  add_point_array(pd, "u_h", f.su_h, path);
  add_point_array(pd, "u_exact", f.su, path);
  add_point_array(pd, "error", difference(f.su_h, f.su), path);
  add_point_array(pd, "du_h", f.sdu_h, path);
  add_point_array(pd, "du_exact", f.sdu, path);
  add_point_array(pd, "du_error", difference(f.sdu_h, f.sdu), path);
  if (f.su_h.size() != 0) pd->GetPointData()->SetActiveScalars("u_h");
  add_field_data(pd, r);
  write_polydata(path, pd);
}

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
