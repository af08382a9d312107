/// VTK files of a static solve's case: its particles and sampled solution (reports/vtk.hpp
/// writes them).
#pragma once
#include <filesystem>

#include "analyses/case.hpp"

namespace mfv {

/// One vertex per particle at (x, 0, 0) with point data "u_h", "u_exact", "error"
/// (u_h - u_exact), "du_h", "du_exact", "du_error", "coefficient", "volume", and field
/// data "h" and "nodes". A field left empty in the case's fields is left out (its differences
/// too); one of another length than x throws std::invalid_argument naming it.
/// Written atomically (temporary file, then rename); throws std::runtime_error naming the
/// path if VTK cannot write it.
void write_case_vtp(const std::filesystem::path& path, const CaseResult& r);

/// The dense sampling fields.sx as one polyline with point data "u_h", "u_exact", "error",
/// "du_h", "du_exact", "du_error", and the same field data. Throws std::invalid_argument if
/// there is no sampling (fewer than 2 points) or its arrays differ in length.
void write_line_vtp(const std::filesystem::path& path, const CaseResult& r);

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

}  // namespace mfv
