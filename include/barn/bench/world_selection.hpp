#pragma once
/// Which worlds a run uses: `--worlds all | test50 | A:B[:STEP] | 3,7,9 | FOLDER`.

#include <filesystem>
#include <string>
#include <vector>

#include "barn/core/world.hpp"

namespace barn::bench {

/// The ids a spec names, resolved against the ids available (sorted). Throws InputError for
/// an unknown id, a malformed spec or an empty selection. `all` = every available id;
/// `test50` = BARN's test set 0, 6, ..., 294; `A:B` = A <= id < B; `A:B:S` with step S.
std::vector<int> selectWorldIds(const std::string& spec, const std::vector<int>& available);

/// Loads the worlds of `spec`: if `spec` is a folder, every world in it; otherwise the ids it
/// names from `default_dir`. Files are validated before any episode runs.
std::vector<core::WorldSpec> loadWorlds(const std::string& spec, const std::filesystem::path& default_dir);

}  // namespace barn::bench
