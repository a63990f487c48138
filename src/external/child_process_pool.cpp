#include "barn/external/child_process_pool.hpp"

namespace barn::external {

ChildProcessPool::~ChildProcessPool() {
  // All processes get their end of file first and then share one grace period, so shutting
  // down N idle processes takes at most kExitGrace, not N times it.
  for (auto& process : idle_) process->closeInput();
  const auto deadline = ChildProcess::Clock::now() + kExitGrace;
  for (auto& process : idle_) process->waitForExit(deadline);
  idle_.clear();  // the destructors stop whatever is still running
}

std::unique_ptr<ChildProcess> ChildProcessPool::take() {
  {
    std::lock_guard lock(mutex_);
    if (!idle_.empty()) {
      std::unique_ptr<ChildProcess> process = std::move(idle_.back());
      idle_.pop_back();
      return process;
    }
  }
  return std::make_unique<ChildProcess>(command_);  // outside the lock: spawning takes a while
}

void ChildProcessPool::giveBack(std::unique_ptr<ChildProcess> process) {
  if (!process) return;
  std::lock_guard lock(mutex_);
  idle_.push_back(std::move(process));
}

}  // namespace barn::external
