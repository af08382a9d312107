#include "reports/atomic.hpp"

#include <cerrno>
#include <stdexcept>
#include <system_error>

#include <fcntl.h>
#include <unistd.h>

#include <fmt/format.h>

namespace mfv {

namespace fs = std::filesystem;

namespace {

std::string errno_text(int err) { return std::generic_category().message(err); }

/// Closes a descriptor on every path out of write_file_atomic, including exceptions.
class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }
  /// Closes now and returns the error, because close() can report a failed write-back.
  int close() {
    const int rc = ::close(fd_);
    fd_ = -1;
    return rc == 0 ? 0 : errno;
  }

 private:
  int fd_;
};

}  // namespace

PendingFile::PendingFile(fs::path target, std::string_view tag) : target_(std::move(target)) {
  if (!target_.has_filename())
    throw std::runtime_error(fmt::format("cannot write '{}': the path names no file",
                                         target_.string()));
  const std::string stem = fmt::format("{}.{}-{}-", target_.string(), tag, ::getpid());
  // O_EXCL makes the name ours alone; a clash (another thread, or a stale file left by a
  // crashed process with a recycled pid) just moves on to the next number.
  for (int n = 0; n < 10000; ++n) {
    fs::path candidate = stem + std::to_string(n);
    const int fd = ::open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      temp_ = std::move(candidate);
      return;
    }
    if (errno != EEXIST)
      throw std::runtime_error(fmt::format("cannot create a temporary file for '{}': {}",
                                           target_.string(), errno_text(errno)));
  }
  throw std::runtime_error(fmt::format(
      "cannot create a temporary file for '{}': too many stale '{}*' files", target_.string(),
      stem));
}

PendingFile::~PendingFile() {
  if (!committed_) {
    std::error_code ignored;
    fs::remove(temp_, ignored);
  }
}

void PendingFile::commit() {
  std::error_code ec;
  fs::rename(temp_, target_, ec);
  if (ec)
    throw std::runtime_error(fmt::format("cannot move '{}' into place as '{}': {}",
                                         temp_.string(), target_.string(), ec.message()));
  committed_ = true;
}

void write_file_atomic(const fs::path& path, std::string_view content) {
  PendingFile temp(path);
  const auto fail = [&](int err) {
    return std::runtime_error(fmt::format("cannot write '{}': {}", path.string(), errno_text(err)));
  };
  FileDescriptor fd(::open(temp.path().c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC));
  if (fd.get() < 0) throw fail(errno);
  const char* data = content.data();
  std::size_t left = content.size();
  while (left > 0) {
    const ssize_t n = ::write(fd.get(), data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw fail(errno);
    }
    data += n;
    left -= static_cast<std::size_t>(n);
  }
  // Without fsync a crash shortly after the rename can leave an empty file on some
  // filesystems, which is exactly the half-written report this function exists to prevent.
  if (::fsync(fd.get()) != 0) throw fail(errno);
  if (const int err = fd.close(); err != 0) throw fail(err);
  temp.commit();
}

StagedDirectory::StagedDirectory(fs::path target) : target_(std::move(target)) {
  if (!target_.has_filename()) target_ = target_.parent_path();  // "reports/run/"
  const fs::path parent = target_.parent_path();
  const std::string name = target_.filename().string();
  staging_ = parent / fmt::format(".{}.staging-{}", name, ::getpid());
  old_ = parent / fmt::format(".{}.old-{}", name, ::getpid());
  fs::remove_all(staging_);
  if (!parent.empty()) fs::create_directories(parent);
  fs::create_directory(staging_);
}

StagedDirectory::~StagedDirectory() {
  if (!committed_) {
    std::error_code ignored;
    fs::remove_all(staging_, ignored);
  }
}

void StagedDirectory::commit() {
  if (committed_)
    throw std::logic_error(fmt::format("'{}' was already committed", target_.string()));
  std::error_code ec;
  const bool had_previous = fs::exists(fs::symlink_status(target_));
  if (had_previous) {
    fs::remove_all(old_, ec);  // left over from a crashed run with the same pid
    fs::rename(target_, old_, ec);
    if (ec)
      throw std::runtime_error(fmt::format("cannot move the previous '{}' aside: {}",
                                           target_.string(), ec.message()));
  }
  fs::rename(staging_, target_, ec);
  if (ec) {
    std::string restored;
    if (had_previous) {
      std::error_code back;
      fs::rename(old_, target_, back);
      if (back) restored = fmt::format("; the previous report is left in '{}'", old_.string());
    }
    throw std::runtime_error(fmt::format("cannot move '{}' into place as '{}': {}{}",
                                         staging_.string(), target_.string(), ec.message(),
                                         restored));
  }
  committed_ = true;
  // The new report is in place; a leftover old copy is hidden and replaced next time.
  if (had_previous) fs::remove_all(old_, ec);
}

}  // namespace mfv
