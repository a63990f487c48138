#include "barn/report/set_summary.hpp"

#include <cstdio>

#include "barn/core/protocol.hpp"

namespace barn::report {

namespace {

struct Accumulator {
  double fill_pct = 0.0;
  int smooth_iter = 0;
  int count = 0;
  double filled_fraction = 0.0;
  double path_cells = 0.0;
  double length = 0.0;
  double time = 0.0;
  std::array<double, 5> metrics{};

  void add(const core::WorldSpec& w, const core::Protocol& protocol) {
    ++count;
    filled_fraction += static_cast<double>(w.grid.countFilled()) / static_cast<double>(w.grid.rows() * w.grid.cols());
    path_cells += static_cast<double>(w.path.size());
    length += core::referencePathLength(w.path, protocol);
    time += core::optimalTime(w.path, protocol);
    const auto m = w.metrics.toArray();
    for (std::size_t k = 0; k < 5; ++k) metrics[k] += m[k];
  }

  std::string row(const char* label) const {
    const double n = count;
    char line[256];
    std::snprintf(line, sizeof(line), "%-14s %5d %7.3f %7.2f %7.3f %6.3f %7.3f %7.3f %7.3f %7.3f %7.3f\n", label, count,
                  filled_fraction / n, path_cells / n, length / n, time / n, metrics[0] / n, metrics[1] / n,
                  metrics[2] / n, metrics[3] / n, metrics[4] / n);
    return line;
  }
};

}  // namespace

std::string parameterSetTable(const std::vector<core::WorldSpec>& worlds) {
  const core::Protocol protocol = core::protocolPreset(core::ProtocolName::Barn2023);
  std::vector<Accumulator> sets;
  Accumulator all;
  for (const auto& w : worlds) {
    Accumulator* set = nullptr;
    for (auto& s : sets)
      if (s.fill_pct == w.fill_pct && s.smooth_iter == w.smooth_iter) set = &s;
    if (!set) {
      sets.push_back({});
      set = &sets.back();
      set->fill_pct = w.fill_pct;
      set->smooth_iter = w.smooth_iter;
    }
    set->add(w, protocol);
    all.add(w, protocol);
  }
  std::string table = "set (fill/sm)  count  filled  cells   len_m   OT_s  closest  avgvis  disper chardim  tortu\n";
  for (const auto& s : sets) {
    char label[32];
    std::snprintf(label, sizeof(label), "%.2f / %d", s.fill_pct, s.smooth_iter);
    table += s.row(label);
  }
  table += all.row("all");
  return table;
}

}  // namespace barn::report
