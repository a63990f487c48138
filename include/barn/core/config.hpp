#pragma once
/// Config files: YAML read into plain structs through one field list per struct.
///
/// Every config struct has a `visit(V& v)` member listing its fields once:
///
///     struct LidarConfig {
///       int beams = 720;            // [-]
///       double range_max = 30.0;    // [m]
///       template <class V> void visit(V& v) { v("beams", beams); v("range_max", range_max); }
///     };
///
/// The same list drives reading (ConfigReader: strict, unknown keys are errors naming the full
/// key path, missing keys keep the struct default) and writing back (ConfigWriter, for the
/// effective config in a run's manifest). yaml-cpp stays inside config.cpp: ConfigNode is an
/// opaque handle.
///
/// A field of a type that is neither a scalar nor a struct with a field list (a grid cell
/// written `[row, col]`, say) reads itself: the reader calls
/// `readConfigValue(const ConfigNode&, T&, Errors&)`, found by argument-dependent lookup,
/// which records its problems with `node.where()`.
///
/// An enum field is read and written by name. Its namespace declares the names, in the
/// enum's order (the first for value 0, ...):
///
///     enum class SafetyCheck { Front, Fi };
///     std::span<const std::string_view> enumNames(SafetyCheck);

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "barn/core/errors.hpp"

namespace barn::core {

/// An enum with names for config files (see the header comment).
template <class E>
concept NamedEnum = std::is_enum_v<E> && requires(E e) {
  { enumNames(e) } -> std::convertible_to<std::span<const std::string_view>>;
};

/// The name of `value`, e.g. for messages and labels.
template <NamedEnum E>
std::string_view enumName(E value) {
  return enumNames(value)[static_cast<std::size_t>(value)];
}

/// The value named `name`, if any.
template <NamedEnum E>
bool enumFromName(std::string_view name, E& value) {
  const std::span<const std::string_view> names = enumNames(value);
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) {
      value = static_cast<E>(i);
      return true;
    }
  return false;
}

/// A node of a parsed YAML document, remembering its key path ("controller.fi.offset") and
/// the file it came from.
class ConfigNode {
 public:
  ConfigNode();
  ~ConfigNode();
  ConfigNode(const ConfigNode&);
  ConfigNode& operator=(const ConfigNode&);

  /// Parses a YAML file; InputError naming the file if it is unreadable or not YAML.
  static ConfigNode parseFile(const std::filesystem::path& path);
  /// Parses YAML text; `source_name` prefixes every error message.
  static ConfigNode parseString(const std::string& text, const std::string& source_name);

  bool isNull() const;  // absent or empty document
  bool isMap() const;
  bool isSequence() const;
  /// Elements of a sequence (0 if this is not one).
  std::size_t size() const;
  bool has(std::string_view key) const;
  ConfigNode child(std::string_view key) const;
  /// Element `index` of a sequence (a null node past the end or if this is not a sequence).
  ConfigNode element(std::size_t index) const;
  /// Keys in file order, duplicates included; InputError naming the file and line if a key is
  /// a list or a map (`[1]: 2`) rather than a name.
  std::vector<std::string> keys() const;

  /// Every scalar value under this node (list elements and map values, not keys), in document
  /// order: e.g. to find the files a config names.
  std::vector<std::string> scalarValues() const;

  /// Scalar reads; false if the node is not a scalar of that type.
  bool read(double& value) const;
  bool read(int& value) const;
  bool read(std::uint64_t& value) const;
  bool read(bool& value) const;
  bool read(std::string& value) const;
  bool read(std::vector<double>& value) const;
  bool read(std::vector<std::string>& value) const;

  /// Sets `dotted_key` ("safety.fi.offset") to the YAML scalar `value_text`, creating maps as
  /// needed: command-line overrides for runs and sweeps.
  void set(const std::string& dotted_key, const std::string& value_text);

  /// The node as YAML text (block style).
  std::string toYaml() const;

  const std::string& path() const { return path_; }      // "" for the root
  const std::string& source() const { return source_; }  // file name or label
  /// "file: key.path" for error messages.
  std::string where(std::string_view key = {}) const;

 private:
  struct Impl;
  std::shared_ptr<Impl> impl_;
  std::string path_;
  std::string source_;
};

/// A type that reads itself from a node (see the header comment).
template <class T>
concept SelfReading = requires(const ConfigNode& node, T& value, Errors& errors) { readConfigValue(node, value, errors); };

/// What a missing key means: configs keep the struct default; data files (a world file)
/// must give every field.
enum class MissingKeys { KeepDefault, Error };

/// Reads a struct's fields from a map node (see the header comment). Errors are collected.
class ConfigReader {
 public:
  ConfigReader(const ConfigNode& node, Errors& errors, MissingKeys missing = MissingKeys::KeepDefault);

  template <class T>
  void operator()(const char* key, T& value) {
    seen_.emplace_back(key);
    if (!node_.has(key)) {
      if (missing_ == MissingKeys::Error) errors_.add(node_.where(key), "missing");
      return;
    }
    const ConfigNode child = node_.child(key);
    if constexpr (SelfReading<T>) {
      readConfigValue(child, value, errors_);
    } else if constexpr (requires { value.visit(*this); }) {
      if (!child.isMap()) {
        errors_.add(child.where(), "expected a map");
        return;
      }
      ConfigReader nested(child, errors_, missing_);
      value.visit(nested);
      nested.finish();
    } else if constexpr (requires(ConfigReader& r) { value.front().visit(r); }) {
      readList(child, value);
    } else if constexpr (NamedEnum<T>) {
      std::string name;
      if (!child.read(name) || !enumFromName(name, value)) {
        std::string names;
        for (std::string_view n : enumNames(value)) names += (names.empty() ? "" : ", ") + std::string(n);
        errors_.add(child.where(), "expected one of " + names);
      }
    } else {
      if (!child.read(value)) errors_.add(child.where(), std::string("expected ") + typeName(value) + given(child));
    }
  }

  /// Records "unknown key" and "duplicate key" errors for the keys no field claimed.
  void finish();

 private:
  // A list of structs with field lists, each element a map ("parameters[1].key").
  template <class T>
  void readList(const ConfigNode& list, std::vector<T>& values) {
    if (!list.isSequence()) {
      errors_.add(list.where(), "expected a list of maps");
      return;
    }
    std::vector<T> read(list.size());
    for (std::size_t i = 0; i < read.size(); ++i) {
      const ConfigNode element = list.element(i);
      if (!element.isMap()) {
        errors_.add(element.where(), "expected a map");
        continue;
      }
      ConfigReader nested(element, errors_, missing_);
      read[i].visit(nested);
      nested.finish();
    }
    values = std::move(read);
  }

  // Not-a-number and infinities are rejected too, so say so.
  // ", got 'text'" for a scalar node, so the message shows what was written; "" otherwise.
  static std::string given(const ConfigNode& node);

  static const char* typeName(const double&) { return "a finite number"; }
  static const char* typeName(const int&) { return "an integer"; }
  static const char* typeName(const std::uint64_t&) { return "an unsigned integer"; }
  static const char* typeName(const bool&) { return "true or false"; }
  static const char* typeName(const std::string&) { return "a string"; }
  static const char* typeName(const std::vector<double>&) { return "a list of numbers"; }
  static const char* typeName(const std::vector<std::string>&) { return "a list of strings"; }

  ConfigNode node_;
  Errors& errors_;
  MissingKeys missing_;
  std::vector<std::string> seen_;
};

/// Writes a struct's fields as YAML text (block style, two-space indent).
class ConfigWriter {
 public:
  explicit ConfigWriter(int indent = 0) : indent_(indent) {}

  template <class T>
  void operator()(const char* key, const T& value) {
    if constexpr (requires(ConfigWriter& w) { const_cast<T&>(value).visit(w); }) {
      line(key, "");
      ConfigWriter nested(indent_ + 2);
      const_cast<T&>(value).visit(nested);
      text_ += nested.text_;
    } else if constexpr (requires(ConfigWriter& w) { const_cast<T&>(value).front().visit(w); }) {
      writeList(key, value);
    } else if constexpr (NamedEnum<T>) {
      line(key, scalar(std::string(enumName(value))));
    } else {
      line(key, scalar(value));
    }
  }

  const std::string& text() const { return text_; }

 private:
  // A block list of maps, each element's first field after "- ".
  template <class T>
  void writeList(const char* key, const std::vector<T>& values) {
    line(key, values.empty() ? "[]" : "");
    for (const T& element : values) {
      ConfigWriter nested(indent_ + 4);
      const_cast<T&>(element).visit(nested);
      if (nested.text_.empty()) nested.text_ = std::string(static_cast<std::size_t>(indent_ + 4), ' ') + "{}\n";
      text_ += nested.text_.replace(static_cast<std::size_t>(indent_ + 2), 2, "- ");
    }
  }

  void line(const char* key, const std::string& value);
  static std::string scalar(double value);
  static std::string scalar(int value);
  static std::string scalar(std::uint64_t value);
  static std::string scalar(bool value);
  static std::string scalar(const std::string& value);
  static std::string scalar(const std::vector<double>& value);
  static std::string scalar(const std::vector<std::string>& value);

  int indent_;
  std::string text_;
};

/// Reads `T` from `node` (defaults for missing keys) and throws one InputError listing every
/// problem, each with its key path.
template <class T>
T readConfig(const ConfigNode& node) {
  T config;
  Errors errors;
  if (!node.isNull()) {
    if (!node.isMap()) {
      errors.add(node.where(), "expected a map");
    } else {
      ConfigReader reader(node, errors);
      config.visit(reader);
      reader.finish();
    }
  }
  errors.throwIfAny();
  return config;
}

/// The YAML text of a config struct (for manifests and `--print-config`).
template <class T>
std::string writeConfig(const T& config) {
  ConfigWriter writer;
  const_cast<T&>(config).visit(writer);
  return writer.text();
}

}  // namespace barn::core
