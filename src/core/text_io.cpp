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

std::string systemError(const std::filesystem::path& path, const char* what) {
  return path.string() + ": " + what + ": " + std::strerror(errno);
}

// Writes the whole file and flushes it to the disk (fsync) before it is renamed into place, so
// a power loss leaves the old file or the new one, never a truncated one.
void writeOrThrow(const std::filesystem::path& path, std::string_view content) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw IoError(systemError(path, "cannot write"));
  std::size_t written = 0;
  while (written < content.size()) {
    const ssize_t n = ::write(fd, content.data() + written, content.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string message = systemError(path, "write failed");
      ::close(fd);
      throw IoError(message);
    }
    written += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    const std::string message = systemError(path, "write failed (fsync)");
    ::close(fd);
    throw IoError(message);
  }
  if (::close(fd) != 0) throw IoError(systemError(path, "write failed (close)"));
}

// Makes the renames in `dir` durable.
void syncFolder(const std::filesystem::path& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;  // best effort: the files themselves are on the disk
  ::fsync(fd);
  ::close(fd);
}

std::string uniqueSuffix() { return ".tmp-" + std::to_string(::getpid()); }

}  // namespace

void writeFileAtomic(const std::filesystem::path& path, std::string_view content) {
  const std::filesystem::path temporary = path.string() + uniqueSuffix();
  writeOrThrow(temporary, content);
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    std::filesystem::remove(temporary, ec);
    throw IoError(path.string() + ": cannot write (rename failed: " + ec.message() + ")");
  }
  syncFolder(path.has_parent_path() ? path.parent_path() : std::filesystem::path("."));
}

void writeFilesAtomic(const std::filesystem::path& dir, const std::vector<FileContent>& files) {
  namespace fs = std::filesystem;
  for (const auto& file : files) {
    const fs::path name(file.name);
    const bool escapes = std::any_of(name.begin(), name.end(), [](const fs::path& part) { return part == ".."; });
    if (name.empty() || name.is_absolute() || escapes)
      throw std::invalid_argument("writeFilesAtomic: '" + file.name + "' is not a path inside the folder");
  }
  const auto create_folder = [](const fs::path& folder) {
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (ec) throw IoError(folder.string() + ": cannot create folder: " + ec.message());
  };
  create_folder(dir);
  std::error_code ec;
  const fs::path staging = dir / (".staging" + uniqueSuffix());
  fs::remove_all(staging, ec);
  std::set<fs::path> folders;  // dir and the subfolders the names hold
  try {
    create_folder(staging);
    for (const auto& file : files) {
      create_folder((staging / file.name).parent_path());
      writeOrThrow(staging / file.name, file.content);
    }
    // Every target folder exists before the first rename, so a folder that cannot be made
    // fails the write before anything is in place.
    for (const auto& file : files) folders.insert((dir / file.name).parent_path());
    for (const auto& folder : folders) create_folder(folder);
  } catch (...) {
    fs::remove_all(staging, ec);
    throw;
  }
  // Renames within one file system do not fail for lack of space, so the set lands whole.
  for (const auto& file : files) {
    fs::rename(staging / file.name, dir / file.name, ec);
    if (ec) {
      const std::string reason = ec.message();
      fs::remove_all(staging, ec);
      throw IoError((dir / file.name).string() + ": cannot write (rename failed: " + reason + ")");
    }
  }
  fs::remove_all(staging, ec);
  folders.insert(dir);
  for (const auto& folder : folders) syncFolder(folder);
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
