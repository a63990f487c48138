#include "policy_header.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>

#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"

namespace barn::learning::header {

namespace {

constexpr const char* kEndHeader = "end_header";
constexpr const char* kUnknown = "unknown";  // a loss or plant not known (an imported policy)

std::uint32_t toLittle(std::uint32_t bits) {
  if constexpr (std::endian::native == std::endian::little) return bits;
  else return ((bits & 0xFFu) << 24) | ((bits & 0xFF00u) << 8) | ((bits >> 8) & 0xFF00u) | (bits >> 24);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Writing

void HeaderWriter::operator()(const char* key, double value) { line(key, core::formatDouble(value)); }

void HeaderWriter::operator()(const char* key, HexNumber number) { line(key, core::formatHex(number.value)); }

void HeaderWriter::operator()(const char* key, Loss loss) {
  line(key, std::isnan(loss.value) ? std::string(kUnknown) : core::formatDouble(loss.value));
}

void HeaderWriter::operator()(const char* key, PlantHash plant) {
  if (plant.value == 0) line(key, kUnknown);
  else (*this)(key, HexNumber{plant.value});
}

// ---------------------------------------------------------------------------------------------
// Reading

void HeaderReader::operator()(const char* key, FormatVersion& version) {
  version.value = static_cast<int>(integer(key, IntRange{0, 1000000}));
  if (version.value < 1 || version.value > version.newest)
    fail("unsupported version " + header_[key] + " (this build reads versions 1 to " + std::to_string(version.newest) + ")");
}

void HeaderReader::operator()(const char* key, FixedText fixed) {
  if (header_[key] != fixed.text) fail("header: " + std::string(key) + " is '" + header_[key] + "', expected '" + fixed.text + "'");
}

void HeaderReader::operator()(const char* key, HexNumber& number) {
  const std::string& text = header_[key];
  if (!core::parseHex(text, number.value)) fail("header: " + std::string(key) + " '" + text + "': expected hexadecimal");
}

void HeaderReader::operator()(const char* key, Loss& loss) {
  loss.value = header_[key] == kUnknown ? std::numeric_limits<double>::quiet_NaN() : number(key);
}

void HeaderReader::operator()(const char* key, PlantHash& plant) {
  if (header_[key] == kUnknown) {
    plant.value = 0;
    return;
  }
  HexNumber number;
  (*this)(key, number);
  if (number.value == 0) fail("header: plant_hash 0x0: write 'unknown' for an unknown plant");
  plant.value = number.value;
}

void HeaderReader::fail(const std::string& message) const { throw core::InputError(where_ + message); }

long long HeaderReader::integer(const char* key, IntRange range) const {
  const std::string& text = header_.at(key);
  long long value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || value < range.lo || value > range.hi)
    fail("header: " + std::string(key) + " '" + text + "': expected an integer in [" + std::to_string(range.lo) + ", " +
         std::to_string(range.hi) + "]");
  return value;
}

double HeaderReader::number(const char* key) const {
  const std::string& text = header_.at(key);
  double value = 0.0;
  if (!core::parseDouble(text, value) || !std::isfinite(value)) fail("header: " + std::string(key) + " '" + text + "': expected a number");
  return value;
}

// ---------------------------------------------------------------------------------------------
// Lines and payload

std::array<int, 4> parseArchitecture(const std::string& text, const std::string& example, const std::string& where) {
  std::array<int, 4> sizes{};
  const char* p = text.data();
  const char* end = text.data() + text.size();
  for (int k = 0; k < 4; ++k) {
    const auto [next, ec] = std::from_chars(p, end, sizes[k]);
    if (ec != std::errc() || sizes[k] < 1 || (k < 3 ? (next == end || *next != '-') : next != end))
      throw core::InputError(where + "header: architecture '" + text + "': expected inputs-hidden-hidden-outputs, e.g. " +
                             example);
    p = next + 1;
  }
  return sizes;
}

HeaderLines splitHeader(const std::string& file, const std::string& magic, const std::string& what,
                        const std::string& where) {
  const auto fail = [&](const std::string& message) { throw core::InputError(where + message); };
  const std::string first = "format: " + magic;
  const std::string wrong_magic = "wrong magic: the first line must be '" + first + "' (not " + what + ")";
  HeaderLines lines;
  std::size_t pos = 0;
  bool ended = false;
  while (pos < file.size()) {
    const std::size_t eol = file.find('\n', pos);
    if (eol == std::string::npos) break;
    const std::string line = file.substr(pos, eol - pos);
    pos = eol + 1;
    if (lines.order.empty() && line != first) fail(wrong_magic);
    if (line == kEndHeader) {
      ended = true;
      break;
    }
    const auto colon = line.find(": ");
    if (colon == std::string::npos) fail("header line '" + line.substr(0, 60) + "': expected 'key: value'");
    const std::string key = line.substr(0, colon);
    if (lines.values.count(key)) fail("header: duplicate key '" + key + "'");
    lines.values[key] = line.substr(colon + 2);
    lines.order.push_back(key);
  }
  if (lines.order.empty()) fail(wrong_magic);
  if (!ended) fail(std::string("truncated header: no '") + kEndHeader + "' line");
  lines.payload_offset = pos;
  return lines;
}

void checkKeys(const HeaderLines& lines, const std::vector<std::string>& keys, const std::string& where) {
  for (const std::string& key : lines.order) {
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) throw core::InputError(where + "header: unknown key '" + key + "'");
  }
  for (const std::string& key : keys) {
    if (!lines.values.count(key)) throw core::InputError(where + "header: missing key '" + key + "'");
  }
}

void appendFloats(std::string& out, const float* data, std::size_t count) {
  const std::size_t start = out.size();
  out.resize(start + 4 * count);
  char* p = out.data() + start;
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t bits = toLittle(std::bit_cast<std::uint32_t>(data[i]));
    std::memcpy(p, &bits, 4);
    p += 4;
  }
}

bool readFloats(const char* in, float* data, std::size_t count) {
  bool finite = true;
  for (std::size_t i = 0; i < count; ++i) {
    std::uint32_t bits;
    std::memcpy(&bits, in, 4);
    in += 4;
    data[i] = std::bit_cast<float>(toLittle(bits));
    finite = finite && std::isfinite(data[i]);
  }
  return finite;
}

}  // namespace barn::learning::header
