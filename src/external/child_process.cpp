#include "barn/external/child_process.hpp"

#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <spawn.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace barn::external {

namespace {

using Clock = ChildProcess::Clock;

std::string errnoText(int error) { return std::strerror(error); }

// A pipe whose ends are close-on-exec, so that a child spawned by another worker thread at the
// same moment does not inherit them (an inherited write end would keep our child's stdin open
// after we close it). Both ends are moved above 2: posix_spawn's dup2 onto 0, 1, 2 would not
// clear close-on-exec on a descriptor that is already there (possible when barn runs with a
// closed stdin).
void makePipe(int fds[2]) {
  if (pipe2(fds, O_CLOEXEC) != 0) throw ChildProcessError("cannot create a pipe: " + errnoText(errno));
  for (int i = 0; i < 2; ++i)
    if (fds[i] <= 2) {
      const int moved = fcntl(fds[i], F_DUPFD_CLOEXEC, 3);
      const int error = errno;
      close(fds[i]);
      fds[i] = moved;
      if (moved < 0) throw ChildProcessError("cannot create a pipe: " + errnoText(error));
    }
}

void setNonBlocking(int fd) { fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK); }

// Milliseconds to `deadline`, rounded up (0 if past), for poll().
int millisecondsTo(Clock::time_point deadline) {
  const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return left <= 0 ? 0 : static_cast<int>(std::min<long long>(left, 60'000));
}

// RAII for posix_spawn's two helper objects.
struct SpawnSetup {
  posix_spawn_file_actions_t actions;
  posix_spawnattr_t attributes;
  SpawnSetup() {
    posix_spawn_file_actions_init(&actions);
    posix_spawnattr_init(&attributes);
  }
  ~SpawnSetup() {
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
  }
};

}  // namespace

ChildProcess::ChildProcess(const ChildCommand& command) {
  if (command.argv.empty() || command.argv[0].empty()) throw ChildProcessError("no program to run");
  int in[2] = {-1, -1}, out[2] = {-1, -1}, err[2] = {-1, -1};
  const auto closeAll = [&] {
    for (int* fd : {&in[0], &in[1], &out[0], &out[1], &err[0], &err[1]}) closeFd(*fd);
  };
  try {
    makePipe(in);
    makePipe(out);
    makePipe(err);
  } catch (...) {
    closeAll();
    throw;
  }

  SpawnSetup setup;
  if (!command.working_dir.empty()) posix_spawn_file_actions_addchdir_np(&setup.actions, command.working_dir.c_str());
  posix_spawn_file_actions_adddup2(&setup.actions, in[0], STDIN_FILENO);
  posix_spawn_file_actions_adddup2(&setup.actions, out[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&setup.actions, err[1], STDERR_FILENO);
  // Own process group (see the header), default signal handling and an empty signal mask: the
  // child must not inherit a blocked or ignored SIGPIPE, nor the mask of an OpenMP worker.
  sigset_t all, none;
  sigfillset(&all);
  sigemptyset(&none);
  posix_spawnattr_setpgroup(&setup.attributes, 0);
  posix_spawnattr_setsigdefault(&setup.attributes, &all);
  posix_spawnattr_setsigmask(&setup.attributes, &none);
  posix_spawnattr_setflags(&setup.attributes, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);

  std::vector<char*> argv;
  for (const std::string& arg : command.argv) argv.push_back(const_cast<char*>(arg.c_str()));
  argv.push_back(nullptr);
  const int error = posix_spawnp(&pid_, argv[0], &setup.actions, &setup.attributes, argv.data(), environ);
  closeFd(in[0]);
  closeFd(out[1]);
  closeFd(err[1]);
  stdin_fd_ = in[1];
  stdout_fd_ = out[0];
  stderr_fd_ = err[0];
  if (error != 0) {
    pid_ = -1;
    reaped_ = true;
    closeFd(stdin_fd_);
    closeFd(stdout_fd_);
    closeFd(stderr_fd_);
    std::string where = command.working_dir.empty() ? "" : " in '" + command.working_dir + "'";
    throw ChildProcessError("cannot start '" + command.argv[0] + "'" + where + ": " + errnoText(error));
  }
  setNonBlocking(stdin_fd_);
  setNonBlocking(stdout_fd_);
  setNonBlocking(stderr_fd_);
  // Readable once the child exits, so a wait for its answer ends then (Linux 5.3; without it
  // the wait runs to its deadline). Close-on-exec by default.
#ifdef SYS_pidfd_open
  exit_fd_ = static_cast<int>(syscall(SYS_pidfd_open, pid_, 0));
#endif
}

ChildProcess::~ChildProcess() {
  if (!reaped_) {
    kill(-pid_, SIGKILL);
    int status = 0;
    while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
  }
  closeFd(stdin_fd_);
  closeFd(stdout_fd_);
  closeFd(stderr_fd_);
  closeFd(exit_fd_);
}

void ChildProcess::closeFd(int& fd) {
  if (fd >= 0) close(fd);
  fd = -1;
}

// ---------------------------------------------------------------------------------------------
// Exchanging lines

bool ChildProcess::drainStderr() {
  char buffer[4096];
  while (stderr_fd_ >= 0) {
    const ssize_t n = read(stderr_fd_, buffer, sizeof(buffer));
    if (n > 0) {
      stderr_tail_.append(buffer, static_cast<std::size_t>(n));
      if (stderr_tail_.size() > kStderrTailBytes) stderr_tail_.erase(0, stderr_tail_.size() - kStderrTailBytes);
    } else if (n < 0 && errno == EINTR) {
      continue;
    } else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      return true;
    } else {
      closeFd(stderr_fd_);  // end of file (or an error: nothing more to read either way)
    }
  }
  return false;
}

bool ChildProcess::waitReady(int fd, short events, Clock::time_point deadline) {
  while (true) {
    // fd first; stderr and the exit descriptor only when open.
    pollfd fds[3] = {{fd, events, 0}, {stderr_fd_, POLLIN, 0}, {exit_fd_, POLLIN, 0}};
    const int ready = poll(fds, 3, millisecondsTo(deadline));
    if (ready < 0) {
      if (errno == EINTR) continue;
      throw ChildProcessError("poll failed: " + errnoText(errno));
    }
    if (fds[1].revents != 0) drainStderr();
    if (fds[0].revents != 0) return true;  // ready, or hung up / error: the read or write says which
    if (fds[2].revents != 0) {
      // It exited, yet the pipe is still open: a process it started holds the other end. No
      // answer will come from the program itself.
      throw ChildProcessError(events == POLLIN ? "it exited without answering (a process it started still holds its stdout)"
                                               : "it exited (a process it started still holds its stdin)");
    }
    if (Clock::now() >= deadline) return false;
  }
}

void ChildProcess::drainStdout() {
  char buffer[4096];
  while (stdout_fd_ >= 0 && stdout_buffer_.size() <= kMaxLineBytes) {
    const ssize_t n = read(stdout_fd_, buffer, sizeof(buffer));
    if (n > 0) stdout_buffer_.append(buffer, static_cast<std::size_t>(n));
    else if (n < 0 && errno == EINTR) continue;
    else return;  // nothing more now, end of file or an error: the next read says which
  }
}

void ChildProcess::writeLine(std::string_view line, Clock::time_point deadline) {
  if (stdin_fd_ < 0) throw ChildProcessError("its stdin is closed");
  // Whatever it wrote since its last answer answers nothing: an extra line would be taken as
  // the answer to this message and shift every later one by one.
  drainStdout();
  if (!stdout_buffer_.empty()) {
    std::string shown = stdout_buffer_.substr(0, 60);
    for (char& ch : shown)
      if (static_cast<unsigned char>(ch) < 0x20 || static_cast<unsigned char>(ch) >= 0x7f) ch = '?';
    throw ChildProcessError("it wrote " + std::to_string(stdout_buffer_.size()) +
                            " bytes that answer no message ('" + shown + (stdout_buffer_.size() > 60 ? "...'" : "'") +
                            "): one line per message");
  }
  std::string data(line);
  data += '\n';
  std::size_t written = 0;
  // SIGPIPE is blocked for this thread during the write, and one raised by it is taken off the
  // pending set, so a child that went away gives EPIPE here instead of killing barn. Nothing
  // process-wide changes.
  sigset_t pipe_signal, previous;
  sigemptyset(&pipe_signal);
  sigaddset(&pipe_signal, SIGPIPE);
  while (written < data.size()) {
    if (!waitReady(stdin_fd_, POLLOUT, deadline)) throw ChildProcessTimeout("it does not read its stdin");
    pthread_sigmask(SIG_BLOCK, &pipe_signal, &previous);
    const ssize_t n = write(stdin_fd_, data.data() + written, data.size() - written);
    const int error = errno;
    if (n < 0 && error == EPIPE) {
      const timespec no_wait{0, 0};
      while (sigtimedwait(&pipe_signal, nullptr, &no_wait) > 0) {
      }
    }
    pthread_sigmask(SIG_SETMASK, &previous, nullptr);
    if (n >= 0) {
      written += static_cast<std::size_t>(n);
    } else if (error == EPIPE) {
      throw ChildProcessError("it closed its stdin");
    } else if (error != EAGAIN && error != EWOULDBLOCK && error != EINTR) {
      throw ChildProcessError("writing to its stdin failed: " + errnoText(error));
    }
  }
}

std::string ChildProcess::readLine(Clock::time_point deadline) {
  char buffer[65536];
  std::size_t searched = 0;
  while (true) {
    const std::size_t newline = stdout_buffer_.find('\n', searched);
    if (newline != std::string::npos) {
      std::string line = stdout_buffer_.substr(0, newline);
      stdout_buffer_.erase(0, newline + 1);
      if (!stdout_buffer_.empty())
        throw ChildProcessError("it wrote more than one line for one message (" + std::to_string(stdout_buffer_.size()) +
                                " bytes after its answer)");
      return line;
    }
    searched = stdout_buffer_.size();
    if (stdout_buffer_.size() > kMaxLineBytes)
      throw ChildProcessError("it wrote a line longer than " + std::to_string(kMaxLineBytes) + " bytes");
    if (stdout_fd_ < 0) throw ChildProcessError("its stdout is closed");
    if (!waitReady(stdout_fd_, POLLIN, deadline)) throw ChildProcessTimeout("it did not answer");
    const ssize_t n = read(stdout_fd_, buffer, sizeof(buffer));
    if (n > 0) {
      stdout_buffer_.append(buffer, static_cast<std::size_t>(n));
    } else if (n == 0) {
      closeFd(stdout_fd_);
      throw ChildProcessError(stdout_buffer_.empty() ? "it closed its stdout (exited?)"
                                                     : "it closed its stdout in the middle of a line");
    } else if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
      throw ChildProcessError("reading its stdout failed: " + errnoText(errno));
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Ending

void ChildProcess::closeInput() { closeFd(stdin_fd_); }

void ChildProcess::noteExit(int status) {
  reaped_ = true;
  if (WIFEXITED(status)) {
    ending_ = "exited with status " + std::to_string(WEXITSTATUS(status));
  } else if (WIFSIGNALED(status)) {
    const int signal = WTERMSIG(status);
    ending_ = killed_by_us_ && signal == SIGKILL
                  ? std::string("was stopped by barn")
                  : "was killed by signal " + std::to_string(signal) + " (" + strsignal(signal) + ")";
  } else {
    ending_ = "ended";
  }
}

bool ChildProcess::reapIfExited(bool wait) {
  if (reaped_) return true;
  siginfo_t info{};
  int result = 0;
  // WNOWAIT: look without reaping, so the zombie keeps its pid (the group's id) reserved until
  // the group has been killed.
  while ((result = waitid(P_PID, static_cast<id_t>(pid_), &info, WEXITED | WNOWAIT | (wait ? 0 : WNOHANG))) < 0 &&
         errno == EINTR) {
  }
  if (result < 0) {  // not our child any more: nothing left to wait for
    reaped_ = true;
    ending_ = "ended";
    return true;
  }
  if (info.si_pid == 0) return false;  // still running
  kill(-pid_, SIGKILL);                // whatever it started goes with it
  int status = 0;
  pid_t done = -1;
  while ((done = waitpid(pid_, &status, 0)) < 0 && errno == EINTR) {
  }
  if (done == pid_) noteExit(status);
  reaped_ = true;
  return true;
}

bool ChildProcess::waitForExit(Clock::time_point deadline) {
  while (!reapIfExited(false)) {
    if (Clock::now() >= deadline) return false;
    // Sleep a little, draining stderr meanwhile (a child blocked on a full stderr pipe never exits).
    pollfd fds{stderr_fd_, POLLIN, 0};
    if (poll(&fds, stderr_fd_ >= 0 ? 1 : 0, 2) > 0) drainStderr();
  }
  return true;
}

std::string ChildProcess::stop() {
  if (!reaped_) {
    // A child that is already on its way out (it crashed, or closed stdout to exit) gets a
    // moment to finish, so that its own exit status and last words are reported.
    if (!waitForExit(Clock::now() + std::chrono::milliseconds(100))) {
      kill(-pid_, SIGKILL);
      killed_by_us_ = true;
      reapIfExited(true);
    }
  }
  // Whatever is left in the stderr pipe. Its write ends died with the process group; the
  // deadline covers a descendant that left the group and still holds one.
  const auto deadline = Clock::now() + std::chrono::milliseconds(200);
  while (stderr_fd_ >= 0) {
    pollfd fds{stderr_fd_, POLLIN, 0};
    const int ready = poll(&fds, 1, millisecondsTo(deadline));
    if (ready > 0) drainStderr();
    else if (ready == 0 || errno != EINTR) break;
  }
  closeInput();
  closeFd(stdout_fd_);
  closeFd(stderr_fd_);
  return ending_;
}

}  // namespace barn::external
