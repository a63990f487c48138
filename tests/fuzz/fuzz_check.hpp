#pragma once
// Shared by the libFuzzer targets: how a target reports a finding that is not a crash.
//
// Each target feeds its input to one reader and catches the documented error type
// (core::InputError). Any other exception escapes LLVMFuzzerTestOneInput, ends in
// std::terminate and is reported by libFuzzer as a crash, with the exception's type printed;
// a sanitizer report, a timeout or going over -rss_limit_mb / -malloc_limit_mb is a finding too.

#include <cstdio>
#include <cstdlib>
#include <string>

namespace barn::fuzz {

/// A property the reader must keep (e.g. write-then-read gives the same text) did not hold:
/// prints what and the two texts, then aborts so libFuzzer saves the input.
[[noreturn]] inline void propertyFailed(const char* what, const std::string& expected, const std::string& actual) {
  std::fprintf(stderr, "fuzz finding: %s\n--- expected ---\n%s\n--- actual ---\n%s\n", what, expected.c_str(),
               actual.c_str());
  std::abort();
}

}  // namespace barn::fuzz
