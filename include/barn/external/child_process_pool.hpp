#pragma once
/// Child processes of one command kept between episodes, so a controller program starts once
/// per worker thread instead of once per episode.
///
/// A controller takes a process at reset and gives it back when it is destroyed; at most as many
/// processes exist as episodes run at once (one per worker thread). Only healthy processes are
/// given back: one that failed is stopped by its controller and a fresh one replaces it.

#include <memory>
#include <mutex>
#include <vector>

#include "barn/external/child_process.hpp"

namespace barn::external {

class ChildProcessPool {
 public:
  explicit ChildProcessPool(ChildCommand command) : command_(std::move(command)) {}
  /// Closes the idle processes' stdin, gives them kExitGrace to exit by themselves (a program
  /// may write logs at the end), then stops the rest.
  ~ChildProcessPool();
  ChildProcessPool(const ChildProcessPool&) = delete;
  ChildProcessPool& operator=(const ChildProcessPool&) = delete;

  /// An idle process, or a new one (ChildProcessError if it cannot be started). Thread-safe.
  std::unique_ptr<ChildProcess> take();
  /// Returns a healthy process, waiting for its next reset. Thread-safe.
  void giveBack(std::unique_ptr<ChildProcess> process);

  const ChildCommand& command() const { return command_; }

  static constexpr std::chrono::milliseconds kExitGrace{1000};

 private:
  ChildCommand command_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<ChildProcess>> idle_;
};

}  // namespace barn::external
