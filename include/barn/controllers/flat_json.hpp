#pragma once
/// The tiny JSON subset the external-controller protocol needs: numbers written so they read
/// back exactly, strings escaped, and a strict reader for one flat object per line.
///
/// barnbench has no JSON library (the CLI's json_writer only writes), and the answers of an
/// external controller are flat objects such as {"v": 0.5, "w": -0.1}, so a small hand-written
/// reader is enough and adds no dependency.

#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

namespace barn::controllers::json {

/// A malformed line; the message says what and where (column, 1-based).
class ParseError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A scalar JSON value: null, true/false, a number, or a string.
using Scalar = std::variant<std::nullptr_t, bool, double, std::string>;

/// The members of a flat JSON object, in the order written.
using FlatObject = std::vector<std::pair<std::string, Scalar>>;

/// Parses `line` as one JSON object whose values are all scalars (no nested objects or
/// arrays), with nothing but white space around it. Duplicate keys are errors. Numbers follow
/// the JSON grammar and are read with correct rounding (std::from_chars); numbers outside the
/// double range are errors.
FlatObject parseFlatObject(std::string_view line);

/// Appends `value` in the shortest form that reads back as the same double (std::to_chars),
/// as JSON: a non-finite value becomes null, and -0 is written "-0.0" so that readers that
/// turn "-0" into the integer 0 keep the sign.
void appendNumber(std::string& out, double value);

/// Appends `text` as a JSON string literal (quotes, escapes for '"', '\\' and control bytes).
void appendString(std::string& out, std::string_view text);

}  // namespace barn::controllers::json
