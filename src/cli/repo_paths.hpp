#pragma once
/// Where the repository's data folders (configs/, worlds/) are, wherever `barn` is run from.

#include <filesystem>
#include <string>

namespace barn::cli {

/// `name` (e.g. "configs") found in the current folder, beside the executable's parent
/// (build/barn -> ./configs) or in the source tree the binary was built from.
std::filesystem::path repoPath(const std::string& name);

}  // namespace barn::cli
