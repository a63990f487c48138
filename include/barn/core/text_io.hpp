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

/// Writes `content` to `path` so a reader never sees a half-written file: the bytes go to an
/// unnamed file in the same folder (O_TMPFILE; a named `NAME.tmp-PID` where the file system
/// has none), flushed to the disk (fsync), then linked and renamed into place, and the folder
/// flushed. A failure or a kill leaves the old file and no temporary (at most a complete
/// `NAME.tmp-PID` if the kill falls between the link and the rename). Throws IoError naming
/// the path and the system's reason on failure (disk full: exit 1, not bad input).
void writeFileAtomic(const std::filesystem::path& path, std::string_view content);

/// Writes several files into `dir` (created if missing) as one set, all or nothing, and
/// deletes `removals` (names in `dir`, missing ones ignored) with them:
///   1. every file is written into a staging folder in `dir` (`.staging.tmp-PID`), flushed;
///   2. a commit note (`.barn.commit`) listing the renames and removals is written, flushed;
///   3. the files are renamed into place, the removals deleted, the note and staging removed.
/// A failure or kill before 2 leaves `dir` as it was (and a staging folder that the next
/// locked writer removes); a kill during 3 leaves the note, and the set is completed by
/// finishInterruptedWrite, while readers refuse the folder (checkNoInterruptedWrite). A name
/// may hold subfolders ("grid_files/grid_0.npy"). IoError on failure, as writeFileAtomic;
/// std::invalid_argument for an absolute name, one with "..", or one with a newline.
/// Two processes must not write one folder at once: bench::RecordWriter locks it.
struct FileContent {
  std::string name;     // path relative to the folder, e.g. "index.csv" or "grid_files/grid_0.npy"
  std::string content;
};
void writeFilesAtomic(const std::filesystem::path& dir, const std::vector<FileContent>& files,
                      const std::vector<std::string>& removals = {});

/// The commit note writeFilesAtomic leaves in a folder while a set lands.
inline constexpr const char* kCommitNote = ".barn.commit";

/// For a writer that holds `dir` alone (bench::RecordWriter): completes a set write that a
/// kill interrupted (its commit note), then removes what killed writers left behind: staging
/// folders and `*.tmp-PID` files in `dir` and its immediate subfolders. Returns true if a set
/// was completed. IoError if that fails.
bool finishInterruptedWrite(const std::filesystem::path& dir);

/// InputError naming `dir` if a set write into it was interrupted (a commit note is there):
/// its files are a mix of two sets until a writer of the folder completes it.
void checkNoInterruptedWrite(const std::filesystem::path& dir);

/// Shortest decimal text that reads back as exactly `value` (std::to_chars round trip).
std::string formatDouble(double value);

/// 64-bit FNV-1a hash of `text`, continuing from `hash` (to digest several texts in order).
std::uint64_t fnv1a64(std::string_view text, std::uint64_t hash = 0xcbf29ce484222325ull);

/// 64-bit FNV-1a hash of a regular file's bytes, read in pieces (a large file is not loaded
/// whole); InputError naming the file if it cannot be read (see requireRegularFile).
std::uint64_t fnv1a64File(const std::filesystem::path& path);

/// Parses a whole string as a double (std::from_chars); false if it is not one.
bool parseDouble(std::string_view text, double& value);

/// "0x" and the lowercase hexadecimal digits of `value`: how file headers write hashes.
std::string formatHex(std::uint64_t value);
/// Parses a whole string as a hexadecimal number, with or without "0x"; false if it is not one.
bool parseHex(std::string_view text, std::uint64_t& value);

}  // namespace barn::core
