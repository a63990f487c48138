// barn config: the effective controller config of a run (or of a sweep cell) as a YAML file of
// its own, which `barn run --config FILE` takes back to run the same controller again; or, for
// a controller name, its config's fields with value, unit, range and meaning.

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "barn/bench/run_record.hpp"
#include "barn/bench/sweep_grid.hpp"
#include "barn/controllers/registry.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "commands.hpp"

namespace barn::cli {

namespace {

namespace fs = std::filesystem;

struct ConfigOptions {
  std::string record;
  std::string out;
};

// Why `dir` has no manifest to read, as a message that says what to give instead.
[[noreturn]] void throwNoManifest(const std::string& record) {
  const fs::path dir = record;
  if (!fs::exists(dir)) throw core::InputError(record + ": no such record folder");
  if (!fs::is_directory(dir)) throw core::InputError(record + ": is a file, expected a record folder");
  if (fs::exists(dir / bench::kSweepFile)) {
    std::string example = "CELL";
    try {
      const bench::SweepGrid grid = bench::readSweepFile(dir);
      if (!grid.cells.empty()) example = grid.cells.front();
    } catch (const core::InputError&) {
      // The hint is only a hint: a damaged sweep.yaml still gets the message below.
    }
    throw core::InputError(record + ": a sweep folder, whose cells have configs of their own; give a cell folder, e.g. " +
                           (dir / example).string());
  }
  throw core::InputError(record + ": no " + bench::kManifestFile + " (not a run record)");
}

// One line per field: key, value, unit, range, doc, in aligned columns.
std::string schemaTable(const std::vector<core::FieldRow>& rows) {
  std::size_t key_width = 3, value_width = 5, unit_width = 4, range_width = 5;
  for (const core::FieldRow& row : rows) {
    key_width = std::max(key_width, row.key.size());
    value_width = std::max(value_width, row.value.size());
    unit_width = std::max(unit_width, row.unit.size());
    range_width = std::max(range_width, row.range.size());
  }
  const auto padded = [](const std::string& text, std::size_t width) { return text + std::string(width - text.size() + 2, ' '); };
  const auto line = [&](const std::string& key, const std::string& value, const std::string& unit, const std::string& range,
                        const std::string& doc) {
    std::string text = padded(key, key_width) + padded(value, value_width) + padded(unit, unit_width) +
                       padded(range, range_width) + doc;
    return text.erase(text.find_last_not_of(' ') + 1) + "\n";
  };
  std::string text = line("key", "value", "unit", "range", "meaning");
  for (const core::FieldRow& row : rows) text += line(row.key, row.value, row.unit, row.range, row.doc);
  return text;
}

}  // namespace

void addConfigCommand(CLI::App& app, CommandContext& /*context*/) {
  auto options = std::make_shared<ConfigOptions>();
  CLI::App* cmd = app.add_subcommand(
      "config",
      "Print a run's (or a sweep cell's) effective controller config, for barn run --config FILE; or, given a "
      "controller name, its config's fields with value, unit, range and meaning");
  cmd->add_option("record", options->record,
                  "Run record folder (a sweep's cell folder for a sweep), or a controller name (as --controller takes)")
      ->required();
  cmd->add_option("--out", options->out, "Write the config to this file instead of printing it");
  cmd->callback([options] {
    const std::vector<std::string> types = controllers::controllerTypes();
    const bool controller_name = !fs::exists(options->record) && options->record.find('/') == std::string::npos &&
                                 (!controllerConfigFile(options->record, "").empty() ||
                                  std::find(types.begin(), types.end(), options->record) != types.end());
    if (controller_name) {
      // A controller name: its config file's values (configs/controllers/NAME.yaml) or the
      // type's defaults, each field with its schema.
      const std::string table = schemaTable(controllers::controllerSchema(controllerConfigFor(options->record, "")));
      if (options->out.empty()) {
        std::fputs(table.c_str(), stdout);
        return;
      }
      if (fs::is_directory(options->out)) throw core::InputError("--out " + options->out + ": is a folder, expected a file");
      core::writeFileAtomic(options->out, table);
      std::printf("wrote %s (fields of %s)\n", options->out.c_str(), options->record.c_str());
      return;
    }
    const fs::path manifest_file = fs::path(options->record) / bench::kManifestFile;
    if (!fs::exists(manifest_file)) throwNoManifest(options->record);
    const bench::RunManifest manifest = bench::readManifest(manifest_file);
    if (!manifest.source.empty())
      throw core::InputError(options->record + ": imported from " + manifest.source +
                             " (barn import-out): nothing was run, so it has no controller config");
    if (manifest.controller_config.empty())
      throw core::InputError(manifest_file.string() + ": controller_config: missing");
    // The text is the record's own, byte for byte; parsing it only makes sure a damaged
    // manifest is reported here rather than by the run it is given to.
    core::ConfigNode::parseString(manifest.controller_config, manifest_file.string() + " controller_config");
    if (options->out.empty()) {
      std::fputs(manifest.controller_config.c_str(), stdout);
      return;
    }
    if (fs::is_directory(options->out)) throw core::InputError("--out " + options->out + ": is a folder, expected a file");
    core::writeFileAtomic(options->out, manifest.controller_config);
    std::printf("wrote %s (controller config of %s)\n", options->out.c_str(), options->record.c_str());
  });
}

}  // namespace barn::cli
