#pragma once
/// A small, strict reader of NumPy .npy files (format 1.0/2.0/3.0), enough for the BARN dataset:
/// little-endian int64 ('<i8') and float64 ('<f8') arrays in C order.
///
/// Anything else — wrong magic, an unsupported dtype, Fortran order, a header or data block
/// shorter than the shape says — is an InputError naming the file.

#include <cstdint>
#include <filesystem>
#include <vector>

namespace barn::core {

struct NpyInt64Array {
  std::vector<std::size_t> shape;     // e.g. {30, 30}
  std::vector<std::int64_t> values;   // row-major, product(shape) entries
};

struct NpyFloat64Array {
  std::vector<std::size_t> shape;
  std::vector<double> values;
};

/// Reads an int64 array; throws InputError (message starts with the path) on any problem.
NpyInt64Array readNpyInt64(const std::filesystem::path& path);
/// Reads a float64 array; throws InputError (message starts with the path) on any problem.
NpyFloat64Array readNpyFloat64(const std::filesystem::path& path);

}  // namespace barn::core
