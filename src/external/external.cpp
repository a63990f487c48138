#include "barn/external/external.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <unistd.h>

#include "barn/external/external_protocol.hpp"

namespace barn::external {

namespace {

namespace fs = std::filesystem;

// The program as the shell would find it: a path if it has a '/', else the first executable
// file of that name on PATH. Empty if there is none.
std::string findProgram(const std::string& program) {
  const auto executable = [](const fs::path& p) {
    std::error_code ec;
    return fs::is_regular_file(p, ec) && access(p.c_str(), X_OK) == 0;
  };
  if (program.find('/') != std::string::npos) return executable(program) ? program : std::string();
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/local/bin:/usr/bin:/bin";
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const std::size_t colon = std::min(dirs.find(':', start), dirs.size());
    const std::string dir = dirs.substr(start, colon - start);
    const fs::path candidate = fs::path(dir.empty() ? "." : dir) / program;
    if (executable(candidate)) return candidate.string();
    start = colon + 1;
  }
  return {};
}

// The command as one short string for messages.
std::string describe(const std::vector<std::string>& argv) {
  std::string text;
  for (const std::string& arg : argv) text += (text.empty() ? "" : " ") + arg;
  constexpr std::size_t kShown = 160;  // [characters]
  return text.size() > kShown ? text.substr(0, kShown) + "..." : text;
}

std::string seconds(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%g", value);
  return buffer;
}

// The stderr tail for a message: trailing newlines trimmed, cut to whole lines when the tail
// starts mid-line.
std::string stderrPart(std::string tail) {
  while (!tail.empty() && (tail.back() == '\n' || tail.back() == '\r' || tail.back() == ' ')) tail.pop_back();
  if (tail.empty()) return "its stderr was empty";
  if (tail.size() >= ChildProcess::kStderrTailBytes) {
    const std::size_t newline = tail.find('\n');
    if (newline != std::string::npos && newline + 1 < tail.size()) tail.erase(0, newline + 1);
    return "its stderr ends with:\n" + tail;
  }
  return "its stderr:\n" + tail;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Config

void validate(const ExternalConfig& c, core::Errors& errors, const std::string& prefix) {
  const std::string command_key = prefix + ".command";
  if (errors.check(!c.command.empty(), command_key, "must name the program to run, e.g. [python3, my_controller.py]")) {
    for (std::size_t i = 0; i < c.command.size(); ++i)
      errors.check(!c.command[i].empty(), command_key + "[" + std::to_string(i) + "]", "must not be empty");
    const std::string& program = c.command.front();
    if (!program.empty() && findProgram(program).empty()) {
      if (program.find('/') == std::string::npos)
        errors.add(command_key, "program '" + program + "' not found on PATH");
      else if (!fs::exists(program))
        errors.add(command_key, "program '" + program + "' does not exist");
      else
        errors.add(command_key, "'" + program +
                                    "' is not an executable file (make it executable, or name its interpreter "
                                    "first, e.g. [python3, script.py])");
    }
  }
  errors.check(std::isfinite(c.rate) && c.rate > 0.0, prefix + ".rate", "must be > 0 [Hz]");
  errors.check(std::isfinite(c.timeout) && c.timeout > 0.0, prefix + ".timeout", "must be > 0 [s]");
  errors.check(std::isfinite(c.reset_timeout) && c.reset_timeout > 0.0, prefix + ".reset_timeout", "must be > 0 [s]");
  // Waits longer than a day are typos (our bound); far longer ones would overflow the clock.
  errors.check(!(c.timeout > 86400.0), prefix + ".timeout", "must be <= 86400 [s]");
  errors.check(!(c.reset_timeout > 86400.0), prefix + ".reset_timeout", "must be <= 86400 [s]");
  errors.check(!(c.rate > 1000.0), prefix + ".rate", "must be <= 1000 [Hz]");
  std::error_code ec;
  errors.check(fs::is_directory(c.working_dir, ec), prefix + ".working_dir",
               "'" + c.working_dir + "' is not a folder");
}

ExternalConfig resolveExternalPaths(ExternalConfig config, const std::string& config_source) {
  std::error_code ec;
  const fs::path source(config_source);
  const fs::path base = !config_source.empty() && fs::is_regular_file(source, ec)
                            ? fs::absolute(source).parent_path()
                            : fs::current_path();
  const auto beside = [&](const std::string& text) -> std::string {
    const fs::path path(text);
    if (text.empty() || path.is_absolute()) return text;
    std::error_code exists_ec;
    if (!fs::exists(base / path, exists_ec)) return text;
    return (base / path).lexically_normal().string();
  };
  config.working_dir = config.working_dir.empty() ? base.lexically_normal().string()
                       : fs::path(config.working_dir).is_absolute()
                           ? config.working_dir
                           : (base / config.working_dir).lexically_normal().string();
  for (std::size_t i = 0; i < config.command.size(); ++i)
    if (i > 0 || config.command[i].find('/') != std::string::npos) config.command[i] = beside(config.command[i]);
  return config;
}

// ---------------------------------------------------------------------------------------------
// Controller

ExternalController::ExternalController(const ExternalConfig& config, std::shared_ptr<ChildProcessPool> pool)
    : config_(config), pool_(std::move(pool)) {}

ExternalController::~ExternalController() {
  if (process_) pool_->giveBack(std::move(process_));
}

void ExternalController::reset(const controllers::EpisodeInfo& info) {
  state_.clear();
  costmaps_sent_ = {};
  if (!process_) {
    try {
      process_ = pool_->take();
    } catch (const ChildProcessError& e) {
      throw std::runtime_error("external controller: " + std::string(e.what()));
    }
  }
  const std::string answer = exchange(external::resetMessage(info, period()), config_.reset_timeout, "reset");
  try {
    external::readResetAnswer(answer);
  } catch (const external::ProtocolError& e) {
    fail("reset", e.what());
  }
}

core::Twist ExternalController::act(const controllers::Observation& obs) {
  char during[64];
  std::snprintf(during, sizeof(during), "the observation at t = %.2f s", obs.time);
  if (!process_) throw std::runtime_error("external controller: act() without a successful reset()");
  const std::string answer = exchange(external::observationMessage(obs, costmaps_sent_), config_.timeout, during);
  external::CommandAnswer command;
  try {
    command = external::readCommandAnswer(answer);
  } catch (const external::ProtocolError& e) {
    fail(during, e.what());
  }
  state_ = std::move(command.state);
  if (!command.params.empty() && !obs.stack_parameters)
    throw std::runtime_error("external controller: \"params\" in the answer to " + std::string(during) +
                             ", but the controller config has no global_plan block whose parameters it could set");
  // An unknown key or a bad value ends the episode as an error naming the key.
  for (const auto& [key, value] : command.params) obs.stack_parameters->set(key, value);
  return command.command;
}

std::string ExternalController::exchange(const std::string& message, double timeout, const std::string& during) {
  const auto deadline = ChildProcess::Clock::now() + std::chrono::duration_cast<ChildProcess::Clock::duration>(
                                                         std::chrono::duration<double>(timeout));
  try {
    process_->writeLine(message, deadline);
    return process_->readLine(deadline);
  } catch (const ChildProcessTimeout& e) {
    fail(during, std::string("no answer within ") + seconds(timeout) + " s (" + e.what() + ")");
  } catch (const ChildProcessError& e) {
    fail(during, e.what());
  }
}

void ExternalController::fail(const std::string& during, const std::string& problem) {
  const pid_t pid = process_->pid();
  const std::string ending = process_->stop();
  const std::string tail = process_->stderrTail();
  process_.reset();  // the next reset takes a fresh process
  throw std::runtime_error("external controller '" + describe(pool_->command().argv) + "' (pid " +
                           std::to_string(pid) + ") failed at " + during + ": " + problem + "; the program " + ending +
                           "; " + stderrPart(tail));
}

}  // namespace barn::external
