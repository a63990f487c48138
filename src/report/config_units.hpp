#pragma once
/// The unit a YAML config file states for one of its keys, for figure axes: the house style puts
/// it in brackets at the start of the key's comment (`speed: 0.5  # [m/s]`).

#include <filesystem>
#include <string>

namespace barn::report {

/// The unit of `key` (dotted: relative to the file's `type` block, or from the top) in the
/// config file `file`: the text between "[" and "]" opening the comment on the key's line.
/// Empty when the file cannot be read, the key is not in it, its comment states no unit, or
/// the unit is "-" (dimensionless).
std::string configKeyUnit(const std::filesystem::path& file, const std::string& key);

}  // namespace barn::report
