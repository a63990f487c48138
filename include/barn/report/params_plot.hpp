#pragma once
/// `barn plot params`: the stack parameters a controller set while it ran (the `params` column
/// of a trajectory file, `barn run --trajectories`), one panel per parameter against time.

#include <filesystem>
#include <string>
#include <vector>

namespace barn::report {

/// One parameter's values: each set at a time, in force until the next.
struct ParameterSeries {
  std::string key;
  std::vector<double> time;   // [s] when it was set, ascending
  std::vector<double> value;  // what it was set to
};

/// The parameters of a trajectory file's text (header `time_s,...,params`; each params cell is
/// `key=value;key=value` or empty), in the order each key first appears, and the time of the
/// last row in `end_time`. InputError prefixed by `where` for a file that is not a trajectory
/// file or a params cell that does not parse (naming the line).
std::vector<ParameterSeries> readParameterSeries(const std::string& csv, const std::string& where, double& end_time);

/// Draws each series of `keys` (every key the file holds if empty; InputError naming a key it
/// does not hold) as a step line from when it was set to the end of the episode, one panel per
/// key stacked over the time axis, into `output` (.png, .pdf or .svg).
void renderParameterPlot(const std::filesystem::path& trajectory, const std::vector<std::string>& keys,
                         const std::string& title, const std::filesystem::path& output);

}  // namespace barn::report
