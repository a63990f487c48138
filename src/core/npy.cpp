#include "barn/core/npy.hpp"

#include <algorithm>
#include <bit>
#include <cstddef>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"

namespace barn::core {
namespace {

// The data block is read straight into the value vectors (and written straight from them),
// which is only correct when the host byte order matches the '<' (little-endian) dtypes.
static_assert(std::endian::native == std::endian::little,
              "readNpy*/formatNpy* move '<i8'/'<f8' data in place and need a little-endian host");

constexpr std::string_view kMagic = "\x93NUMPY";

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what) {
  throw InputError(path.string() + ": " + what);
}

/// What the header dict says about the array.
struct NpyHeader {
  std::string descr;  // dtype string, e.g. "<i8"
  bool fortran_order = false;
  std::vector<std::size_t> shape;  // empty for a 0-d array
};

// ---------------------------------------------------------------------------------------------
// Header dict parser
//
// The header is a Python dict literal written by numpy's repr(). We accept exactly the subset
// numpy produces (plus any whitespace and key order), rather than scanning for substrings, so a
// damaged or hand-edited header is reported instead of being half-understood.
// ---------------------------------------------------------------------------------------------

class DictParser {
 public:
  DictParser(const std::filesystem::path& path, std::string_view text, std::size_t file_offset)
      : path_(path), text_(text), file_offset_(file_offset) {}

  NpyHeader parse() {
    NpyHeader header;
    bool seen_descr = false;
    bool seen_fortran = false;
    bool seen_shape = false;
    auto mark_seen = [&](bool& seen, const std::string& key) {
      if (seen) malformed("duplicate key '" + key + "'");
      seen = true;
    };

    expect('{', "'{' opening the header dict");
    while (!consume('}')) {
      const std::string key = parseString("a quoted key");
      expect(':', "':' after key '" + key + "'");
      if (key == "descr") {
        mark_seen(seen_descr, key);
        skipSpace();
        // Structured dtypes are a list of fields; say so instead of "expected a string".
        if (peek() == '[') fail(path_, "structured dtypes are not supported");
        header.descr = parseString("a quoted dtype string for 'descr'");
      } else if (key == "fortran_order") {
        mark_seen(seen_fortran, key);
        header.fortran_order = parseBool();
      } else if (key == "shape") {
        mark_seen(seen_shape, key);
        header.shape = parseShape();
      } else {
        malformed("unknown key '" + key + "'");
      }
      // Python allows a trailing comma before '}', and numpy writes one.
      if (!consume(',')) {
        expect('}', "',' or '}' after the value of '" + key + "'");
        break;
      }
    }
    skipSpace();
    if (pos_ != text_.size()) malformed("unexpected text after the header dict");

    if (!seen_descr) malformed("missing key 'descr'");
    if (!seen_fortran) malformed("missing key 'fortran_order'");
    if (!seen_shape) malformed("missing key 'shape'");
    return header;
  }

 private:
  [[noreturn]] void malformed(const std::string& what) const {
    fail(path_, "malformed header: " + what);
  }

  // Names what sits at the cursor, with its file offset so the file can be checked in a hex dump.
  std::string describeHere() const {
    const std::string at = " at byte " + std::to_string(file_offset_ + pos_);
    if (pos_ >= text_.size()) return "end of header" + at;
    const auto c = static_cast<unsigned char>(text_[pos_]);
    if (c >= 0x20 && c < 0x7f) return std::string("'") + static_cast<char>(c) + "'" + at;
    return "byte value " + std::to_string(c) + at;
  }

  [[noreturn]] void expected(const std::string& what) const {
    malformed("expected " + what + ", found " + describeHere());
  }

  int peek() const { return pos_ < text_.size() ? static_cast<unsigned char>(text_[pos_]) : -1; }

  void skipSpace() {
    while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\t' ||
                                   text_[pos_] == '\n' || text_[pos_] == '\r')) {
      ++pos_;
    }
  }

  bool consume(char c) {
    skipSpace();
    if (peek() != static_cast<unsigned char>(c)) return false;
    ++pos_;
    return true;
  }

  void expect(char c, const std::string& what) {
    if (!consume(c)) expected(what);
  }

  // numpy writes dtype strings and keys without escapes, so a backslash is treated as damage.
  std::string parseString(const std::string& what) {
    skipSpace();
    const int quote = peek();
    if (quote != '\'' && quote != '"') expected(what);
    const std::size_t start = ++pos_;
    while (pos_ < text_.size() && text_[pos_] != static_cast<char>(quote)) {
      if (text_[pos_] == '\\' || text_[pos_] == '\n') {
        expected("a plain string without escapes or line breaks");
      }
      ++pos_;
    }
    if (pos_ >= text_.size()) malformed("unterminated string");
    return std::string(text_.substr(start, pos_++ - start));
  }

  bool parseBool() {
    skipSpace();
    for (const auto& [word, value] :
         {std::pair{std::string_view("True"), true}, std::pair{std::string_view("False"), false}}) {
      if (text_.substr(pos_, word.size()) == word && !isWordChar(pos_ + word.size())) {
        pos_ += word.size();
        return value;
      }
    }
    expected("True or False for 'fortran_order'");
  }

  bool isWordChar(std::size_t i) const {
    if (i >= text_.size()) return false;
    const char c = text_[i];
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  }

  std::size_t parseDimension() {
    skipSpace();
    if (peek() < '0' || peek() > '9') expected("a non-negative integer in 'shape'");
    std::size_t value = 0;
    while (peek() >= '0' && peek() <= '9') {
      const auto digit = static_cast<std::size_t>(peek() - '0');
      if (value > (std::numeric_limits<std::size_t>::max() - digit) / 10) {
        malformed("shape dimension too large at byte " + std::to_string(file_offset_ + pos_));
      }
      value = value * 10 + digit;
      ++pos_;
    }
    return value;
  }

  std::vector<std::size_t> parseShape() {
    expect('(', "a tuple '(' for 'shape'");
    std::vector<std::size_t> shape;
    bool trailing_comma = false;
    while (!consume(')')) {
      shape.push_back(parseDimension());
      trailing_comma = consume(',');
      if (!trailing_comma) {
        expect(')', "',' or ')' in 'shape'");
        break;
      }
    }
    // In Python "(5)" is the int 5, not a tuple; numpy always writes "(5,)".
    if (shape.size() == 1 && !trailing_comma) {
      malformed("shape (" + std::to_string(shape[0]) + ") is not a tuple, expected (" +
                std::to_string(shape[0]) + ",)");
    }
    return shape;
  }

  const std::filesystem::path& path_;
  std::string_view text_;
  std::size_t file_offset_;  // where text_ starts in the file, for error positions
  std::size_t pos_ = 0;      // cursor into text_
};

// ---------------------------------------------------------------------------------------------
// File layout
// ---------------------------------------------------------------------------------------------

std::uint32_t littleEndianUint(const unsigned char* bytes, int count) {
  std::uint32_t value = 0;
  for (int i = count - 1; i >= 0; --i) value = (value << 8) | bytes[i];
  return value;
}

// Reads exactly `size` bytes; the caller has already checked the file is long enough.
void readExactly(std::ifstream& in, const std::filesystem::path& path, char* out,
                 std::size_t size) {
  in.read(out, static_cast<std::streamsize>(size));
  if (static_cast<std::size_t>(in.gcount()) != size) fail(path, "read error");
}

template <typename Array>
Array readNpy(const std::filesystem::path& path, std::string_view expected_descr) {
  using Value = typename decltype(Array::values)::value_type;
  static_assert(sizeof(Value) == 8);

  // Folders, devices and fifos have no size to check the header against (and a fifo would
  // block on open): refused with the path.
  requireRegularFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open");

  // Knowing the size up front lets a bogus header be reported before anything is allocated.
  in.seekg(0, std::ios::end);
  const std::streamoff end = in.tellg();
  in.seekg(0, std::ios::beg);
  if (end < 0 || !in) fail(path, "cannot determine file size");
  const auto file_size = static_cast<std::size_t>(end);

  // Preamble: magic, major/minor version, header length (2 bytes in 1.0, 4 bytes in 2.0/3.0).
  if (file_size == 0) fail(path, "not a .npy file (empty file)");
  unsigned char preamble[12] = {};
  const std::size_t magic_bytes = std::min(file_size, kMagic.size());
  readExactly(in, path, reinterpret_cast<char*>(preamble), magic_bytes);
  if (magic_bytes < kMagic.size() ||
      std::string_view(reinterpret_cast<const char*>(preamble), kMagic.size()) != kMagic) {
    fail(path, "not a .npy file (bad magic)");
  }
  if (file_size < 8) fail(path, "truncated: file ends inside the .npy preamble");
  readExactly(in, path, reinterpret_cast<char*>(preamble) + 6, 2);
  const int major = preamble[6];
  const int minor = preamble[7];
  if (major < 1 || major > 3 || minor != 0) {
    fail(path, "unsupported .npy format version " + std::to_string(major) + "." +
                   std::to_string(minor) + " (supported: 1.0, 2.0, 3.0)");
  }
  const int length_bytes = major == 1 ? 2 : 4;
  const std::size_t preamble_size = 8 + static_cast<std::size_t>(length_bytes);
  if (file_size < preamble_size) fail(path, "truncated: file ends inside the .npy preamble");
  readExactly(in, path, reinterpret_cast<char*>(preamble) + 8,
              static_cast<std::size_t>(length_bytes));
  const std::size_t header_size = littleEndianUint(preamble + 8, length_bytes);
  if (header_size > file_size - preamble_size) {
    fail(path, "truncated header: preamble says " + std::to_string(header_size) +
                   " header bytes, file has " + std::to_string(file_size - preamble_size));
  }

  std::string header_text(header_size, '\0');
  readExactly(in, path, header_text.data(), header_size);
  const NpyHeader header = DictParser(path, header_text, preamble_size).parse();

  if (header.descr != expected_descr) {
    fail(path, "dtype '" + header.descr + "', expected '" + std::string(expected_descr) + "'");
  }
  if (header.fortran_order) fail(path, "fortran_order arrays are not supported");

  std::size_t count = 1;
  for (const std::size_t dim : header.shape) {
    if (dim != 0 && count > std::numeric_limits<std::size_t>::max() / sizeof(Value) / dim) {
      fail(path, "shape too large");
    }
    count *= dim;
  }
  const std::size_t data_bytes = count * sizeof(Value);
  const std::size_t available = file_size - preamble_size - header_size;
  const std::string says = "header says " + std::to_string(count) + " values (" +
                           std::to_string(data_bytes) + " bytes), file has " +
                           std::to_string(available);
  if (available < data_bytes) fail(path, "truncated: " + says);
  if (available > data_bytes) fail(path, "extra data after the array: " + says);

  Array array;
  array.shape = header.shape;
  array.values.resize(count);
  readExactly(in, path, reinterpret_cast<char*>(array.values.data()), data_bytes);
  return array;
}

// ---------------------------------------------------------------------------------------------
// Writer
// ---------------------------------------------------------------------------------------------

// numpy's repr of a shape tuple: "()", "(5,)", "(30, 30)".
std::string shapeRepr(const std::vector<std::size_t>& shape) {
  std::string text = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) text += (i ? ", " : "") + std::to_string(shape[i]);
  return text + (shape.size() == 1 ? ",)" : ")");
}

template <typename Array>
std::string formatNpy(const Array& array, std::string_view descr) {
  using Value = typename decltype(Array::values)::value_type;
  std::size_t count = 1;
  for (const std::size_t dim : array.shape) count *= dim;
  if (count != array.values.size()) {
    throw std::invalid_argument("formatNpy: shape " + shapeRepr(array.shape) + " holds " + std::to_string(count) +
                                " values, the array has " + std::to_string(array.values.size()));
  }
  // Format 1.0 as np.save writes it: the dict, spaces, and a newline ending the header at a
  // multiple of 64 bytes, so the data block starts aligned.
  constexpr std::size_t kPreambleSize = 10;  // magic, version, 2-byte header length
  std::string header = "{'descr': '" + std::string(descr) + "', 'fortran_order': False, 'shape': " +
                       shapeRepr(array.shape) + ", }";
  header.append(63 - (kPreambleSize + header.size()) % 64, ' ');
  header += '\n';
  if (header.size() > std::numeric_limits<std::uint16_t>::max()) {
    throw std::invalid_argument("formatNpy: shape " + shapeRepr(array.shape) + " needs a header longer than format 1.0 allows");
  }

  std::string out(kMagic);
  out += '\x01';  // major version
  out += '\x00';  // minor version
  out += static_cast<char>(header.size() & 0xff);
  out += static_cast<char>(header.size() >> 8);
  out += header;
  out.append(reinterpret_cast<const char*>(array.values.data()), array.values.size() * sizeof(Value));
  return out;
}

}  // namespace

NpyInt64Array readNpyInt64(const std::filesystem::path& path) {
  return readNpy<NpyInt64Array>(path, "<i8");
}

NpyFloat64Array readNpyFloat64(const std::filesystem::path& path) {
  return readNpy<NpyFloat64Array>(path, "<f8");
}

std::string formatNpyInt64(const NpyInt64Array& array) { return formatNpy(array, "<i8"); }

std::string formatNpyFloat64(const NpyFloat64Array& array) { return formatNpy(array, "<f8"); }

}  // namespace barn::core
