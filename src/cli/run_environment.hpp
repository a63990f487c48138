#pragma once
/// Facts about where a run happens, for its manifest: git commit, host, time.

#include <string>

namespace barn::cli {

/// `git rev-parse HEAD` of the source tree (with "-dirty" if it has changes), or "unknown".
std::string gitCommit();
std::string hostName();
/// Current UTC time, ISO 8601.
std::string utcNow();

}  // namespace barn::cli
