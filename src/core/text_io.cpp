#include "barn/core/text_io.hpp"

#include <charconv>
#include <fstream>
#include <sstream>
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
  return buffer.str();
}

namespace {

void writeOrThrow(const std::filesystem::path& path, std::string_view content) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw InputError(path.string() + ": cannot write");
  out.write(content.data(), static_cast<std::streamsize>(content.size()));
  out.close();
  if (!out) throw InputError(path.string() + ": write failed");
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
    throw InputError(path.string() + ": cannot write (rename failed)");
  }
}

void writeFilesAtomic(const std::filesystem::path& dir, const std::vector<FileContent>& files) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create folder: " + ec.message());
  const std::filesystem::path staging = dir / (".staging" + uniqueSuffix());
  std::filesystem::remove_all(staging, ec);
  std::filesystem::create_directories(staging, ec);
  if (ec) throw InputError(staging.string() + ": cannot create folder: " + ec.message());
  try {
    for (const auto& file : files) writeOrThrow(staging / file.name, file.content);
  } catch (...) {
    std::filesystem::remove_all(staging, ec);
    throw;
  }
  // Renames within one file system do not fail for lack of space, so the set lands whole.
  for (const auto& file : files) {
    std::filesystem::rename(staging / file.name, dir / file.name, ec);
    if (ec) {
      std::filesystem::remove_all(staging, ec);
      throw InputError((dir / file.name).string() + ": cannot write (rename failed)");
    }
  }
  std::filesystem::remove_all(staging, ec);
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

}  // namespace barn::core
