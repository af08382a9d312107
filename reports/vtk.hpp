/// VTK XML files of particles and sampled fields (VtpFile), symmetric stress tensors in
/// ParaView's order, and ParaView collections (.pvd). Knows nothing of cases or problems.
#pragma once
#include <array>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <memory>

#include <Eigen/Dense>

namespace mfv {

/// The component names of a symmetric tensor in ParaView's 6-component order.
inline constexpr std::array<const char*, 6> kTensorComponents = {"XX", "YY", "ZZ",
                                                                 "XY", "YZ", "XZ"};

/// In-plane Voigt stresses (rows xx, yy, xy; N columns) as 6 × N symmetric tensors in
/// ParaView's order (XX, YY, ZZ, XY, YZ, XZ). The out-of-plane ZZ, YZ, XZ are written 0: exact
/// for plane stress and for the ν = 0 plane-strain rod (σ_zz = ν (σ_xx + σ_yy)), the 2D
/// problems the suite runs; the 2D models compute no σ_zz. Throws std::invalid_argument for
/// another row count.
Eigen::MatrixXd stress_tensor(const Eigen::MatrixXd& voigt);

/// One .vtp file of points (1 × n on the x axis, or 2 × n at (x, y, 0)) as vertices or, for
/// a 1D sampling, one polyline; point arrays and field data are added, then `write` writes
/// it atomically (temporary file, then rename; std::runtime_error naming the path if VTK
/// cannot). An empty array (a field not computed) is skipped; one of another length than the
/// points throws std::invalid_argument naming it.
class VtpFile {
 public:
  enum class Topology { vertices, polyline };
  VtpFile(const Eigen::MatrixXd& points, Topology topology, std::filesystem::path path);
  ~VtpFile();
  VtpFile(const VtpFile&) = delete;
  VtpFile& operator=(const VtpFile&) = delete;

  void scalars(const std::string& name, const Eigen::VectorXd& v);
  /// a − b, or nothing if either is missing.
  void difference(const std::string& name, const Eigen::VectorXd& a, const Eigen::VectorXd& b);
  /// Columns as 3-vectors (z = 0 pads 2D fields, so ParaView can warp by them).
  void vectors(const std::string& name, const Eigen::MatrixXd& m);
  /// Voigt stresses (3 × n) as symmetric tensors with component names XX … XZ.
  void tensors(const std::string& name, const Eigen::MatrixXd& voigt);
  /// `name`, `name`_exact and `name`_error (computed − exact), as vectors or tensors.
  void with_error(const std::string& name, const Eigen::MatrixXd& computed,
                  const Eigen::MatrixXd& exact, bool tensor = false);
  void active_scalars(const std::string& name);
  /// File-wide values, so a file opened on its own still says what it shows.
  void field(const std::string& name, double value);
  void field(const std::string& name, int value);
  void write();

 private:
  struct Data;  // the VTK poly data, kept out of this header
  std::unique_ptr<Data> data_;
};

/// A ParaView collection (.pvd) of (timestep, file) entries, file names relative to the
/// .pvd's directory. Entries sharing a timestep become parts 0, 1, ... of it, so a
/// particle file and a line file can be shown together. Written atomically.
void write_pvd(const std::filesystem::path& path,
               const std::vector<std::pair<double, std::string>>& entries);

}  // namespace mfv
