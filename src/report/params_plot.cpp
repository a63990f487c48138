#include "barn/report/params_plot.hpp"

#include <algorithm>

#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "barn/viz/line_plot.hpp"

namespace barn::report {

namespace {

constexpr const char* kHeader = "time_s,x,y,yaw,cmd_linear,cmd_angular,state,params";
constexpr int kPanelWidth = 900;   // [px]
constexpr int kPanelHeight = 170;  // [px] the key as the title, a 68 px tall plot, the time axis

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = text.find(separator, start);
    parts.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
    if (end == std::string::npos) return parts;
    start = end + 1;
  }
}

}  // namespace

std::vector<ParameterSeries> readParameterSeries(const std::string& csv, const std::string& where, double& end_time) {
  std::vector<ParameterSeries> series;
  std::vector<std::string> lines = split(csv, '\n');
  if (!lines.empty() && lines.back().empty()) lines.pop_back();
  if (lines.empty() || lines.front() != kHeader)
    throw core::InputError(where + ": not a trajectory file (its first line must be '" + std::string(kHeader) + "')");
  end_time = 0.0;
  for (std::size_t n = 1; n < lines.size(); ++n) {
    const std::string at = where + ":" + std::to_string(n + 1);
    const std::vector<std::string> fields = split(lines[n], ',');
    double time = 0.0;
    if (fields.size() != 8 || !core::parseDouble(fields[0], time))
      throw core::InputError(at + ": expected 8 fields, the first the time [s]");
    end_time = time;
    if (fields[7].empty()) continue;
    for (const std::string& pair : split(fields[7], ';')) {
      const std::size_t equals = pair.find('=');
      double value = 0.0;
      if (equals == std::string::npos || equals == 0 || !core::parseDouble(pair.substr(equals + 1), value))
        throw core::InputError(at + ": params entry '" + pair + "': expected key=number");
      const std::string key = pair.substr(0, equals);
      auto it = std::find_if(series.begin(), series.end(), [&](const ParameterSeries& s) { return s.key == key; });
      if (it == series.end()) it = series.insert(series.end(), ParameterSeries{key, {}, {}});
      it->time.push_back(time);
      it->value.push_back(value);
    }
  }
  return series;
}

void renderParameterPlot(const std::filesystem::path& trajectory, const std::vector<std::string>& keys,
                         const std::string& title, const std::filesystem::path& output) {
  double end_time = 0.0;
  const std::vector<ParameterSeries> all = readParameterSeries(core::readTextFile(trajectory), trajectory.string(), end_time);
  std::vector<const ParameterSeries*> chosen;
  if (keys.empty()) {
    for (const ParameterSeries& s : all) chosen.push_back(&s);
  } else {
    for (const std::string& key : keys) {
      const auto it = std::find_if(all.begin(), all.end(), [&](const ParameterSeries& s) { return s.key == key; });
      if (it == all.end()) {
        std::string held;
        for (const ParameterSeries& s : all) held += (held.empty() ? "" : ", ") + s.key;
        throw core::InputError(trajectory.string() + ": no parameter '" + key + "' (it holds: " + (held.empty() ? "none" : held) + ")");
      }
      chosen.push_back(&*it);
    }
  }
  if (chosen.empty()) throw core::InputError(trajectory.string() + ": no parameter was set (the params column is empty)");
  std::vector<viz::LinePlot> panels;
  for (std::size_t k = 0; k < chosen.size(); ++k) {
    const ParameterSeries& s = *chosen[k];
    viz::LinePlot panel;
    panel.title = k == 0 && !title.empty() ? title + ": " + s.key : s.key;
    panel.x_label = "time [s]";
    panel.width = kPanelWidth;
    panel.height = kPanelHeight;
    // A step line: each value holds from when it was set to the next setting (the last to the
    // episode's last tick).
    viz::LineSeries line;  // no label: the panel's title names it
    for (std::size_t i = 0; i < s.time.size(); ++i) {
      const double until = i + 1 < s.time.size() ? s.time[i + 1] : std::max(end_time, s.time[i]);
      line.x.insert(line.x.end(), {s.time[i], until});
      line.y.insert(line.y.end(), {s.value[i], s.value[i]});
    }
    panel.series.push_back(std::move(line));
    panels.push_back(std::move(panel));
  }
  viz::renderLinePlots(panels, output);
}

}  // namespace barn::report
