#pragma once
/// Small file helpers: whole-file reads, atomic writes, exact number formatting.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace barn::core {

/// Throws InputError naming `path` unless it is a regular file (after following symlinks):
/// missing, a folder, or a device, fifo or socket, which could hang or never end.
void requireRegularFile(const std::filesystem::path& path);

/// Reads a whole regular file; throws InputError naming the path if it cannot (see
/// requireRegularFile).
std::string readTextFile(const std::filesystem::path& path);

/// Writes `content` to `path` through a temporary file and a rename, so a reader never sees
/// a half-written file; the file is flushed to the disk (fsync) before the rename and the
/// folder after it, so a power loss does not leave a truncated file either. Throws IoError
/// naming the path and the system's reason on failure (disk full: exit 1, not bad input).
void writeFileAtomic(const std::filesystem::path& path, std::string_view content);

/// Writes several files into `dir` (created if missing) all or nothing: every file is first
/// written into a staging folder inside `dir` (and flushed to the disk), and only moved into
/// place once all succeeded. A name may hold subfolders ("grid_files/grid_0.npy"), which are
/// created. IoError on failure, as writeFileAtomic; std::invalid_argument for an absolute name
/// or one with "..".
struct FileContent {
  std::string name;     // path relative to the folder, e.g. "index.csv" or "grid_files/grid_0.npy"
  std::string content;
};
void writeFilesAtomic(const std::filesystem::path& dir, const std::vector<FileContent>& files);

/// Shortest decimal text that reads back as exactly `value` (std::to_chars round trip).
std::string formatDouble(double value);

/// 64-bit FNV-1a hash of `text`, continuing from `hash` (to digest several texts in order).
std::uint64_t fnv1a64(std::string_view text, std::uint64_t hash = 0xcbf29ce484222325ull);

/// Parses a whole string as a double (std::from_chars); false if it is not one.
bool parseDouble(std::string_view text, double& value);

/// "0x" and the lowercase hexadecimal digits of `value`: how file headers write hashes.
std::string formatHex(std::uint64_t value);
/// Parses a whole string as a hexadecimal number, with or without "0x"; false if it is not one.
bool parseHex(std::string_view text, std::uint64_t& value);

}  // namespace barn::core
