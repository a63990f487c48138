// Fuzz target: episodes.csv and its journal, episodes.partial.csv (bench::parseEpisodesCsv,
// strict and as a journal whose last line may be cut), and the check of rows against a record
// (bench::checkRows, bench::checkCompleteRows) that resume and merge rely on.
//
// Bad input must end in core::InputError. Rows that read must write back (episodesCsv) and
// read again to the same text: writing then reading is stable (a written row may differ from
// the input's spelling, e.g. "1.0" is written "1").

#include <cstddef>
#include <cstdint>
#include <string>

#include "barn/bench/results_io.hpp"
#include "barn/bench/run_record.hpp"
#include "barn/core/errors.hpp"
#include "fuzz_check.hpp"

namespace {

using namespace barn;

// A record of worlds 0..9 x 3 trials, seed 0: what the rows are checked against.
bench::RunManifest record() {
  bench::RunManifest m;
  m.controller = "fuzz";
  for (int id = 0; id < 10; ++id) m.world_ids.push_back(id);
  m.trials = 3;
  m.episodes_total = m.episodes_done = 30;
  m.complete = true;
  return m;
}

void episodes(const std::string& text, bool journal) {
  std::vector<bench::EpisodeResult> rows;
  try {
    rows = bench::parseEpisodesCsv(text, "fuzz/episodes.csv", journal);
  } catch (const core::InputError&) {
    return;
  }
  const std::string written = bench::episodesCsv(rows);
  std::string rewritten;
  try {
    rewritten = bench::episodesCsv(bench::parseEpisodesCsv(written, "written/episodes.csv", false));
  } catch (const core::InputError& e) {
    fuzz::propertyFailed("rows that were read do not read back after writing", written, e.what());
  }
  if (rewritten != written) fuzz::propertyFailed("write, read, write changed the rows", written, rewritten);
  static const bench::RunManifest m = record();
  try {
    bench::checkRows(m, rows, "fuzz/episodes.partial.csv", {}, false);
  } catch (const core::InputError&) {
  }
  try {
    bench::checkCompleteRows(m, rows, "fuzz/episodes.csv");
  } catch (const core::InputError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  episodes(text, false);
  episodes(text, true);
  return 0;
}
