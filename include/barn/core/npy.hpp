#pragma once
/// A small, strict reader and writer of NumPy .npy files, enough for the BARN dataset:
/// little-endian int64 ('<i8') and float64 ('<f8') arrays in C order.
///
/// The reader takes format 1.0/2.0/3.0. Anything else — wrong magic, an unsupported dtype,
/// Fortran order, a header or data block shorter than the shape says — is an InputError naming
/// the file. The writer makes what numpy's np.save makes for such an array: format 1.0, the
/// header dict padded with spaces and a newline to a multiple of 64 bytes.

#include <cstdint>
#include <filesystem>
#include <string>
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

/// The bytes of an int64 array's .npy file (write them with writeFileAtomic or
/// writeFilesAtomic). std::invalid_argument if `values` does not hold product(shape) entries.
std::string formatNpyInt64(const NpyInt64Array& array);
/// The bytes of a float64 array's .npy file; std::invalid_argument as formatNpyInt64.
std::string formatNpyFloat64(const NpyFloat64Array& array);

}  // namespace barn::core
