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

/// The worlds of `spec` and where they came from.
struct LoadedWorlds {
  std::filesystem::path folder;         // absolute
  std::vector<core::WorldSpec> worlds;  // in run order (ascending id)
  std::vector<std::string> skipped;     // with keep_going: one message per unreadable file
};

/// Loads the worlds of `spec`: if `spec` is a folder, every world in it; otherwise the ids it
/// names from `default_dir`. Every file is validated before any episode runs; an invalid one
/// is an InputError unless `keep_going`, which skips it and reports it in `skipped`.
LoadedWorlds loadWorlds(const std::string& spec, const std::filesystem::path& default_dir, bool keep_going = false);

}  // namespace barn::bench
