#include "barn/controllers/flat_json.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <system_error>

namespace barn::controllers::json {

namespace {

// A cursor over one line; every error names the column, since a researcher debugging their
// controller sees only the message.
class Reader {
 public:
  explicit Reader(std::string_view text) : text_(text) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw ParseError(what + " at column " + std::to_string(pos_ + 1));
  }

  void skipSpace() {
    while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\t' || text_[pos_] == '\r' || text_[pos_] == '\n'))
      ++pos_;
  }
  bool atEnd() const { return pos_ >= text_.size(); }
  char peek() const { return atEnd() ? '\0' : text_[pos_]; }

  void expect(char c, const char* what) {
    if (peek() != c) fail(std::string("expected ") + what);
    ++pos_;
  }

  bool consumeWord(std::string_view word) {
    if (text_.substr(pos_, word.size()) != word) return false;
    pos_ += word.size();
    return true;
  }

  std::string string() {
    expect('"', "'\"'");
    std::string out;
    while (true) {
      if (atEnd()) fail("unterminated string");
      const char c = text_[pos_++];
      if (c == '"') return out;
      if (static_cast<unsigned char>(c) < 0x20) fail("control character in a string");
      if (c != '\\') {
        out += c;
        continue;
      }
      if (atEnd()) fail("unterminated escape");
      switch (text_[pos_++]) {
        case '"': out += '"'; break;
        case '\\': out += '\\'; break;
        case '/': out += '/'; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'n': out += '\n'; break;
        case 'r': out += '\r'; break;
        case 't': out += '\t'; break;
        case 'u': appendCodePoint(out, codePoint()); break;
        default: --pos_; fail("unknown escape");
      }
    }
  }

  double number() {
    // The JSON grammar: -?(0|[1-9][0-9]*)(\.[0-9]+)?([eE][+-]?[0-9]+)?  (no '+', no leading
    // zeros, no bare '.', no inf/nan), which from_chars alone would not enforce.
    const std::size_t start = pos_;
    if (peek() == '-') ++pos_;
    if (peek() == '0') {
      ++pos_;
    } else if (peek() >= '1' && peek() <= '9') {
      digits();
    } else {
      fail("expected a value");
    }
    if (peek() == '.') {
      ++pos_;
      if (!isDigit(peek())) fail("expected a digit after '.'");
      digits();
    }
    if (peek() == 'e' || peek() == 'E') {
      ++pos_;
      if (peek() == '+' || peek() == '-') ++pos_;
      if (!isDigit(peek())) fail("expected a digit in the exponent");
      digits();
    }
    double value = 0.0;
    const auto [end, ec] = std::from_chars(text_.data() + start, text_.data() + pos_, value);
    if (ec == std::errc::result_out_of_range) {
      pos_ = start;
      fail("number out of the double range");
    }
    if (ec != std::errc() || end != text_.data() + pos_) {
      pos_ = start;
      fail("malformed number");
    }
    return value;
  }

 private:
  static bool isDigit(char c) { return c >= '0' && c <= '9'; }
  void digits() {
    while (isDigit(peek())) ++pos_;
  }

  unsigned hex4() {
    unsigned value = 0;
    for (int i = 0; i < 4; ++i) {
      const char c = peek();
      unsigned digit = 0;
      if (c >= '0' && c <= '9') digit = static_cast<unsigned>(c - '0');
      else if (c >= 'a' && c <= 'f') digit = static_cast<unsigned>(c - 'a' + 10);
      else if (c >= 'A' && c <= 'F') digit = static_cast<unsigned>(c - 'A' + 10);
      else fail("expected four hex digits after \\u");
      value = value * 16 + digit;
      ++pos_;
    }
    return value;
  }

  // A \u escape, joining a UTF-16 surrogate pair into one code point.
  unsigned codePoint() {
    const unsigned first = hex4();
    if (first >= 0xDC00 && first <= 0xDFFF) fail("lone low surrogate");
    if (first < 0xD800 || first > 0xDBFF) return first;
    if (!consumeWord("\\u")) fail("high surrogate without its pair");
    const unsigned second = hex4();
    if (second < 0xDC00 || second > 0xDFFF) fail("high surrogate without its pair");
    return 0x10000 + ((first - 0xD800) << 10) + (second - 0xDC00);
  }

  static void appendCodePoint(std::string& out, unsigned cp) {
    const auto byte = [&](unsigned b) { out += static_cast<char>(static_cast<unsigned char>(b)); };
    if (cp < 0x80) {
      byte(cp);
    } else if (cp < 0x800) {
      byte(0xC0 | (cp >> 6));
      byte(0x80 | (cp & 0x3F));
    } else if (cp < 0x10000) {
      byte(0xE0 | (cp >> 12));
      byte(0x80 | ((cp >> 6) & 0x3F));
      byte(0x80 | (cp & 0x3F));
    } else {
      byte(0xF0 | (cp >> 18));
      byte(0x80 | ((cp >> 12) & 0x3F));
      byte(0x80 | ((cp >> 6) & 0x3F));
      byte(0x80 | (cp & 0x3F));
    }
  }

  std::string_view text_;
  std::size_t pos_ = 0;
};

}  // namespace

FlatObject parseFlatObject(std::string_view line) {
  Reader in(line);
  FlatObject members;
  in.skipSpace();
  in.expect('{', "a JSON object ('{')");
  in.skipSpace();
  if (in.peek() == '}') {
    in.expect('}', "'}'");
  } else {
    while (true) {
      in.skipSpace();
      std::string key = in.string();
      for (const auto& member : members)
        if (member.first == key) in.fail("duplicate key \"" + key + "\"");
      in.skipSpace();
      in.expect(':', "':'");
      in.skipSpace();
      Scalar value;
      const char c = in.peek();
      if (c == '"') value = in.string();
      else if (c == '{' || c == '[') in.fail("nested objects and arrays are not expected here");
      else if (in.consumeWord("true")) value = true;
      else if (in.consumeWord("false")) value = false;
      else if (in.consumeWord("null")) value = nullptr;
      else value = in.number();
      members.emplace_back(std::move(key), std::move(value));
      in.skipSpace();
      if (in.peek() == ',') {
        in.expect(',', "','");
        continue;
      }
      in.expect('}', "',' or '}'");
      break;
    }
  }
  in.skipSpace();
  if (!in.atEnd()) in.fail("unexpected text after the object");
  return members;
}

void appendNumber(std::string& out, double value) {
  if (!std::isfinite(value)) {
    out += "null";
    return;
  }
  if (value == 0.0 && std::signbit(value)) {
    out += "-0.0";
    return;
  }
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

void appendString(std::string& out, std::string_view text) {
  static constexpr char kHex[] = "0123456789abcdef";
  out += '"';
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (byte < 0x20) {
      out += "\\u00";
      out += kHex[byte >> 4];
      out += kHex[byte & 0xF];
    } else {
      out += c;
    }
  }
  out += '"';
}

}  // namespace barn::controllers::json
