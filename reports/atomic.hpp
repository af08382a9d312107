/// Atomic file and directory replacement: nothing half-written may replace a good report.
#pragma once
#include <filesystem>
#include <string>
#include <string_view>

namespace mfv {

/// Writes `content` to a temporary file next to `path`, flushes it to disk and renames it
/// over `path`, so readers (and a crash) see either the old or the new file, never a part.
/// On failure the temporary file is removed and std::runtime_error names the path and cause.
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

/// A uniquely named temporary file next to `target` (`<target>.<tag>-<pid>-<n>`), created
/// empty and exclusively, for writers that insist on a file name of their own (VTK,
/// gnuplot). commit() renames it over `target`; otherwise the destructor removes it.
/// Being in the same directory as the target keeps the rename atomic (same filesystem).
class PendingFile {
 public:
  /// Throws std::runtime_error naming `target` if the file cannot be created.
  explicit PendingFile(std::filesystem::path target, std::string_view tag = "tmp");
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;
  ~PendingFile();

  const std::filesystem::path& path() const { return temp_; }
  const std::filesystem::path& target() const { return target_; }

  /// Renames the temporary file over the target; throws std::runtime_error naming both.
  void commit();

 private:
  std::filesystem::path target_, temp_;
  bool committed_ = false;
};

/// Builds a whole report directory in `<parent>/.<name>.staging-<pid>` and, on commit(),
/// swaps it in for `<parent>/<name>`. A run that fails before commit() leaves the previous
/// report untouched: the destructor only removes the staging directory.
/// Two objects for the same target in one process would share the staging directory.
class StagedDirectory {
 public:
  /// Creates the staging directory afresh (and the parent if missing); throws
  /// std::filesystem::filesystem_error on failure.
  explicit StagedDirectory(std::filesystem::path target);
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;
  ~StagedDirectory();

  /// Where to write the report's files until commit().
  const std::filesystem::path& path() const { return staging_; }
  const std::filesystem::path& target() const { return target_; }
  bool committed() const { return committed_; }

  /// Moves an existing target aside to `<parent>/.<name>.old-<pid>`, renames the staging
  /// directory to the target and removes the old one. If the second rename fails the old
  /// directory is moved back and std::runtime_error is thrown.
  void commit();

 private:
  std::filesystem::path target_, staging_, old_;
  bool committed_ = false;
};

}  // namespace mfv
