#pragma once
/// `external`: a controller written in any language, run as a separate program that barn talks
/// to over its stdin and stdout, one JSON line per message, in lockstep (protocol v1,
/// docs/external_controller.md). A researcher scores their controller without recompiling barn.
///
/// One program process serves one worker thread's episodes one after another (see
/// child_process_pool.hpp). A program that exits, writes something that is not a valid answer,
/// or does not answer within `timeout` ends that episode with an error whose message carries
/// the end of the program's stderr; the process is stopped and the next episode gets a new one.

#include <memory>
#include <string>
#include <vector>

#include "barn/controllers/controller.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/external/child_process_pool.hpp"
#include "barn/external/external_protocol.hpp"

namespace barn::external {

struct ExternalConfig {
  std::vector<std::string> command;
  double rate = 20.0;
  double timeout = 5.0;
  double reset_timeout = 30.0;
  std::string working_dir;

  template <class V> void visit(V& v) {
    v("command", command, {.doc = "program and arguments, no shell (e.g. [python3, my_ctrl.py])"});
    v("rate", rate, {.unit = "Hz", .doc = "control rate: an observation every 1 / rate s of simulated time"});
    v("timeout", timeout, {.unit = "s", .doc = "wall time to wait for each command answer"});
    v("reset_timeout", reset_timeout,
      {.unit = "s", .doc = "wall time to wait for the answer to reset; a fresh process starts up within it (imports, loading a model)"});
    v("working_dir", working_dir, {.doc = "the program's folder; \"\" = the config file's folder"});
  }
};

/// Checks every field; the program must exist (on PATH when it has no '/') and be executable,
/// and working_dir must be a folder. Call after resolveExternalPaths.
void validate(const ExternalConfig& config, core::Errors& errors, const std::string& prefix);

/// Relative paths made absolute against the folder of the config file `config_source` (if it
/// is a file; else the current folder), as resolvePolicyPath does for policies: working_dir
/// ("" = that folder), and every argument, and the program if it has a '/', that names a file
/// or folder existing there. Other arguments (and programs found on PATH) stay as written.
ExternalConfig resolveExternalPaths(ExternalConfig config, const std::string& config_source);

class ExternalController : public controllers::Controller {
 public:
  /// `pool` holds the program processes shared by every controller of the same factory.
  ExternalController(const ExternalConfig& config, std::shared_ptr<ChildProcessPool> pool);
  /// Gives a healthy process back to the pool for the next episode.
  ~ExternalController() override;

  /// Sends the reset message (starting a process if this controller has none) and waits for
  /// {"ok": true}; throws std::runtime_error if the program fails.
  void reset(const controllers::EpisodeInfo& info) override;
  /// Sends the observation and waits for {"v", "w"}; throws std::runtime_error if the program
  /// fails.
  core::Twist act(const controllers::Observation& observation) override;
  double period() const override { return 1.0 / config_.rate; }
  /// The "state" the program sent with its last command ("" if none).
  std::string_view stateLabel() const override { return state_; }

 private:
  // Sends `message` and returns the answer line; a failure of the process ends it (fail).
  std::string exchange(const std::string& message, double timeout, const std::string& during);
  // Stops the process and throws one message: what went wrong, how the program ended, and
  // the end of its stderr.
  [[noreturn]] void fail(const std::string& during, const std::string& problem);

  ExternalConfig config_;
  std::shared_ptr<ChildProcessPool> pool_;
  std::unique_ptr<ChildProcess> process_;  // null between a failure and the next reset
  std::string state_;
  external::CostmapsSent costmaps_sent_;  // this episode's
};

}  // namespace barn::external
