// The commit barnbench was built from, recorded at build time (cmake/build_commit.cmake), so a
// record names the code that ran it whatever the checkout holds by then, and running barn
// never touches the checkout.

#include "barn/bench/record_session.hpp"
#include "barn_build_commit.hpp"

namespace barn::bench {

std::string gitCommit() { return BARN_BUILD_COMMIT; }

}  // namespace barn::bench
