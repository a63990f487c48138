#pragma once
// A folder of its own in the temp folder for one test, removed with everything in it when the
// test ends. The random suffix keeps concurrent runs (ctest -j, two build trees) apart.

#include <filesystem>
#include <random>
#include <string>
#include <system_error>

namespace barn::test {

class ScratchDir {
 public:
  explicit ScratchDir(const std::string& stem) {
    std::random_device device;
    path_ = std::filesystem::temp_directory_path() /
            (stem + "_" + std::to_string(device()) + "_" + std::to_string(device()));
    std::filesystem::create_directories(path_);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace barn::test
