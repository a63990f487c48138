// barn export-worlds: worlds back to the official harness (Gazebo .world files with their path
// files) or to the original BARN dataset's .npy layout, which `barn import-barn` reads.

#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "barn/bench/record_writer.hpp"
#include "barn/bench/world_selection.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "commands.hpp"
#include "generator/dataset_export.hpp"
#include "generator/dataset_files.hpp"
#include "generator/gazebo_world.hpp"
#include "repo_paths.hpp"

namespace barn::cli {

namespace {

namespace fs = std::filesystem;

struct ExportWorldsOptions {
  std::string world_dir;
  std::string worlds = "all";
  std::string format;
  std::string out;
  bool force = false;
};

// The files of an earlier export (either format) in `dir`, relative to it: world_*.world and
// the dataset folders' STEM_*.npy.
std::vector<fs::path> existingExportFiles(const fs::path& dir) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with("world_") && name.ends_with(".world")) files.push_back(name);
  }
  for (const generator::DatasetArrayFiles& kind : generator::kDatasetArrays) {
    for (const auto& entry : fs::directory_iterator(dir / kind.folder, ec)) {
      const std::string name = entry.path().filename().string();
      if (name.starts_with(std::string(kind.stem) + "_") && name.ends_with(".npy"))
        files.push_back(fs::path(kind.folder) / name);
    }
  }
  return files;
}

}  // namespace

void addExportWorldsCommand(CLI::App& app, CommandContext& /*context*/) {
  auto options = std::make_shared<ExportWorldsOptions>();
  CLI::App* cmd = app.add_subcommand(
      "export-worlds", "Write worlds as Gazebo .world files for the official harness, or as the BARN dataset's .npy files");
  cmd->add_option("--world-dir", options->world_dir, "Folder the ids of --worlds refer to (default worlds/)");
  cmd->add_option("--worlds", options->worlds, "all, test50, A:B[:STEP], 3,7,9, or a folder of world files")
      ->capture_default_str();
  cmd->add_option("--format", options->format,
                  "gazebo: world_N.world + path_files/path_N.npy (the harness's worlds/BARN/ folder); "
                  "npy: grid_files/, cspace_files/, path_files/, metrics_files/, norm_metrics_files/")
      ->required()
      ->check(CLI::IsMember({"gazebo", "npy"}));
  cmd->add_option("--out", options->out, "Folder to write")->required();
  cmd->add_flag("--force", options->force,
                "Replace an earlier export in --out (its files not in the new export are deleted)");
  cmd->callback([options] {
    // Everything is read and checked before anything is written.
    if (!options->world_dir.empty() && !fs::is_directory(options->world_dir))
      throw core::InputError("--world-dir " + options->world_dir + ": no such folder");
    const fs::path out = options->out;
    if (fs::exists(out) && !fs::is_directory(out))
      throw core::InputError("--out " + options->out + ": is a file, expected a folder");
    const bench::LoadedWorlds loaded = bench::loadWorlds(
        options->worlds, options->world_dir.empty() ? repoPath("worlds") : fs::path(options->world_dir));
    const bool gazebo = options->format == "gazebo";
    const std::vector<core::FileContent> files =
        gazebo ? generator::harnessFiles(loaded.worlds) : generator::datasetFiles(loaded.worlds);

    // A folder holding another export is replaced only with --force, and then whole: a
    // smaller export over a larger one would otherwise leave files that import-barn (or the
    // harness) takes for part of it.
    // One locked set write: a kill leaves the earlier export or the new one, never a mix.
    checkOutFolder(out, "--out");
    const bench::RecordWriter writer(out);
    const std::vector<fs::path> old_files = existingExportFiles(out);
    if (!old_files.empty() && !options->force)
      throw core::InputError("--out " + options->out + ": already holds exported worlds (" +
                             std::to_string(old_files.size()) + " files, e.g. " + old_files.front().string() +
                             "); --force replaces them, or choose another --out");
    std::set<fs::path> written;
    for (const auto& file : files) written.insert(file.name);
    std::vector<std::string> removals;
    for (const auto& file : old_files)
      if (!written.count(file)) removals.push_back(file.string());
    writer.write(files, removals);
    const std::size_t removed = removals.size();

    std::printf("wrote %zu worlds (%zu files, %s) to %s%s\n", loaded.worlds.size(), files.size(),
                gazebo ? "world_N.world and path_files/path_N.npy" : "the BARN dataset layout", options->out.c_str(),
                removed ? (", removed " + std::to_string(removed) + " files of the earlier export").c_str() : "");
    if (gazebo) {
      // run.py reads world_idx 300 and above as DynaBARN worlds, not from worlds/BARN/.
      for (const auto& w : loaded.worlds)
        if (w.id >= 300)
          std::fprintf(stderr, "warning: world %d: the official run.py takes --world_idx >= 300 as a DynaBARN world\n", w.id);
    }
  });
}

}  // namespace barn::cli
