// barn: the barnbench command-line tool. Parsing only; the work lives in the libraries.
//
// Exit codes: 0 ok, 1 the run or check failed, 2 bad usage or bad input.

#include <cstdio>
#include <exception>
#include <string>

#include <CLI/CLI.hpp>

#include "barn/bench/record_session.hpp"
#include "barn/core/errors.hpp"
#include "commands.hpp"

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
    return code == 0 ? 0 : 2;
  } catch (const barn::core::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return context.exit_code;
}
