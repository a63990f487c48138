#include "barn/core/json_writer.hpp"

#include <cmath>
#include <cstdio>

#include "barn/core/text_io.hpp"

namespace barn::core {

void JsonWriter::newLine(std::size_t depth) {
  out_ += '\n';
  out_.append(2 * depth, ' ');
}

void JsonWriter::separate() {
  if (after_key_) {
    after_key_ = false;
    return;
  }
  if (scopes_.empty()) return;
  Scope& scope = scopes_.back();
  if (scope.layout == Layout::OneItemPerLine) {
    if (!scope.first) out_ += ',';
    newLine(scopes_.size());
  } else if (!scope.first) {
    out_ += ", ";
  }
  scope.first = false;
}

JsonWriter& JsonWriter::open(char bracket, Layout layout) {
  separate();
  out_ += bracket;
  scopes_.push_back({layout});
  return *this;
}

JsonWriter& JsonWriter::close(char bracket) {
  const bool own_line = scopes_.back().layout == Layout::OneItemPerLine;
  scopes_.pop_back();
  if (own_line) newLine(scopes_.size());
  out_ += bracket;
  return *this;
}

JsonWriter& JsonWriter::beginObject(Layout layout) { return open('{', layout); }
JsonWriter& JsonWriter::endObject() { return close('}'); }
JsonWriter& JsonWriter::beginArray(Layout layout) { return open('[', layout); }
JsonWriter& JsonWriter::endArray() { return close(']'); }

JsonWriter& JsonWriter::key(std::string_view name) {
  value(name);
  out_ += ": ";
  after_key_ = true;
  return *this;
}

JsonWriter& JsonWriter::value(std::string_view text) {
  separate();
  out_ += '"';
  for (char ch : text) {
    switch (ch) {
      case '"': out_ += "\\\""; break;
      case '\\': out_ += "\\\\"; break;
      case '\n': out_ += "\\n"; break;
      case '\t': out_ += "\\t"; break;
      default:
        if (static_cast<unsigned char>(ch) < 0x20) {
          char escaped[8];
          std::snprintf(escaped, sizeof(escaped), "\\u%04x", static_cast<unsigned>(ch));
          out_ += escaped;
        } else {
          out_ += ch;
        }
    }
  }
  out_ += '"';
  return *this;
}

JsonWriter& JsonWriter::value(double number) {
  if (!std::isfinite(number)) return null();
  separate();
  out_ += formatDouble(number);
  return *this;
}

JsonWriter& JsonWriter::value(std::int64_t number) {
  separate();
  out_ += std::to_string(number);
  return *this;
}

JsonWriter& JsonWriter::value(std::uint64_t number) {
  separate();
  out_ += std::to_string(number);
  return *this;
}

JsonWriter& JsonWriter::value(bool flag) {
  separate();
  out_ += flag ? "true" : "false";
  return *this;
}

JsonWriter& JsonWriter::null() {
  separate();
  out_ += "null";
  return *this;
}

}  // namespace barn::core
