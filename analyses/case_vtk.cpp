#include "analyses/case_vtk.hpp"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "reports/vtk.hpp"

namespace mfv {

namespace fs = std::filesystem;

namespace {

/// Case-wide values, so a file opened on its own still says which resolution it shows.
void add_case_fields(VtpFile& f, const CaseResult& r) {
  f.field("h", r.h);
  f.field("nodes", r.spec.nodes);
}

Eigen::MatrixXd row(const Eigen::VectorXd& x) { return x.transpose(); }

}  // namespace

void write_particles_vtp(const fs::path& path, const CaseResult& r) {
  const CaseFields& f = r.data<StaticSolveData>().fields;
  if (f.points.size() == 0)
    throw std::invalid_argument(fmt::format("cannot write '{}': the case has no 2D particle "
                                            "fields",
                                            path.string()));
  VtpFile file(f.points, VtpFile::Topology::vertices, path);
  file.with_error("displacement", f.disp_h, f.disp_exact);
  file.with_error("stress", f.stress_h, f.stress_exact, true);
  file.scalars("volume", f.volume);
  add_case_fields(file, r);
  file.write();
}

void write_quadrature_vtp(const fs::path& path, const CaseResult& r) {
  const CaseFields& f = r.data<StaticSolveData>().fields;
  if (f.q_points.size() == 0)
    throw std::invalid_argument(fmt::format("cannot write '{}': the case has no quadrature "
                                            "fields",
                                            path.string()));
  VtpFile file(f.q_points, VtpFile::Topology::vertices, path);
  file.with_error("stress", f.q_stress_h, f.q_stress_exact, true);
  Eigen::VectorXd is_particle = Eigen::VectorXd::Zero(f.q_points.cols());
  const Eigen::Index np =
      r.quadrature_kind == "gauss-cells" ? 0 : std::min<Eigen::Index>(r.particles, f.q_points.cols());
  is_particle.head(np).setOnes();
  file.scalars("is_particle", is_particle);
  add_case_fields(file, r);
  file.write();
}

void write_case_vtp(const fs::path& path, const CaseResult& r) {
  const CaseFields& f = r.data<StaticSolveData>().fields;
  VtpFile file(row(f.x), VtpFile::Topology::vertices, path);
  file.scalars("u_h", f.u_h);
  file.scalars("u_exact", f.u_exact);
  file.difference("error", f.u_h, f.u_exact);
  file.scalars("du_h", f.du_h);
  file.scalars("du_exact", f.du_exact);
  file.difference("du_error", f.du_h, f.du_exact);
  file.scalars("coefficient", f.coefficient);
  file.scalars("volume", f.volume);
  if (f.u_h.size() != 0) file.active_scalars("u_h");
  add_case_fields(file, r);
  file.write();
}

void write_line_vtp(const fs::path& path, const CaseResult& r) {
  const CaseFields& f = r.data<StaticSolveData>().fields;
  if (f.sx.size() < 2)
    throw std::invalid_argument(fmt::format(
        "cannot write '{}': the case has no dense sampling (sx has {} points)", path.string(),
        f.sx.size()));
  VtpFile file(row(f.sx), VtpFile::Topology::polyline, path);
  file.scalars("u_h", f.su_h);
  file.scalars("u_exact", f.su);
  file.difference("error", f.su_h, f.su);
  file.scalars("du_h", f.sdu_h);
  file.scalars("du_exact", f.sdu);
  file.difference("du_error", f.sdu_h, f.sdu);
  if (f.su_h.size() != 0) file.active_scalars("u_h");
  add_case_fields(file, r);
  file.write();
}

}  // namespace mfv
