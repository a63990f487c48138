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
///
/// A field's schema (its unit, the values it may take and one line of doc) is written once,
/// as a third argument of its visit call:
///
///     v("range_max", range_max, {.unit = "m", .range = kPositive, .doc = "farthest return"});
///
/// Every visitor takes the call with or without it. ConfigValidator checks the ranges
/// (validateFields), so a struct's validate() keeps only its cross-field rules; schemaOf lists
/// key, value, unit, range and doc (`barn config <controller>`, sweep axes). The unit is the
/// only place a field's unit is stated in code.

#include <cstdint>
#include <filesystem>
#include <limits>
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

/// The values a numeric field may take: an interval, each end closed, open or absent (the
/// default, all of them).
struct Range {
  double low = -std::numeric_limits<double>::infinity();
  double high = std::numeric_limits<double>::infinity();
  bool low_open = false;   // low itself excluded
  bool high_open = false;  // high itself excluded

  bool contains(double value) const {
    return (low_open ? value > low : value >= low) && (high_open ? value < high : value <= high);
  }
  bool unbounded() const { return low == -std::numeric_limits<double>::infinity() && high == std::numeric_limits<double>::infinity(); }
  /// "> 0", ">= 2", "< 0", "<= 1", "in [0, 1]", "in (0, 1]"; "" if unbounded.
  std::string text() const;
};

constexpr Range above(double low) { return {low, std::numeric_limits<double>::infinity(), true, false}; }
constexpr Range atLeast(double low) { return {low, std::numeric_limits<double>::infinity(), false, false}; }
constexpr Range below(double high) { return {-std::numeric_limits<double>::infinity(), high, false, true}; }
constexpr Range atMost(double high) { return {-std::numeric_limits<double>::infinity(), high, false, false}; }
/// [low, high]
constexpr Range closed(double low, double high) { return {low, high, false, false}; }
/// (low, high)
constexpr Range open(double low, double high) { return {low, high, true, true}; }
/// (low, high]
constexpr Range openClosed(double low, double high) { return {low, high, true, false}; }
/// [low, high)
constexpr Range closedOpen(double low, double high) { return {low, high, false, true}; }
inline constexpr Range kPositive = above(0.0);
inline constexpr Range kNonNegative = atLeast(0.0);
inline constexpr Range kUnit = closed(0.0, 1.0);  // a share or a probability

/// A field's schema, the third argument of its visit call (see the header comment).
struct FieldSpec {
  std::string_view unit = {};  // e.g. "m/s", "rad", "Hz"; "" = dimensionless or not a quantity
  Range range = {};            // checked by validateFields on numbers (each element of a list)
  std::string_view doc = {};   // one line: what the field means
};

/// Calls `config.visit(v)` on a const config, for visitors that only read (the one place the
/// const is cast away).
template <class T, class V>
void visitConst(const T& config, V& v) {
  const_cast<T&>(config).visit(v);
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
  /// Sets `dotted_key` to the string `value` as it is (not read as YAML).
  void setString(const std::string& dotted_key, const std::string& value);
  /// Sets `dotted_key` to a list of the strings `values`.
  void setStrings(const std::string& dotted_key, const std::vector<std::string>& values);

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

  /// The schema is not the reader's business: ranges are validateFields's.
  template <class T>
  void operator()(const char* key, T& value, const FieldSpec&) {
    (*this)(key, value);
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
      visitConst(value, nested);
      text_ += nested.text_;
    } else if constexpr (requires(ConfigWriter& w) { const_cast<T&>(value).front().visit(w); }) {
      writeList(key, value);
    } else {
      line(key, valueText(value));
    }
  }
  template <class T>
  void operator()(const char* key, const T& value, const FieldSpec&) {
    (*this)(key, value);
  }

  const std::string& text() const { return text_; }

  /// A scalar's (a number, a string, a list of them, an enum's name) value as YAML text.
  template <class T>
  static std::string valueText(const T& value) {
    if constexpr (NamedEnum<T>) {
      return scalar(std::string(enumName(value)));
    } else {
      return scalar(value);
    }
  }

 private:
  // A block list of maps, each element's first field after "- ".
  template <class T>
  void writeList(const char* key, const std::vector<T>& values) {
    line(key, values.empty() ? "[]" : "");
    for (const T& element : values) {
      ConfigWriter nested(indent_ + 4);
      visitConst(element, nested);
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
  visitConst(config, writer);
  return writer.text();
}

/// Checks each field of one struct against its FieldSpec's range, recording "prefix.key: must
/// be > 0 m/s, got -1 m/s". Nested structs are not entered: each struct's validate() calls
/// validateFields for its own fields (see validateFields).
class ConfigValidator {
 public:
  ConfigValidator(Errors& errors, std::string prefix) : errors_(errors), prefix_(std::move(prefix)) {}

  template <class T>
  void operator()(const char*, const T&) {}  // no schema: nothing to check
  template <class T>
  void operator()(const char* key, const T& value, const FieldSpec& spec) {
    if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
      check(key, static_cast<double>(value), spec);
    } else if constexpr (std::is_same_v<T, std::vector<double>>) {
      for (std::size_t i = 0; i < value.size(); ++i) check(std::string(key) + "[" + std::to_string(i) + "]", value[i], spec);
    }
  }

 private:
  void check(const std::string& key, double value, const FieldSpec& spec);

  Errors& errors_;
  std::string prefix_;  // "file: block" as validate() gets it
};

/// Range checks of `config`'s own fields (not of nested structs), each error naming
/// `prefix.key`, the range and the unit. A struct's validate() calls it first, then adds its
/// cross-field rules and validates its nested structs.
template <class T>
void validateFields(const T& config, Errors& errors, const std::string& prefix) {
  ConfigValidator validator(errors, prefix);
  visitConst(config, validator);
}

/// One field of a config as `barn config <controller>` lists it.
struct FieldRow {
  std::string key;    // dotted path from the struct ("nav.global_costmap.inflation_radius")
  std::string value;  // as the config writer writes it
  std::string unit;   // "" = dimensionless or not stated
  std::string range;  // Range::text(), or an enum's names; "" = any
  std::string doc;
};

/// Lists a struct's fields, nested structs flattened into dotted keys (a list of structs is
/// one row).
class ConfigSchema {
 public:
  explicit ConfigSchema(std::string prefix = {}) : prefix_(std::move(prefix)) {}

  template <class T>
  void operator()(const char* key, const T& value) {
    (*this)(key, value, FieldSpec{});
  }
  template <class T>
  void operator()(const char* key, const T& value, const FieldSpec& spec) {
    const std::string path = prefix_ + key;
    if constexpr (requires(ConfigSchema& s) { const_cast<T&>(value).visit(s); }) {
      ConfigSchema nested(path + ".");
      visitConst(value, nested);
      rows_.insert(rows_.end(), nested.rows_.begin(), nested.rows_.end());
    } else if constexpr (requires(ConfigSchema& s) { const_cast<T&>(value).front().visit(s); }) {
      rows_.push_back({path, "[" + std::to_string(value.size()) + " entries]", std::string(spec.unit), "", std::string(spec.doc)});
    } else if constexpr (NamedEnum<T>) {
      std::string names;
      for (std::string_view n : enumNames(value)) names += (names.empty() ? "one of " : ", ") + std::string(n);
      rows_.push_back({path, ConfigWriter::valueText(value), std::string(spec.unit), names, std::string(spec.doc)});
    } else {
      rows_.push_back({path, ConfigWriter::valueText(value), std::string(spec.unit), spec.range.text(), std::string(spec.doc)});
    }
  }

  const std::vector<FieldRow>& rows() const { return rows_; }

 private:
  std::string prefix_;
  std::vector<FieldRow> rows_;
};

/// Every field of `config` with its value and schema, in visit order.
template <class T>
std::vector<FieldRow> schemaOf(const T& config) {
  ConfigSchema schema;
  visitConst(config, schema);
  return schema.rows();
}

}  // namespace barn::core
