#include "barn/bench/record_writer.hpp"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <stdexcept>
#include <sys/file.h>
#include <unistd.h>

#include "barn/core/errors.hpp"

namespace barn::bench {

namespace fs = std::filesystem;

RecordLock::RecordLock(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw core::IoError(dir.string() + ": cannot create folder: " + ec.message());
  const fs::path path = dir / ".barn.lock";
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw core::IoError(path.string() + ": cannot open: " + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    char holder[32] = {};
    const ssize_t n = ::pread(fd_, holder, sizeof(holder) - 1, 0);
    ::close(fd_);
    fd_ = -1;
    throw core::InputError(dir.string() + ": another barn process is writing this folder" +
                           (n > 0 ? " (pid " + std::string(holder, static_cast<std::size_t>(n)) + ")" : std::string()) +
                           "; wait for it or choose another --out");
  }
  const std::string pid = std::to_string(::getpid());
  if (::ftruncate(fd_, 0) == 0 && ::pwrite(fd_, pid.data(), pid.size(), 0) < 0) {
    // The pid is only for the message above; the lock holds without it.
  }
}

RecordLock& RecordLock::operator=(RecordLock&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

RecordLock::~RecordLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the flock
}

RecordWriter::RecordWriter(const fs::path& dir) : dir_(dir), lock_(dir) {
  completed_interrupted_ = core::finishInterruptedWrite(dir_);
}

void RecordWriter::write(const std::vector<core::FileContent>& files, const std::vector<std::string>& removals) const {
  if (!lock_.held()) throw std::logic_error("RecordWriter::write: no folder locked");
  core::writeFilesAtomic(dir_, files, removals);
}

}  // namespace barn::bench
