#pragma once
// The text header and float32 payload shared by barnbench's network files (the LfLH MLP,
// learning::Policy; the LiCS transformer, learning::TransformerPolicy). Private to learning.
//
// A file is "key: value" lines, the first `format: <magic>`, ending with the line
// `end_header`, then the weights as little-endian float32. Each format lists its keys once, in
// file order, in a struct's visit(v); HeaderWriter writes them, HeaderReader converts and
// checks them (the first bad one throws an InputError naming the key and its text).

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace barn::learning::header {

// The range a header integer must lie in.
struct IntRange {
  long long lo, hi;
};

// The format version: the reader refuses versions outside [1, newest].
struct FormatVersion {
  int value;
  int newest;
};

// A text fixed by the format (an input or output convention): part of the contract, so a file
// written for another convention fails to load instead of driving the robot backwards.
struct FixedText {
  const char* text;
};

struct HexNumber {
  std::uint64_t value = 0;
};

// A plant hash; 0 (written "unknown") when the plant is not known (an imported policy, or one
// written before the LfLH format's version 3).
struct PlantHash {
  std::uint64_t value = 0;
};

// A loss; NaN (written "unknown") for an imported policy.
struct Loss {
  double value = 0.0;
};

class HeaderWriter {
 public:
  void operator()(const char* key, const std::string& value) { line(key, value); }
  void operator()(const char* key, FormatVersion version) { line(key, std::to_string(version.value)); }
  void operator()(const char* key, FixedText fixed) { line(key, fixed.text); }
  void operator()(const char* key, double value);
  void operator()(const char* key, HexNumber number);
  void operator()(const char* key, Loss loss);
  void operator()(const char* key, PlantHash plant);
  template <class Int>
  void operator()(const char* key, Int value, IntRange) {
    line(key, std::to_string(value));
  }

  /// The lines written so far and the closing `end_header` line.
  std::string text() const { return text_ + "end_header\n"; }

 private:
  void line(const char* key, const std::string& value) { text_ += std::string(key) + ": " + value + "\n"; }
  std::string text_;
};

// Converts the header's texts (checked against the key list already) into values; throws an
// InputError prefixed by `where` naming the key and its text at the first that does not convert.
class HeaderReader {
 public:
  HeaderReader(std::map<std::string, std::string>& header, std::string where) : header_(header), where_(std::move(where)) {}

  void operator()(const char* key, std::string& value) { value = header_[key]; }
  void operator()(const char* key, FormatVersion& version);
  void operator()(const char* key, FixedText fixed);
  void operator()(const char* key, double& value) { value = number(key); }
  void operator()(const char* key, HexNumber& number);
  void operator()(const char* key, Loss& loss);
  void operator()(const char* key, PlantHash& plant);
  template <class Int>
  void operator()(const char* key, Int& value, IntRange range) {
    value = static_cast<Int>(integer(key, range));
  }

 private:
  [[noreturn]] void fail(const std::string& message) const;
  long long integer(const char* key, IntRange range) const;
  double number(const char* key) const;

  std::map<std::string, std::string>& header_;
  std::string where_;
};

// The header's keys in file order.
struct KeyList {
  std::vector<std::string> keys;
  template <class T, class... Range>
  void operator()(const char* key, const T&, Range...) {
    keys.emplace_back(key);
  }
};

template <class Fields>
std::vector<std::string> keysOf() {
  KeyList list;
  Fields().visit(list);
  return list.keys;
}

/// An `architecture` value "inputs-hidden-hidden-outputs" (four whole numbers >= 1) as its four
/// sizes; InputError prefixed by `where` otherwise, showing `example`.
std::array<int, 4> parseArchitecture(const std::string& text, const std::string& example, const std::string& where);

/// A file's header lines as read.
struct HeaderLines {
  std::map<std::string, std::string> values;  // key -> value text
  std::vector<std::string> order;             // keys in file order
  std::size_t payload_offset = 0;             // first byte after the end_header line
};

/// Reads the "key: value" lines of `file` up to end_header: InputErrors prefixed by `where` for
/// a first line other than `format: <magic>` ("wrong magic: ... (not <what>)"), a line that is
/// not "key: value", a duplicate key, a missing end_header.
HeaderLines splitHeader(const std::string& file, const std::string& magic, const std::string& what,
                        const std::string& where);

/// InputError prefixed by `where` for the first key not in `keys`, then for the first of
/// `keys` missing.
void checkKeys(const HeaderLines& lines, const std::vector<std::string>& keys, const std::string& where);

/// A policy file's header read into `fields` (a struct with visit()): the magic line, no
/// unknown or missing key (`keys`), every value converted; InputError prefixed by `where`
/// otherwise. Returns the split lines, whose payload_offset says where the weights begin.
template <class Fields>
HeaderLines readHeader(const std::string& file, const std::string& magic, const std::string& what,
                       const std::vector<std::string>& keys, const std::string& where, Fields& fields) {
  HeaderLines lines = splitHeader(file, magic, what, where);
  checkKeys(lines, keys, where);
  HeaderReader reader(lines.values, where);
  fields.visit(reader);
  return lines;
}

/// Appends `count` floats as little-endian float32.
void appendFloats(std::string& out, const float* data, std::size_t count);
/// Reads `count` little-endian float32 from `in` into `data`; true if all are finite.
bool readFloats(const char* in, float* data, std::size_t count);

}  // namespace barn::learning::header
