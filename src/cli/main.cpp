// barn: the barnbench command-line tool. Parsing only; the work lives in the libraries.
//
// Exit codes: 0 ok, 1 the run or check failed, 2 bad usage or bad input.

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <string>
#include <system_error>

#include <CLI/CLI.hpp>

#include "barn/bench/record_session.hpp"
#include "barn/core/errors.hpp"
#include "commands.hpp"

namespace {

// A file-system failure as "PATH: REASON". Exit 2 when the path itself is at fault (too long, a
// symlink loop, a file where a folder is wanted): bad input; 1 otherwise (no space, read-only,
// permissions, I/O): the work failed.
int reportFilesystemError(const std::filesystem::filesystem_error& e) {
  std::string paths = e.path1().string();
  if (!e.path2().empty()) paths += " -> " + e.path2().string();
  std::fprintf(stderr, "error: %s: %s\n", paths.empty() ? "file system" : paths.c_str(), e.code().message().c_str());
  const std::error_code code = e.code();
  const bool bad_path = code == std::errc::filename_too_long || code == std::errc::too_many_symbolic_link_levels ||
                        code == std::errc::not_a_directory || code == std::errc::is_a_directory ||
                        code == std::errc::invalid_argument;
  return bad_path ? 2 : 1;
}

// Exit status after the command: what it said, unless its output could not be written (a full
// disk behind `barn config R > cfg.yaml`, /dev/full): a short file is never a success.
int finishOutput(int status) {
  errno = 0;
  const bool flushed = std::fflush(stdout) == 0;
  const int error = errno;
  if (flushed && !std::ferror(stdout)) return status;
  std::fprintf(stderr, "error: stdout: write failed: %s\n",
               !flushed && error != 0 ? std::strerror(error) : "an earlier write failed (disk full?)");
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"barnbench: BARN worlds, simulation and scoring without ROS or Gazebo", "barn"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("barn (barnbench) ") + BARN_VERSION + ", commit " + barn::bench::gitCommit());
  barn::cli::CommandContext context;
  barn::cli::addGenerateCommand(app, context);
  barn::cli::addImportCommand(app, context);
  barn::cli::addWorldCommand(app, context);
  barn::cli::addRunCommand(app, context);
  barn::cli::addMergeCommand(app, context);
  barn::cli::addShowCommand(app, context);
  barn::cli::addReportCommand(app, context);
  barn::cli::addRegressCommand(app, context);
  barn::cli::addSweepCommand(app, context);
  barn::cli::addPlotCommand(app, context);
  barn::cli::addHarnessOutCommands(app, context);
  barn::cli::addCompareCommand(app, context);
  barn::cli::addLflhCommand(app, context);
  barn::cli::addPolicyCommand(app, context);
  barn::cli::addExportWorldsCommand(app, context);
  barn::cli::addConfigCommand(app, context);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return finishOutput(code == 0 ? 0 : 2);
  } catch (const barn::core::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return finishOutput(2);
  } catch (const std::filesystem::filesystem_error& e) {
    return finishOutput(reportFilesystemError(e));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return finishOutput(1);
  }
  return finishOutput(context.exit_code);
}
