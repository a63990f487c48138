// barn report: a finished run record or sweep as one self-contained HTML page; the page is
// assembled by report::writeReport (barn/report/report.hpp), which barnbench.report() calls too.

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "barn/core/errors.hpp"
#include "barn/report/report.hpp"
#include "commands.hpp"

namespace barn::cli {

namespace {

namespace fs = std::filesystem;

struct ReportOptions {
  std::string input;
  std::string output;
  int max_failures = 12;
};

}  // namespace

void addReportCommand(CLI::App& app, CommandContext& /*context*/) {
  auto options = std::make_shared<ReportOptions>();
  CLI::App* cmd = app.add_subcommand("report", "A finished run record or sweep as one self-contained HTML page");
  cmd->add_option("input", options->input, "Run record or sweep folder")->required();
  cmd->add_option("-o,--output", options->output, "HTML file")->required();
  cmd->add_option("--max-failures", options->max_failures, "Failed episodes to re-simulate and draw at most")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  cmd->callback([options] {
    const fs::path output = options->output;
    if (output.extension() != ".html") throw core::InputError("-o " + output.string() + ": expected a .html file");
    report::ReportOptions report_options;
    report_options.max_failures = options->max_failures;
    report::writeReport(options->input, output, report_options);
    std::printf("wrote %s\n", output.c_str());
  });
}

}  // namespace barn::cli
