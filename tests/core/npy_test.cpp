#include "barn/core/npy.hpp"

#include <sys/stat.h>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "barn/core/errors.hpp"

namespace barn::core {
namespace {

namespace fs = std::filesystem;
using testing::AllOf;
using testing::HasSubstr;
using testing::StartsWith;

// The files are built byte by byte here rather than with numpy, so the test needs no python and
// pins the on-disk layout independently of the reader under test.

void appendLittleEndian(std::string& out, std::uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out += static_cast<char>((value >> (8 * i)) & 0xff);
}

/// A .npy file: magic, version, header length, `dict` padded with spaces and ended by '\n' so
/// the whole header is a multiple of 64 bytes (as numpy writes it), then `data`.
std::string npyFile(const std::string& dict, const std::string& data, int major = 1) {
  const std::size_t preamble_size = major == 1 ? 10 : 12;
  std::string header = dict;
  while ((preamble_size + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';

  std::string out = "\x93NUMPY";
  out += static_cast<char>(major);
  out += '\0';
  appendLittleEndian(out, header.size(), major == 1 ? 2 : 4);
  return out + header + data;
}

std::string dictFor(const std::string& descr, const std::string& shape,
                    const std::string& fortran = "False") {
  return "{'descr': '" + descr + "', 'fortran_order': " + fortran + ", 'shape': " + shape + ", }";
}

std::string int64Data(const std::vector<std::int64_t>& values) {
  std::string out;
  for (const std::int64_t v : values) appendLittleEndian(out, static_cast<std::uint64_t>(v), 8);
  return out;
}

std::string float64Data(const std::vector<double>& values) {
  std::string out;
  for (const double v : values) appendLittleEndian(out, std::bit_cast<std::uint64_t>(v), 8);
  return out;
}

class NpyTest : public testing::Test {
 protected:
  void SetUp() override {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    // A random suffix keeps concurrent runs of the same test (e.g. two build trees) apart.
    dir_ = fs::temp_directory_path() / ("barn_npy_test_" + std::string(info->name()) + "_" +
                                        std::to_string(std::random_device{}()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, const std::string& bytes) {
    const fs::path path = dir_ / name;
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return path;
  }

  // Asserts `read(path)` throws an InputError starting with the path and containing `needle`.
  template <typename Read>
  void expectInputError(Read read, const fs::path& path, const std::string& needle) {
    try {
      read(path);
      ADD_FAILURE() << "no InputError for " << path << " (expected '" << needle << "')";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), AllOf(StartsWith(path.string() + ": "), HasSubstr(needle)));
    }
  }

  fs::path dir_;
};

std::vector<std::int64_t> gridValues() {
  std::vector<std::int64_t> values(900);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = (i * 7 + i / 30) % 3 == 0 ? 1 : 0;
  // Values that need every byte and the sign bit, to catch byte-order or width mistakes.
  values[1] = -1;
  values[31] = std::numeric_limits<std::int64_t>::min();
  values[899] = std::numeric_limits<std::int64_t>::max();
  values[450] = 0x0102030405060708;
  return values;
}

// ---------------------------------------------------------------------------------------------
// Arrays that read
// ---------------------------------------------------------------------------------------------

TEST_F(NpyTest, Int64Grid30x30RoundTrips) {
  const auto values = gridValues();
  const auto path = write("grid.npy", npyFile(dictFor("<i8", "(30, 30)"), int64Data(values)));
  const NpyInt64Array array = readNpyInt64(path);
  EXPECT_EQ(array.shape, (std::vector<std::size_t>{30, 30}));
  EXPECT_EQ(array.values, values);
}

TEST_F(NpyTest, Float64VectorRoundTripsExactDoubles) {
  const std::vector<double> values = {0.1, -1.0 / 3.0, 5e-324, 1.7976931348623157e308, -0.0};
  const auto path = write("metrics.npy", npyFile(dictFor("<f8", "(5,)"), float64Data(values)));
  const NpyFloat64Array array = readNpyFloat64(path);
  EXPECT_EQ(array.shape, (std::vector<std::size_t>{5}));
  ASSERT_EQ(array.values.size(), values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    // Bitwise, so -0.0 and the denormal have to come back exactly.
    EXPECT_EQ(std::bit_cast<std::uint64_t>(array.values[i]),
              std::bit_cast<std::uint64_t>(values[i]))
        << "value " << i;
  }
}

TEST_F(NpyTest, Float64Path34x2Reads) {
  std::vector<double> values(68);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = 0.15 * static_cast<double>(i) - 4.5;
  const auto path = write("path.npy", npyFile(dictFor("<f8", "(34, 2)"), float64Data(values)));
  const NpyFloat64Array array = readNpyFloat64(path);
  EXPECT_EQ(array.shape, (std::vector<std::size_t>{34, 2}));
  EXPECT_EQ(array.values, values);
}

TEST_F(NpyTest, KeysInAnyOrderWithExtraWhitespace) {
  const std::string dict = "{ \"shape\" :(2,3) ,\t'fortran_order':False,'descr' : '<i8'}";
  const std::vector<std::int64_t> values = {1, 2, 3, 4, 5, 6};
  const auto path = write("order.npy", npyFile(dict, int64Data(values)));
  const NpyInt64Array array = readNpyInt64(path);
  EXPECT_EQ(array.shape, (std::vector<std::size_t>{2, 3}));
  EXPECT_EQ(array.values, values);
}

TEST_F(NpyTest, ScalarShapeHoldsOneValue) {
  const auto path = write("scalar.npy", npyFile(dictFor("<f8", "()"), float64Data({2.5})));
  const NpyFloat64Array array = readNpyFloat64(path);
  EXPECT_TRUE(array.shape.empty());
  EXPECT_EQ(array.values, (std::vector<double>{2.5}));
}

TEST_F(NpyTest, EmptyArrayReads) {
  const auto path = write("empty.npy", npyFile(dictFor("<i8", "(0, 4)"), ""));
  const NpyInt64Array array = readNpyInt64(path);
  EXPECT_EQ(array.shape, (std::vector<std::size_t>{0, 4}));
  EXPECT_TRUE(array.values.empty());
}

TEST_F(NpyTest, Versions2And3UseFourByteHeaderLength) {
  const std::vector<std::int64_t> values = {7, -8, 9};
  for (const int major : {2, 3}) {
    const auto path = write("v" + std::to_string(major) + ".npy",
                            npyFile(dictFor("<i8", "(3,)"), int64Data(values), major));
    EXPECT_EQ(readNpyInt64(path).values, values) << "version " << major;
  }
}

// ---------------------------------------------------------------------------------------------
// Files that are rejected
// ---------------------------------------------------------------------------------------------

TEST_F(NpyTest, TruncatedDataThrows) {
  std::string data = int64Data(gridValues());
  data.resize(data.size() - 8);
  const auto path = write("grid_3.npy", npyFile(dictFor("<i8", "(30, 30)"), data));
  expectInputError(readNpyInt64, path,
                   "truncated: header says 900 values (7200 bytes), file has 7192");
}

TEST_F(NpyTest, TrailingDataThrows) {
  const auto path =
      write("extra.npy", npyFile(dictFor("<f8", "(5,)"), float64Data({1, 2, 3, 4, 5, 6})));
  expectInputError(readNpyFloat64, path,
                   "extra data after the array: header says 5 values (40 bytes), file has 48");
}

TEST_F(NpyTest, TruncatedHeaderThrows) {
  const std::string file = npyFile(dictFor("<i8", "(1,)"), "");
  const auto path = write("short_header.npy", file.substr(0, 40));
  expectInputError(readNpyInt64, path, "truncated header: preamble says 118 header bytes");
}

TEST_F(NpyTest, BadMagicThrows) {
  std::string file = npyFile(dictFor("<i8", "(1,)"), int64Data({1}));
  file[1] = 'M';
  const auto path = write("bad_magic.npy", file);
  expectInputError(readNpyInt64, path, "not a .npy file (bad magic)");
  expectInputError(readNpyInt64, write("text.npy", "P2\n30 30\n"), "not a .npy file (bad magic)");
  expectInputError(readNpyInt64, write("tiny.npy", "\x93NU"), "not a .npy file (bad magic)");
  expectInputError(readNpyInt64, write("empty_file.npy", ""), "not a .npy file (empty file)");
}

TEST_F(NpyTest, FoldersDevicesAndFifosAreRefused) {
  expectInputError(readNpyInt64, dir_, "is a folder, expected a file");
  expectInputError(readNpyInt64, "/dev/zero", "not a regular file");
  const fs::path fifo = dir_ / "fifo.npy";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expectInputError(readNpyFloat64, fifo, "not a regular file");  // instead of blocking on open
}

TEST_F(NpyTest, UnsupportedVersionThrows) {
  std::string file = npyFile(dictFor("<i8", "(1,)"), int64Data({1}));
  file[6] = '\x04';
  const auto path = write("v4.npy", file);
  expectInputError(readNpyInt64, path, "unsupported .npy format version 4.0");
}

TEST_F(NpyTest, WrongDtypeThrows) {
  const auto f8 = write("grid_3.npy", npyFile(dictFor("<f8", "(1,)"), float64Data({1.0})));
  expectInputError(readNpyInt64, f8, "dtype '<f8', expected '<i8'");

  const auto i8 = write("metrics.npy", npyFile(dictFor("<i8", "(1,)"), int64Data({1})));
  expectInputError(readNpyFloat64, i8, "dtype '<i8', expected '<f8'");

  // Same byte count or not, none of these is an int64 in little-endian order.
  for (const std::string descr : {"|i1", ">i8", "<i4", "<u8", "i8", "=i8"}) {
    const auto path = write("dtype.npy", npyFile(dictFor(descr, "(1,)"), int64Data({1})));
    expectInputError(readNpyInt64, path, "dtype '" + descr + "', expected '<i8'");
  }

  const std::string structured =
      "{'descr': [('x', '<i8')], 'fortran_order': False, 'shape': (1,), }";
  const auto path = write("structured.npy", npyFile(structured, int64Data({1})));
  expectInputError(readNpyInt64, path, "structured dtypes are not supported");
}

TEST_F(NpyTest, FortranOrderThrows) {
  const auto path =
      write("fortran.npy", npyFile(dictFor("<i8", "(2, 2)", "True"), int64Data({1, 2, 3, 4})));
  expectInputError(readNpyInt64, path, "fortran_order arrays are not supported");
}

TEST_F(NpyTest, MalformedHeaderDictThrows) {
  struct Case {
    std::string dict;
    std::string needle;
  };
  const std::vector<Case> cases = {
      {"{'descr': '<i8', 'fortran_order': False, }", "missing key 'shape'"},
      {"{'descr': '<i8', 'fortran_order': False, 'shape': (1,), 'extra': 1}",
       "unknown key 'extra'"},
      {"{'descr': '<i8', 'descr': '<i8', 'fortran_order': False, 'shape': (1,)}",
       "duplicate key 'descr'"},
      {"{'descr': '<i8', 'fortran_order': False, 'shape': (1)}", "shape (1) is not a tuple"},
      {"{'descr': '<i8', 'fortran_order': False, 'shape': (-1,)}",
       "expected a non-negative integer"},
      {"{'descr': '<i8', 'fortran_order': false, 'shape': (1,)}", "expected True or False"},
      {"{'descr': '<i8', 'fortran_order': False 'shape': (1,)}", "expected ',' or '}'"},
      {"{'descr': '<i8', 'fortran_order': False, 'shape': (1,)", "expected ',' or '}'"},
      {"{'descr: '<i8', 'fortran_order': False, 'shape': (1,)}", "expected ':'"},
      {"descr: <i8, fortran_order: False, shape: (1,)", "expected '{'"},
      {"{'descr': '<i8', 'fortran_order': False, 'shape': (1,)} x", "unexpected text after"},
  };
  for (const Case& c : cases) {
    const auto path = write("grid_7.npy", npyFile(c.dict, int64Data({1})));
    expectInputError(readNpyInt64, path, "malformed header: " + c.needle);
  }
}

TEST_F(NpyTest, MissingFileThrows) {
  expectInputError(readNpyInt64, dir_ / "does_not_exist.npy", "cannot read (missing or not readable)");
}

// ---------------------------------------------------------------------------------------------
// Writer
// ---------------------------------------------------------------------------------------------

TEST_F(NpyTest, WriterMakesNumpysFormat10Layout) {
  // Byte for byte the file npyFile() builds: the layout np.save writes for these arrays.
  const auto values = gridValues();
  EXPECT_EQ(formatNpyInt64({{30, 30}, values}), npyFile(dictFor("<i8", "(30, 30)"), int64Data(values)));
  const std::vector<double> metrics = {2.5, 4.75, 3.0, 5.0, 1.125};
  EXPECT_EQ(formatNpyFloat64({{5}, metrics}), npyFile(dictFor("<f8", "(5,)"), float64Data(metrics)));
  EXPECT_EQ(formatNpyInt64({{}, {42}}), npyFile(dictFor("<i8", "()"), int64Data({42})));
}

TEST_F(NpyTest, WrittenInt64ArraysOfEveryShapeReadBack) {
  const std::vector<std::vector<std::size_t>> shapes = {{}, {0}, {1}, {5}, {30, 30}, {43, 2}, {0, 2}, {2, 3, 4}, {1, 1, 1, 7}};
  for (const auto& shape : shapes) {
    std::size_t count = 1;
    for (const std::size_t dim : shape) count *= dim;
    std::vector<std::int64_t> values(count);
    for (std::size_t i = 0; i < count; ++i) values[i] = static_cast<std::int64_t>(i * 0x9E3779B97F4A7C15ull);
    const std::string bytes = formatNpyInt64({shape, values});
    const std::size_t header_end = bytes.size() - 8 * count;
    EXPECT_EQ(header_end % 64, 0u) << "data block starts 64-byte aligned, as numpy writes it";
    const NpyInt64Array back = readNpyInt64(write("a.npy", bytes));
    EXPECT_EQ(back.shape, shape);
    EXPECT_EQ(back.values, values);
  }
}

TEST_F(NpyTest, WrittenFloat64ArraysReadBackBitForBit) {
  const std::vector<double> special = {0.1, -1.0 / 3.0, 5e-324, -0.0, std::numeric_limits<double>::infinity(),
                                       std::numeric_limits<double>::quiet_NaN()};
  const std::vector<std::vector<std::size_t>> shapes = {{6}, {2, 3}, {3, 2}, {1, 6}, {6, 1, 1}};
  for (const auto& shape : shapes) {
    const NpyFloat64Array back = readNpyFloat64(write("f.npy", formatNpyFloat64({shape, special})));
    EXPECT_EQ(back.shape, shape);
    ASSERT_EQ(back.values.size(), special.size());
    for (std::size_t i = 0; i < special.size(); ++i) {
      EXPECT_EQ(std::bit_cast<std::uint64_t>(back.values[i]), std::bit_cast<std::uint64_t>(special[i])) << "value " << i;
    }
  }
}

TEST_F(NpyTest, WriterRefusesAShapeThatDoesNotMatchTheValues) {
  // (2, 3) holds 6 values, not 5.
  EXPECT_THROW(formatNpyInt64({{2, 3}, {1, 2, 3, 4, 5}}), std::invalid_argument);
  EXPECT_THROW(formatNpyFloat64({{}, {}}), std::invalid_argument);
}

}  // namespace
}  // namespace barn::core
