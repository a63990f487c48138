#include "repo_paths.hpp"

#include <unistd.h>

namespace barn::cli {

std::filesystem::path repoPath(const std::string& name) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(fs::path(name), ec)) return name;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec && fs::exists(exe.parent_path().parent_path() / name, ec)) return exe.parent_path().parent_path() / name;
  return fs::path(BARN_SOURCE_DIR) / name;
}

}  // namespace barn::cli
