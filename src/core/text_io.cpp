#include "barn/core/text_io.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <unistd.h>

#include "barn/core/errors.hpp"

namespace barn::core {

void requireRegularFile(const std::filesystem::path& path) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) throw InputError(path.string() + ": cannot read (missing or not readable)");
  if (std::filesystem::is_directory(status)) throw InputError(path.string() + ": is a folder, expected a file");
  // A device (/dev/zero) never ends and a fifo blocks until someone writes to it: reading
  // either would hang or exhaust memory instead of failing.
  if (!std::filesystem::is_regular_file(status))
    throw InputError(path.string() + ": not a regular file (a device, fifo or socket), expected a file");
}

std::string readTextFile(const std::filesystem::path& path) {
  requireRegularFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot read (missing or not readable)");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw InputError(path.string() + ": cannot read (" + std::strerror(errno) + ")");
  return buffer.str();
}

namespace {

namespace fs = std::filesystem;

std::string systemError(const fs::path& path, const char* what, int error) {
  return path.string() + ": " + what + ": " + std::strerror(error);
}

// Writes the whole of `content` to `fd` and flushes it to the disk (fsync), so a power loss
// after the rename that follows leaves the new file, never a truncated one. IoError naming
// `path` (the file the caller means) on failure; `fd` stays open.
void writeAll(int fd, const fs::path& path, std::string_view content) {
  std::size_t written = 0;
  while (written < content.size()) {
    const ssize_t n = ::write(fd, content.data() + written, content.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw IoError(systemError(path, "write failed", n < 0 ? errno : ENOSPC));
    written += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) throw IoError(systemError(path, "write failed (fsync)", errno));
}

// Creates `path` (or truncates it) with `content`, flushed; on failure the file is removed.
void writeOrThrow(const fs::path& path, std::string_view content) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw IoError(systemError(path, "cannot write", errno));
  try {
    writeAll(fd, path, content);
  } catch (...) {
    ::close(fd);
    ::unlink(path.c_str());
    throw;
  }
  if (::close(fd) != 0) {
    const int error = errno;
    ::unlink(path.c_str());
    throw IoError(systemError(path, "write failed (close)", error));
  }
}

// Makes the renames in `dir` durable.
void syncFolder(const fs::path& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;  // best effort: the files themselves are on the disk
  ::fsync(fd);
  ::close(fd);
}

std::string uniqueSuffix() { return ".tmp-" + std::to_string(::getpid()); }

// `content` in an unnamed file of `folder` (O_TMPFILE), flushed, then linked as `temporary`.
// False if the file system cannot (no O_TMPFILE, no /proc): the caller writes `temporary`
// itself. A kill before the link leaves nothing behind; IoError if the write fails.
bool writeUnnamedThenLink(const fs::path& folder, const fs::path& temporary, const fs::path& path,
                          std::string_view content) {
  const int fd = ::open(folder.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0644);
  if (fd < 0) return false;
  try {
    writeAll(fd, path, content);
  } catch (...) {
    ::close(fd);
    throw;
  }
  const std::string self = "/proc/self/fd/" + std::to_string(fd);
  ::unlink(temporary.c_str());  // a complete leftover of a killed process with this pid
  const bool linked = ::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, temporary.c_str(), AT_SYMLINK_FOLLOW) == 0;
  ::close(fd);
  return linked;
}

void createFolder(const fs::path& folder) {
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (!ec) return;
  std::error_code link_ec;
  if (fs::is_symlink(fs::symlink_status(folder, link_ec)) && !fs::exists(folder, link_ec))
    throw IoError(folder.string() + ": cannot create folder: it is a symlink to a missing folder (" +
                  fs::read_symlink(folder, link_ec).string() + ")");
  throw IoError(folder.string() + ": cannot create folder: " + ec.message());
}

// A relative path that stays inside its folder, on one line.
bool insideFolder(const std::string& name) {
  const fs::path path(name);
  const bool escapes = std::any_of(path.begin(), path.end(), [](const fs::path& part) { return part == ".."; });
  return !name.empty() && !path.is_absolute() && !escapes && name.find('\n') == std::string::npos;
}

void checkName(const std::string& name) {
  if (!insideFolder(name))
    throw std::invalid_argument("writeFilesAtomic: '" + name + "' is not a path inside the folder");
}

// A commit note: the staging folder, then one "rename NAME" or "remove NAME" line each.
struct CommitNote {
  std::string staging;
  std::vector<std::string> renames;
  std::vector<std::string> removals;
};

std::string formatCommitNote(const CommitNote& note) {
  std::string text = "staging " + note.staging + "\n";
  for (const auto& name : note.renames) text += "rename " + name + "\n";
  for (const auto& name : note.removals) text += "remove " + name + "\n";
  return text;
}

CommitNote parseCommitNote(const fs::path& file) {
  const std::string text = readTextFile(file);
  CommitNote note;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    const std::string line = text.substr(start, end - start);
    start = end + 1;
    const std::size_t space = line.find(' ');
    const std::string verb = line.substr(0, space);
    const std::string name = space == std::string::npos ? std::string() : line.substr(space + 1);
    if (!insideFolder(name)) throw IoError(file.string() + ": damaged commit note (line '" + line + "')");
    if (verb == "staging") note.staging = name;
    else if (verb == "rename") note.renames.push_back(name);
    else if (verb == "remove") note.removals.push_back(name);
    else throw IoError(file.string() + ": damaged commit note (line '" + line + "')");
  }
  if (note.staging.empty()) throw IoError(file.string() + ": damaged commit note (no staging folder)");
  return note;
}

// Carries out a commit note in `dir`: each staged file still in the staging folder renamed
// into place (one already moved is skipped, so a second go after a kill is harmless), each
// removal deleted, then the note and the staging folder removed.
void completeCommit(const fs::path& dir, const CommitNote& note) {
  const fs::path staging = dir / note.staging;
  std::set<fs::path> folders = {dir};
  std::error_code ec;
  for (const auto& name : note.renames) {
    const fs::path from = staging / name;
    const fs::path to = dir / name;
    if (!fs::exists(fs::symlink_status(from, ec))) continue;
    createFolder(to.parent_path());
    folders.insert(to.parent_path());
    fs::rename(from, to, ec);
    if (ec) throw IoError(to.string() + ": cannot write (rename failed: " + ec.message() + ")");
  }
  for (const auto& name : note.removals) {
    fs::remove(dir / name, ec);
    if (ec && ec != std::errc::no_such_file_or_directory)
      throw IoError((dir / name).string() + ": cannot remove: " + ec.message());
    folders.insert((dir / name).parent_path());
  }
  for (const auto& folder : folders) syncFolder(folder);
  fs::remove(dir / kCommitNote, ec);
  if (ec) throw IoError((dir / kCommitNote).string() + ": cannot remove: " + ec.message());
  syncFolder(dir);
  fs::remove_all(staging, ec);
}

// "NAME.tmp-1234": a temporary of writeFileAtomic.
bool isTemporaryName(const std::string& name) {
  const std::size_t at = name.rfind(".tmp-");
  return at != std::string::npos && at + 5 < name.size() &&
         name.find_first_not_of("0123456789", at + 5) == std::string::npos;
}

// Removes the staging folders and temporaries that killed writers left in `dir`.
void removeLeftovers(const fs::path& dir) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    std::error_code entry_ec;
    if (name.starts_with(".staging.tmp-")) fs::remove_all(entry.path(), entry_ec);
    else if (isTemporaryName(name) && entry.is_regular_file(entry_ec)) fs::remove(entry.path(), entry_ec);
  }
}

}  // namespace

void writeFileAtomic(const fs::path& path, std::string_view content) {
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  const fs::path temporary = path.string() + uniqueSuffix();
  if (!writeUnnamedThenLink(folder, temporary, path, content)) writeOrThrow(temporary, content);
  std::error_code ec;
  fs::rename(temporary, path, ec);
  if (ec) {
    const std::string reason = ec.message();
    fs::remove(temporary, ec);
    throw IoError(path.string() + ": cannot write (rename failed: " + reason + ")");
  }
  syncFolder(folder);
}

void writeFilesAtomic(const fs::path& dir, const std::vector<FileContent>& files, const std::vector<std::string>& removals) {
  for (const auto& file : files) checkName(file.name);
  for (const auto& name : removals) checkName(name);
  createFolder(dir);
  std::error_code ec;
  CommitNote note;
  note.staging = ".staging" + uniqueSuffix();
  const fs::path staging = dir / note.staging;
  fs::remove_all(staging, ec);
  try {
    std::set<fs::path> staged_folders, target_folders;
    for (const auto& file : files) {
      const fs::path parent = (staging / file.name).parent_path();
      if (staged_folders.insert(parent).second) createFolder(parent);
      writeOrThrow(staging / file.name, file.content);
      note.renames.push_back(file.name);
    }
    createFolder(staging);  // an empty set (only removals) still has its staging folder
    for (const auto& folder : staged_folders) syncFolder(folder);
    // Every target folder exists before the commit, so a folder that cannot be made fails the
    // write before anything is in place.
    for (const auto& file : files) target_folders.insert((dir / file.name).parent_path());
    for (const auto& folder : target_folders) createFolder(folder);
    note.removals = removals;
    writeFileAtomic(dir / kCommitNote, formatCommitNote(note));
  } catch (...) {
    fs::remove_all(staging, ec);
    throw;
  }
  // Committed: from here the set lands whole, now or (after a kill) by finishInterruptedWrite.
  // Renames within one file system do not fail for lack of space.
  completeCommit(dir, note);
}

bool finishInterruptedWrite(const fs::path& dir) {
  std::error_code ec;
  bool finished = false;
  if (fs::exists(fs::symlink_status(dir / kCommitNote, ec))) {
    completeCommit(dir, parseCommitNote(dir / kCommitNote));
    finished = true;
  }
  removeLeftovers(dir);
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    std::error_code entry_ec;
    if (entry.is_directory(entry_ec) && !entry.is_symlink(entry_ec)) removeLeftovers(entry.path());
  }
  return finished;
}

void checkNoInterruptedWrite(const fs::path& dir) {
  std::error_code ec;
  if (fs::exists(fs::symlink_status(dir / kCommitNote, ec)))
    throw InputError(dir.string() + ": a write into this folder was interrupted (" + kCommitNote +
                     " is there), so it holds parts of two versions; the next barn command that writes it "
                     "completes the write (for a run record: barn run --resume " + dir.string() + ")");
}

std::string formatDouble(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

std::uint64_t fnv1a64(std::string_view text, std::uint64_t hash) {
  for (unsigned char ch : text) {
    hash ^= ch;
    hash *= 0x100000001b3ull;
  }
  return hash;
}

std::uint64_t fnv1a64File(const std::filesystem::path& path) {
  requireRegularFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot read (missing or not readable)");
  std::uint64_t hash = fnv1a64("");
  char buffer[65536];
  while (in) {
    in.read(buffer, sizeof buffer);
    hash = fnv1a64(std::string_view(buffer, static_cast<std::size_t>(in.gcount())), hash);
  }
  if (in.bad()) throw InputError(path.string() + ": cannot read (" + std::strerror(errno) + ")");
  return hash;
}

bool parseDouble(std::string_view text, double& value) {
  if (text.empty()) return false;
  const char* first = text.data();
  if (*first == '+') ++first;
  const auto result = std::from_chars(first, text.data() + text.size(), value);
  return result.ec == std::errc() && result.ptr == text.data() + text.size();
}

std::string formatHex(std::uint64_t value) {
  char digits[16];
  const auto result = std::to_chars(digits, digits + sizeof digits, value, 16);
  return "0x" + std::string(digits, result.ptr);
}

bool parseHex(std::string_view text, std::uint64_t& value) {
  if (text.rfind("0x", 0) == 0) text.remove_prefix(2);
  const auto result = std::from_chars(text.data(), text.data() + text.size(), value, 16);
  return result.ec == std::errc() && result.ptr == text.data() + text.size();
}

}  // namespace barn::core
