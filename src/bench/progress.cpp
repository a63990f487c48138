#include "barn/bench/progress.hpp"

#include <algorithm>
#include <cstdio>

namespace barn::bench {

std::string formatDuration(double seconds) {
  const long s = static_cast<long>(seconds + 0.5);
  char text[32];
  if (s >= 3600) std::snprintf(text, sizeof(text), "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  else std::snprintf(text, sizeof(text), "%ld:%02ld", s / 60, s % 60);
  return text;
}

ProgressReporter::ProgressReporter(std::size_t total, std::size_t already_done, bool terminal, std::FILE* out)
    : total_(total), done_(already_done), terminal_(terminal), out_(out), next_line_at_(already_done + std::max<std::size_t>(1, total / 10)) {
  heartbeat_ = std::thread([this] { heartbeat(); });
}

ProgressReporter::~ProgressReporter() { finish(); }

void ProgressReporter::update(bool success, double sim_time) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++done_;
  ++done_here_;
  successes_ += success;
  sim_time_ += sim_time;
  const auto now = std::chrono::steady_clock::now();
  const double since_print = std::chrono::duration<double>(now - last_print_).count();
  if (terminal_) {
    if (since_print >= 0.1 || done_ == total_) print();
  } else if (done_ >= next_line_at_ || since_print >= 30.0 || done_ == total_) {
    print();
    next_line_at_ = done_ + std::max<std::size_t>(1, total_ / 10);
  }
}

void ProgressReporter::heartbeat() {
  const auto period = terminal_ ? std::chrono::seconds(1) : std::chrono::seconds(30);
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stopping_) {
    wake_.wait_for(lock, period, [this] { return stopping_; });
    if (stopping_) break;
    if (std::chrono::steady_clock::now() - last_print_ >= period) print();
  }
}

void ProgressReporter::finish() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_) return;
    stopping_ = true;
  }
  wake_.notify_all();
  if (heartbeat_.joinable()) heartbeat_.join();
  if (terminal_) std::fprintf(out_, "\n");
  std::fflush(out_);
}

void ProgressReporter::print() {
  last_print_ = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(last_print_ - start_).count();
  const double eta = done_here_ ? elapsed / static_cast<double>(done_here_) * static_cast<double>(total_ - done_) : 0.0;
  const double rate = elapsed > 0 ? sim_time_ / elapsed : 0.0;
  const double success = done_here_ ? 100.0 * static_cast<double>(successes_) / static_cast<double>(done_here_) : 0.0;
  if (terminal_) {
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(kWidth * static_cast<double>(done_) / static_cast<double>(std::max<std::size_t>(1, total_)));
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(kWidth, '.');
    std::fprintf(out_, "\r[%s] %zu/%zu  success %5.1f%%  %6.0f sim-s/s  eta %s   ", bar.c_str(), done_, total_, success, rate,
                formatDuration(eta).c_str());
  } else {
    std::fprintf(out_, "progress %zu/%zu episodes, success %.1f%%, %.0f sim-s/s, elapsed %s, eta %s\n", done_, total_, success,
                rate, formatDuration(elapsed).c_str(), formatDuration(eta).c_str());
  }
  std::fflush(out_);
}

}  // namespace barn::bench
