// Fuzz target: the .npy reader (core::readNpyInt64 / readNpyFloat64).
//
// The reader takes a path (it checks the header against the file size before allocating), so
// each input is written to a file of this process first. Bad input must end in
// core::InputError naming the file.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "barn/core/errors.hpp"
#include "barn/core/npy.hpp"

namespace {

// tmpfs if there is one: the input is rewritten for every run, and a disk file system may
// flush each rewrite of a truncated file (ext4's auto_da_alloc), which makes runs slow.
std::filesystem::path scratchFolder() {
  std::error_code ec;
  if (std::filesystem::is_directory("/dev/shm", ec)) return "/dev/shm";
  return std::filesystem::temp_directory_path();
}

// One file per process: several fuzzers (or -jobs) may run side by side. Defined before the
// remover, so it is destroyed after it.
const std::filesystem::path kInput = scratchFolder() / ("barn_fuzz_npy_" + std::to_string(::getpid()) + ".npy");

struct RemoveAtExit {
  ~RemoveAtExit() {
    std::error_code ec;
    std::filesystem::remove(kInput, ec);
  }
} remove_at_exit;

template <class Array>
void expectArrayOrInputError(Array (*read)(const std::filesystem::path&)) {
  try {
    const Array array = read(kInput);
    std::size_t count = 1;
    for (const std::size_t dim : array.shape) count *= dim;
    if (array.values.size() != count) {
      std::fprintf(stderr, "fuzz finding: %zu values for a shape of %zu\n", array.values.size(), count);
      std::abort();
    }
  } catch (const barn::core::InputError& e) {
    if (std::string(e.what()).rfind(kInput.string() + ": ", 0) != 0) {
      std::fprintf(stderr, "fuzz finding: the error does not start with the file name: %s\n", e.what());
      std::abort();
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  {
    std::ofstream out(kInput, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    if (!out) {
      std::fprintf(stderr, "fuzz setup: cannot write %s\n", kInput.c_str());
      std::abort();
    }
  }
  expectArrayOrInputError(&barn::core::readNpyInt64);
  expectArrayOrInputError(&barn::core::readNpyFloat64);
  return 0;
}
