#pragma once
/// The world file: one human-readable YAML file per world (format "barnbench-world/1"), plus
/// the index.csv of a set. See worlds/README.md for the format.

#include <filesystem>
#include <string>
#include <vector>

#include "barn/core/world.hpp"
#include "barn/core/text_io.hpp"

namespace barn::core {

inline constexpr const char* kWorldFormat = "barnbench-world/1";

/// The file name of world `id` inside a set folder: world_007.yaml.
std::string worldFileName(int id);

/// The world file text. Byte-stable: the same WorldSpec always gives the same text.
std::string formatWorldFile(const WorldSpec& world);

/// Parses and validates a world file's text; every problem becomes one line of the InputError,
/// prefixed by `source_name` and the field ("world_003.yaml: grid[4]: ...").
WorldSpec parseWorldFile(const std::string& text, const std::string& source_name);

/// Reads and validates a world file.
WorldSpec readWorldFile(const std::filesystem::path& path);

/// All world_*.yaml files of a folder, sorted by id; InputError if there are none, two files
/// share an id, or a write into the folder was interrupted (checkNoInterruptedWrite), and if a
/// file is invalid — or its name's number is not its id (world_003.yaml holding id 7) — unless
/// `skipped` is given: then its message is added there and the file left out.
std::vector<WorldSpec> readWorldSet(const std::filesystem::path& dir, std::vector<std::string>* skipped = nullptr);

/// index.csv of a set: one line per world with the fields a table or a plot needs.
std::string formatWorldIndex(const std::vector<WorldSpec>& worlds);

/// Every world file and index.csv of a set, for a writer of the folder (all or nothing:
/// bench::RecordWriter).
std::vector<FileContent> worldSetFiles(const std::vector<WorldSpec>& worlds);

}  // namespace barn::core
