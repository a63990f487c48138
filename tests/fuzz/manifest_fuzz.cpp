// Fuzz target: the record's YAML files as barn reads them back: a run record's manifest.yaml
// (bench::parseManifest, which every resume, merge, show and regress goes through) and a
// sweep's sweep.yaml (bench::parseSweepFile), each on the same input.
//
// Bad input must end in core::InputError. A manifest that reads must write back
// (formatManifest, paths made relative to the record again) and read again to the same text;
// a sweep file likewise; and the record's row check must hold on no rows without allocating
// beyond what the manifest's bounds allow.

#include <cstddef>
#include <cstdint>
#include <string>

#include "barn/bench/run_record.hpp"
#include "barn/bench/sweep_grid.hpp"
#include "barn/core/errors.hpp"
#include "fuzz_check.hpp"

namespace {

using namespace barn;

const std::filesystem::path kRecord = "/tmp/barn_fuzz_record/run";

void manifest(const std::string& text) {
  bench::RunManifest m;
  try {
    m = bench::parseManifest(text, kRecord, "fuzz/manifest.yaml");
  } catch (const core::InputError&) {
    return;
  }
  const std::string written = bench::formatManifest(m, kRecord);
  std::string rewritten;
  try {
    rewritten = bench::formatManifest(bench::parseManifest(written, kRecord, "written/manifest.yaml"), kRecord);
  } catch (const core::InputError& e) {
    fuzz::propertyFailed("a manifest that was read does not read back after writing", written, e.what());
  }
  if (rewritten != written) fuzz::propertyFailed("write, read, write changed the manifest", written, rewritten);
  try {
    bench::checkCompleteRows(m, {}, "fuzz/episodes.csv");
  } catch (const core::InputError&) {
  }
}

void sweepFile(const std::string& text) {
  bench::SweepGrid grid;
  try {
    grid = bench::parseSweepFile(text, "fuzz/sweep.yaml");
  } catch (const core::InputError&) {
    return;
  }
  const std::string written = bench::formatSweepFile(grid);
  std::string rewritten;
  try {
    rewritten = bench::formatSweepFile(bench::parseSweepFile(written, "written/sweep.yaml"));
  } catch (const core::InputError& e) {
    fuzz::propertyFailed("a sweep file that was read does not read back after writing", written, e.what());
  }
  if (rewritten != written) fuzz::propertyFailed("write, read, write changed the sweep file", written, rewritten);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  manifest(text);
  sweepFile(text);
  return 0;
}
