#pragma once
/// A minimal JSON text builder for barnbench's JSON outputs (the CLI's --json, a record's
/// summary.json): objects, arrays, numbers, strings. Numbers are written as they read back
/// (core::formatDouble), non-finite ones as null.
///
/// An object or array is written on one line, or with `Layout::OneItemPerLine` each member or
/// element on a line of its own, indented two spaces per level, for files people read.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace barn::core {

class JsonWriter {
 public:
  enum class Layout { OneLine, OneItemPerLine };

  JsonWriter& beginObject(Layout layout = Layout::OneLine);
  JsonWriter& endObject();
  JsonWriter& beginArray(Layout layout = Layout::OneLine);
  JsonWriter& endArray();
  JsonWriter& key(std::string_view name);
  JsonWriter& value(std::string_view text);
  JsonWriter& value(const char* text) { return value(std::string_view(text)); }
  JsonWriter& value(double number);  // non-finite numbers are written as null
  JsonWriter& value(std::int64_t number);
  JsonWriter& value(int number) { return value(static_cast<std::int64_t>(number)); }
  JsonWriter& value(std::uint64_t number);
  JsonWriter& value(bool flag);
  JsonWriter& null();

  const std::string& str() const { return out_; }

 private:
  struct Scope {
    Layout layout;
    bool first = true;  // nothing written in it yet
  };

  void separate();
  JsonWriter& open(char bracket, Layout layout);
  JsonWriter& close(char bracket);
  void newLine(std::size_t depth);

  std::string out_;
  std::vector<Scope> scopes_;  // one per open object/array
  bool after_key_ = false;
};

}  // namespace barn::core
