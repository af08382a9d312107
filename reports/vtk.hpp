/// VTK XML files of a case's particles and sampled solution, and ParaView collections of them.
#pragma once
#include <array>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "verify/case.hpp"

namespace mfv {

/// One vertex per particle at (x, 0, 0) with point data "u_h", "u_exact", "error"
/// (u_h - u_exact), "du_h", "du_exact", "du_error", "coefficient", "volume", and field
/// data "h" and "nodes". A field left empty in `r.fields` is left out (its differences
/// too); one of another length than x throws std::invalid_argument naming it.
/// Written atomically (temporary file, then rename); throws std::runtime_error naming the
/// path if VTK cannot write it.
void write_case_vtp(const std::filesystem::path& path, const CaseResult& r);

/// The dense sampling r.fields.sx as one polyline with point data "u_h", "u_exact", "error",
/// "du_h", "du_exact", "du_error", and the same field data. Throws std::invalid_argument if
/// there is no sampling (fewer than 2 points) or its arrays differ in length.
void write_line_vtp(const std::filesystem::path& path, const CaseResult& r);

/// The component names of a symmetric tensor in ParaView's 6-component order.
inline constexpr std::array<const char*, 6> kTensorComponents = {"XX", "YY", "ZZ",
                                                                 "XY", "YZ", "XZ"};

/// In-plane Voigt stresses (rows xx, yy, xy; N columns) as 6 × N symmetric tensors in
/// ParaView's order (XX, YY, ZZ, XY, YZ, XZ). The out-of-plane ZZ, YZ, XZ are written 0: exact
/// for plane stress and for the ν = 0 plane-strain rod (σ_zz = ν (σ_xx + σ_yy)), the 2D
/// problems the suite runs; the 2D models compute no σ_zz. Throws std::invalid_argument for
/// another row count.
Eigen::MatrixXd stress_tensor(const Eigen::MatrixXd& voigt);

/// 2D cases: one vertex per particle at (x, y, 0) with point data "displacement",
/// "displacement_exact", "displacement_error" (3-vectors, z = 0, so ParaView can warp by
/// them), "stress", "stress_exact", "stress_error" (symmetric tensors, stress_tensor, with
/// component names XX … XZ), "volume", and field data "h" and "nodes". Throws
/// std::invalid_argument if the case has no 2D fields.
void write_particles_vtp(const std::filesystem::path& path, const CaseResult& r);

/// 2D cases: one vertex per quadrature point of the method (particles first for nodal and
/// stress-point rules, then stress points or Gauss points) with "stress", "stress_exact",
/// "stress_error" (symmetric tensors as above) and "is_particle".
void write_quadrature_vtp(const std::filesystem::path& path, const CaseResult& r);

/// A ParaView collection (.pvd) of (timestep, file) entries, file names relative to the
/// .pvd's directory. Entries sharing a timestep become parts 0, 1, ... of it, so a
/// particle file and a line file can be shown together. Written atomically.
void write_pvd(const std::filesystem::path& path,
               const std::vector<std::pair<double, std::string>>& entries);

}  // namespace mfv
