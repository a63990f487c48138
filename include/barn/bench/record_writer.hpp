#pragma once
/// The one way barn writes a folder it owns: a run record, a sweep, a world set, an export.
///
///   RecordLock     an exclusive lock on the folder (flock on its `.barn.lock`)
///   RecordWriter   the lock, held for the writer's life, plus writes of whole sets of files
///                  (core::writeFilesAtomic: staged, flushed, committed, renamed into place)
///
/// Taking a writer first completes a set write that a kill interrupted in the folder and
/// removes what killed writers left there (core::finishInterruptedWrite), so every writer
/// finds the folder holding one whole version of its files. Readers refuse a folder whose
/// write was interrupted (core::checkNoInterruptedWrite) and never need the lock.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "barn/core/text_io.hpp"

namespace barn::bench {

/// An exclusive lock on a folder (flock on its `.barn.lock`), held while one process writes
/// it: a second writer of the same folder gets a clear error instead of silently losing one
/// run's results. Released when destroyed (or when the process dies).
class RecordLock {
 public:
  RecordLock() = default;
  /// Takes the lock on `dir` (created if missing). InputError naming the holder if another
  /// process has it; IoError if the lock file cannot be opened (a read-only folder).
  explicit RecordLock(const std::filesystem::path& dir);
  RecordLock(RecordLock&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  RecordLock& operator=(RecordLock&& other) noexcept;
  RecordLock(const RecordLock&) = delete;
  RecordLock& operator=(const RecordLock&) = delete;
  ~RecordLock();

  bool held() const { return fd_ >= 0; }

 private:
  int fd_ = -1;
};

/// A folder this process writes, locked for the writer's life (see the header comment).
class RecordWriter {
 public:
  RecordWriter() = default;
  /// Creates `dir` if missing, takes its lock (RecordLock's errors), then completes an
  /// interrupted write there and removes leftovers (core::finishInterruptedWrite).
  explicit RecordWriter(const std::filesystem::path& dir);

  const std::filesystem::path& dir() const { return dir_; }
  bool held() const { return lock_.held(); }
  /// True if taking the writer completed a set write that a kill had interrupted.
  bool completedInterruptedWrite() const { return completed_interrupted_; }

  /// Writes `files` (names relative to the folder) as one set and deletes `removals` with them
  /// (core::writeFilesAtomic); IoError on failure, the folder then unchanged.
  void write(const std::vector<core::FileContent>& files, const std::vector<std::string>& removals = {}) const;

 private:
  std::filesystem::path dir_;
  RecordLock lock_;
  bool completed_interrupted_ = false;
};

}  // namespace barn::bench
