#pragma once
/// Progress of a long run: a bar redrawn in place on a terminal, plain lines every 10% (or
/// every 30 s) otherwise, so CI logs stay short. `barn run` prints it on stdout, the Python
/// front end on stderr.

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <cstddef>
#include <cstdio>
#include <string>

namespace barn::bench {

class ProgressReporter {
 public:
  /// Starts a heartbeat that redraws the bar (every second on a terminal, a line every 30 s
  /// otherwise) while episodes run, so a run of few long episodes is seen to be alive.
  /// `out` is where the lines go; `terminal` says whether it is one.
  ProgressReporter(std::size_t total, std::size_t already_done, bool terminal, std::FILE* out = stdout);
  ~ProgressReporter();
  ProgressReporter(const ProgressReporter&) = delete;
  ProgressReporter& operator=(const ProgressReporter&) = delete;

  /// One more episode finished (`success`: it reached the goal; `sim_time`: its simulated s).
  void update(bool success, double sim_time);
  /// Stops the heartbeat and ends the bar's line on a terminal.
  void finish();

 private:
  void print();  // with mutex_ held
  void heartbeat();

  std::size_t total_;
  std::size_t done_;
  std::size_t done_here_ = 0;  // finished in this session (for the ETA)
  std::size_t successes_ = 0;
  double sim_time_ = 0.0;
  bool terminal_;
  std::FILE* out_;
  std::size_t next_line_at_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_print_ = start_;
  std::mutex mutex_;  // update() and the heartbeat print from different threads
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread heartbeat_;
};

/// "1:02:03" or "2:03".
std::string formatDuration(double seconds);

}  // namespace barn::bench
