#pragma once
/// A program run as a child process that barnbench talks to line by line over its stdin and
/// stdout, with its stderr captured (POSIX: posix_spawn, pipes, poll, waitpid).
///
/// Nothing here can hang or kill barn: every wait has a deadline, a write to a child that has
/// gone away is an error (SIGPIPE is blocked around the write and the pending signal
/// discarded), stderr is drained while waiting for an answer so a chatty child cannot block on
/// a full pipe, and every child is reaped. The child runs in its own process group, so a
/// Ctrl-C at the terminal reaches barn (which finishes its running episodes) but not the child,
/// and however the child ends (stopped, crashed, or exited by itself) its whole group is
/// killed before it is reaped: no process it started (a shell wrapper's, a helper it forked)
/// outlives it. Lockstep is kept: bytes the child wrote beyond its one answer line, or before a
/// message was sent, are an error (an extra line would shift every later answer by one).

#include <chrono>
#include <stdexcept>
#include <string>
#include <string_view>
#include <sys/types.h>
#include <vector>

namespace barn::external {

/// What to run: argv[0] is looked up on PATH if it has no '/'; no shell is involved.
struct ChildCommand {
  std::vector<std::string> argv;  // program and arguments
  std::string working_dir;        // "" = barn's current folder
};

/// A failed exchange: the child exited, closed a pipe, answered too late or too much.
class ChildProcessError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The deadline passed before the child answered (or made room in its stdin).
class ChildProcessTimeout : public ChildProcessError {
 public:
  using ChildProcessError::ChildProcessError;
};

class ChildProcess {
 public:
  using Clock = std::chrono::steady_clock;

  /// Starts the program; ChildProcessError if it cannot be started (not found, not executable,
  /// no such working folder).
  explicit ChildProcess(const ChildCommand& command);
  /// Stops the child at once (SIGKILL to its process group) unless it has already exited, and
  /// reaps it.
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  /// Writes `line` and a newline to the child's stdin, waiting at most until `deadline` for
  /// room in the pipe. ChildProcessError if the child's stdout already holds bytes (it wrote
  /// something no message asked for).
  void writeLine(std::string_view line, Clock::time_point deadline);
  /// The next line of the child's stdout (without the newline). Errors on end of file, on the
  /// deadline, on a line longer than kMaxLineBytes, on bytes after the line (a second line
  /// for one message), and when the child exits without answering (while a process it started
  /// still holds its stdout open).
  std::string readLine(Clock::time_point deadline);

  /// Closes the child's stdin: a well-behaved child exits when it reads end of file.
  void closeInput();
  /// Waits until `deadline` for the child to exit by itself; true if it did (and is reaped).
  bool waitForExit(Clock::time_point deadline);
  /// Ends the child (SIGKILL to its group, whether or not it already exited), reads what is
  /// left of its stderr and says how it ended: "exited with status 1", "was killed by signal 11
  /// (Segmentation fault)", "was stopped by barn". Safe to call more than once.
  std::string stop();

  /// The last kStderrTailBytes of what the child wrote to stderr so far.
  std::string stderrTail() const { return stderr_tail_; }
  pid_t pid() const { return pid_; }

  static constexpr std::size_t kMaxLineBytes = 1 << 20;  // [bytes] longest answer line accepted
  static constexpr std::size_t kStderrTailBytes = 2048;  // [bytes] stderr kept for messages

 private:
  // Reads whatever stderr holds now (non-blocking); false at end of file.
  bool drainStderr();
  // Waits for `fd` to become ready for `events` (POLLIN/POLLOUT) while draining stderr; false on
  // the deadline.
  bool waitReady(int fd, short events, Clock::time_point deadline);
  // Records the exit status of a reaped child.
  void noteExit(int status);
  // If the child has exited (or `wait`: once it exits), kills what is left of its process group
  // and reaps it; true if it is reaped. The group is killed before the child is reaped: its
  // zombie keeps the group id from being reused.
  bool reapIfExited(bool wait);
  // Reads whatever stdout holds now into stdout_buffer_ (non-blocking).
  void drainStdout();
  static void closeFd(int& fd);

  pid_t pid_ = -1;
  int exit_fd_ = -1;    // pidfd of the child: readable once it has exited (-1 where unsupported)
  int stdin_fd_ = -1;   // write end of the child's stdin
  int stdout_fd_ = -1;  // read end of the child's stdout
  int stderr_fd_ = -1;  // read end of the child's stderr
  bool reaped_ = false;
  bool killed_by_us_ = false;
  std::string ending_;       // how it ended, once reaped
  std::string stdout_buffer_;  // bytes read past the last complete line
  std::string stderr_tail_;
};

}  // namespace barn::external
