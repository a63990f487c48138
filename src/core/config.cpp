#include "barn/core/config.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <cstdio>
#include <string_view>
#include <set>
#include <sstream>

#include <yaml-cpp/eventhandler.h>

#include <yaml-cpp/yaml.h>

#include "barn/core/text_io.hpp"

namespace barn::core {

struct ConfigNode::Impl {
  YAML::Node node;
};

ConfigNode::ConfigNode() : impl_(std::make_shared<Impl>()) {}
ConfigNode::~ConfigNode() = default;
ConfigNode::ConfigNode(const ConfigNode&) = default;
ConfigNode& ConfigNode::operator=(const ConfigNode&) = default;

namespace {

// Parses a document without building it, noting where it starts.
class DocumentStart : public YAML::EventHandler {
 public:
  void OnDocumentStart(const YAML::Mark& at) override {
    seen = true;
    mark = at;
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t, const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}

  bool seen = false;
  YAML::Mark mark = YAML::Mark::null_mark();
};

// The offset of the first byte that is not YAML text (UTF-8 of a printable character, tab, line
// feed or carriage return), or npos. yaml-cpp passes other bytes through into values that no
// writer can give back (an effective config would not read again).
std::size_t firstNonText(std::string_view text) {
  std::size_t i = 0;
  while (i < text.size()) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if (byte < 0x80) {
      if ((byte < 0x20 && byte != '\t' && byte != '\n' && byte != '\r') || byte == 0x7f) return i;
      ++i;
      continue;
    }
    const std::size_t length = byte >= 0xf0 ? 4 : byte >= 0xe0 ? 3 : byte >= 0xc2 ? 2 : 0;
    if (length == 0 || byte > 0xf4 || i + length > text.size()) return i;
    std::uint32_t code = byte & (0xff >> (length + 1));
    for (std::size_t k = 1; k < length; ++k) {
      const auto next = static_cast<unsigned char>(text[i + k]);
      if ((next & 0xc0) != 0x80) return i;
      code = (code << 6) | (next & 0x3f);
    }
    const bool overlong = (length == 3 && code < 0x800) || (length == 4 && code < 0x10000);
    const bool c1 = code >= 0x80 && code <= 0x9f && code != 0x85;
    const bool surrogate = code >= 0xd800 && code <= 0xdfff;
    if (overlong || c1 || surrogate || code == 0xfffe || code == 0xffff || code > 0x10ffff) return i;
    i += length;
  }
  return std::string_view::npos;
}

// "line 3, column 7: message" for a yaml-cpp exception (yaml-cpp counts from 0).
std::string describeYamlError(const YAML::Exception& e) {
  if (e.mark.is_null()) return e.msg;
  return "line " + std::to_string(e.mark.line + 1) + ", column " + std::to_string(e.mark.column + 1) + ": " + e.msg;
}

}  // namespace

ConfigNode ConfigNode::parseString(const std::string& text, const std::string& source_name) {
  ConfigNode result;
  result.source_ = source_name;
  if (const std::size_t bad = firstNonText(text); bad != std::string_view::npos) {
    const long line = 1 + std::count(text.begin(), text.begin() + static_cast<long>(bad), '\n');
    char byte[8];
    std::snprintf(byte, sizeof byte, "0x%02x", static_cast<unsigned char>(text[bad]));
    throw InputError(source_name + ": line " + std::to_string(line) + ": not YAML text (byte " + byte +
                     " is a control character or not UTF-8)");
  }
  try {
    result.impl_->node = YAML::Load(text);
    // YAML::Load reads the first document and drops the rest: text after it (a second
    // document after `---`, anything after `...`) is parsed here too, and refused. Two
    // documents at most are asked for (YAML::LoadAll can loop forever on some malformed text).
    std::istringstream stream(text);
    YAML::Parser parser(stream);
    DocumentStart second;
    parser.HandleNextDocument(second);
    second.seen = false;
    if (parser.HandleNextDocument(second) && second.seen)
      throw InputError(source_name + ": " +
                       (second.mark.is_null() ? std::string() : "line " + std::to_string(second.mark.line + 1) + ": ") +
                       "a second YAML document (after '---' or '...'); a config file holds one");
  } catch (const YAML::Exception& e) {
    throw InputError(source_name + ": not valid YAML: " + describeYamlError(e));
  }
  return result;
}

ConfigNode ConfigNode::parseFile(const std::filesystem::path& path) {
  return parseString(readTextFile(path), path.string());
}

bool ConfigNode::isNull() const { return !impl_->node || impl_->node.IsNull(); }
bool ConfigNode::isMap() const { return impl_->node && impl_->node.IsMap(); }
bool ConfigNode::isSequence() const { return impl_->node && impl_->node.IsSequence(); }
std::size_t ConfigNode::size() const { return isSequence() ? impl_->node.size() : 0; }

bool ConfigNode::has(std::string_view key) const {
  return isMap() && static_cast<bool>(impl_->node[std::string(key)]);
}

ConfigNode ConfigNode::child(std::string_view key) const {
  ConfigNode result;
  result.source_ = source_;
  result.path_ = path_.empty() ? std::string(key) : path_ + "." + std::string(key);
  if (isMap()) result.impl_->node = impl_->node[std::string(key)];
  return result;
}

ConfigNode ConfigNode::element(std::size_t index) const {
  ConfigNode result;
  result.source_ = source_;
  result.path_ = path_ + "[" + std::to_string(index) + "]";
  if (impl_->node && impl_->node.IsSequence() && index < impl_->node.size()) result.impl_->node = impl_->node[index];
  return result;
}

std::vector<std::string> ConfigNode::keys() const {
  std::vector<std::string> keys;
  if (!isMap()) return keys;
  for (const auto& item : impl_->node) {
    // A list or map as a key (`[1]: 2`) has no name to look up or report; yaml-cpp's
    // as<std::string>() would throw a bare "bad conversion" naming neither file nor line.
    if (!item.first.IsScalar()) {
      const YAML::Mark mark = item.first.Mark();
      const std::string line = mark.is_null() ? "unknown line" : "line " + std::to_string(mark.line + 1);
      const std::string owner = path_.empty() ? "a key" : "a key in " + path_;
      throw InputError(source_ + ": " + line + ": " + owner +
                       (item.first.IsNull() ? " is empty (~, null or nothing before ':')"
                                            : " is a list or a map") +
                       ", expected a plain name");
    }
    keys.push_back(item.first.Scalar());
  }
  return keys;
}

namespace {

void collectScalars(const YAML::Node& node, std::vector<std::string>& out) {
  if (!node) return;
  if (node.IsScalar()) {
    out.push_back(node.Scalar());
  } else if (node.IsSequence()) {
    for (const auto& item : node) collectScalars(item, out);
  } else if (node.IsMap()) {
    for (const auto& item : node) collectScalars(item.second, out);
  }
}

}  // namespace

std::vector<std::string> ConfigNode::scalarValues() const {
  std::vector<std::string> values;
  collectScalars(impl_->node, values);
  return values;
}

namespace {

bool scalarText(const YAML::Node& node, std::string& text) {
  if (!node || !node.IsScalar()) return false;
  text = node.Scalar();
  return true;
}

}  // namespace

bool ConfigNode::read(double& value) const {
  std::string text;
  double parsed = 0.0;
  if (!scalarText(impl_->node, text) || !parseDouble(text, parsed) || !std::isfinite(parsed)) return false;
  value = parsed;
  return true;
}

// Integers are decimal digits (and a leading '-' for a signed one), read exactly: no spaces,
// '+', "0x" or fraction, and a value out of range is refused, never wrapped or saturated
// (" -1" as an unsigned seed would otherwise become 2^64 - 1).
bool ConfigNode::read(int& value) const {
  std::string text;
  if (!scalarText(impl_->node, text) || text.empty()) return false;
  int parsed = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), parsed);
  if (error != std::errc() || end != text.data() + text.size()) return false;
  value = parsed;
  return true;
}

bool ConfigNode::read(std::uint64_t& value) const {
  std::string text;
  if (!scalarText(impl_->node, text) || text.empty() || text[0] == '-') return false;
  std::uint64_t parsed = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), parsed);
  if (error != std::errc() || end != text.data() + text.size()) return false;
  value = parsed;
  return true;
}

bool ConfigNode::read(bool& value) const {
  std::string text;
  if (!scalarText(impl_->node, text)) return false;
  if (text == "true") value = true;
  else if (text == "false") value = false;
  else return false;
  return true;
}

bool ConfigNode::read(std::string& value) const {
  if (!impl_->node || !impl_->node.IsScalar()) return false;
  value = impl_->node.Scalar();
  return true;
}

bool ConfigNode::read(std::vector<double>& value) const {
  if (!impl_->node || !impl_->node.IsSequence()) return false;
  std::vector<double> parsed;
  for (const auto& item : impl_->node) {
    std::string text;
    double v = 0.0;
    if (!scalarText(item, text) || !parseDouble(text, v) || !std::isfinite(v)) return false;
    parsed.push_back(v);
  }
  value = std::move(parsed);
  return true;
}

bool ConfigNode::read(std::vector<std::string>& value) const {
  if (!impl_->node || !impl_->node.IsSequence()) return false;
  std::vector<std::string> parsed;
  for (const auto& item : impl_->node) {
    if (!item.IsScalar()) return false;
    parsed.push_back(item.Scalar());
  }
  value = std::move(parsed);
  return true;
}

namespace {

// The node at `dotted_key` under `root` ("safety.fi.offset"), maps created as needed.
YAML::Node settableNode(YAML::Node& root, const std::string& dotted_key) {
  if (!root || !root.IsMap()) root = YAML::Node(YAML::NodeType::Map);
  YAML::Node current = root;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = dotted_key.find('.', start);
    const std::string key = dotted_key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (key.empty()) throw InputError("override '" + dotted_key + "': empty key");
    if (dot == std::string::npos) return current[key];
    YAML::Node next = current[key];
    if (!next || !next.IsMap()) {
      current[key] = YAML::Node(YAML::NodeType::Map);
      next = current[key];
    }
    current.reset(next);
    start = dot + 1;
  }
}

}  // namespace

void ConfigNode::set(const std::string& dotted_key, const std::string& value_text) {
  YAML::Node parsed;
  try {
    parsed = YAML::Load(value_text);
  } catch (const YAML::Exception&) {
    parsed = YAML::Node(value_text);
  }
  settableNode(impl_->node, dotted_key) = parsed;
}

void ConfigNode::setString(const std::string& dotted_key, const std::string& value) {
  settableNode(impl_->node, dotted_key) = YAML::Node(value);
}

void ConfigNode::setStrings(const std::string& dotted_key, const std::vector<std::string>& values) {
  YAML::Node list(YAML::NodeType::Sequence);
  for (const std::string& value : values) list.push_back(value);
  settableNode(impl_->node, dotted_key) = list;
}

std::string ConfigNode::toYaml() const {
  YAML::Emitter out;
  out << impl_->node;
  return std::string(out.c_str()) + "\n";
}

std::string ConfigNode::where(std::string_view key) const {
  std::string full = path_;
  if (!key.empty()) full = full.empty() ? std::string(key) : full + "." + std::string(key);
  if (source_.empty()) return full;
  return full.empty() ? source_ : source_ + ": " + full;
}

// ---------------------------------------------------------------------------------------------

ConfigReader::ConfigReader(const ConfigNode& node, Errors& errors, MissingKeys missing)
    : node_(node), errors_(errors), missing_(missing) {}

std::string ConfigReader::given(const ConfigNode& node) {
  std::string text;
  return node.read(text) ? ", got '" + text + "'" : std::string();
}

void ConfigReader::finish() {
  std::vector<std::string> keys;
  try {
    keys = node_.keys();
  } catch (const InputError& e) {
    errors_.add("", e.what());  // a key that is a list or map; the other errors still count
    return;
  }
  std::set<std::string> listed;
  for (const std::string& key : keys) {
    if (!listed.insert(key).second) {
      errors_.add(node_.where(key), "duplicate key");
    } else if (std::find(seen_.begin(), seen_.end(), key) == seen_.end()) {
      std::string known;
      for (const auto& k : seen_) known += (known.empty() ? "" : ", ") + k;
      errors_.add(node_.where(key), "unknown key (known: " + known + ")");
    }
  }
}

// ---------------------------------------------------------------------------------------------

void ConfigWriter::line(const char* key, const std::string& value) {
  text_ += std::string(static_cast<std::size_t>(indent_), ' ') + key + ":";
  if (!value.empty()) text_ += " " + value;
  text_ += "\n";
}

std::string ConfigWriter::scalar(double value) { return formatDouble(value); }
std::string ConfigWriter::scalar(int value) { return std::to_string(value); }
std::string ConfigWriter::scalar(std::uint64_t value) { return std::to_string(value); }
std::string ConfigWriter::scalar(bool value) { return value ? "true" : "false"; }
std::string ConfigWriter::scalar(const std::string& value) {
  YAML::Emitter out;
  out << value;
  return out.c_str();
}
std::string ConfigWriter::scalar(const std::vector<double>& value) {
  std::string text = "[";
  for (std::size_t i = 0; i < value.size(); ++i) text += (i ? ", " : "") + formatDouble(value[i]);
  return text + "]";
}
std::string ConfigWriter::scalar(const std::vector<std::string>& value) {
  std::string text = "[";
  for (std::size_t i = 0; i < value.size(); ++i) text += (i ? ", " : "") + scalar(value[i]);
  return text + "]";
}

// ---------------------------------------------------------------------------------------------

std::string Range::text() const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (low == -kInf && high == kInf) return {};
  if (high == kInf) return (low_open ? "> " : ">= ") + formatDouble(low);
  if (low == -kInf) return (high_open ? "< " : "<= ") + formatDouble(high);
  return std::string("in ") + (low_open ? "(" : "[") + formatDouble(low) + ", " + formatDouble(high) + (high_open ? ")" : "]");
}

void ConfigValidator::check(const std::string& key, double value, const FieldSpec& spec) {
  if (spec.range.contains(value)) return;
  const std::string unit = spec.unit.empty() ? std::string() : " " + std::string(spec.unit);
  errors_.add(prefix_.empty() ? key : prefix_ + "." + key,
              "must be " + spec.range.text() + unit + ", got " + formatDouble(value) + unit);
}

}  // namespace barn::core
