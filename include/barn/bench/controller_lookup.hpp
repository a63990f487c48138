#pragma once
/// Which controller config a run uses when it is named: `barn run --controller NAME` and
/// `barnbench.run("NAME")` both ask this, so both front ends accept the same names and refuse
/// the same mistakes with the same message.

#include <filesystem>
#include <string>
#include <vector>

#include "barn/core/config.hpp"

namespace barn::bench {

/// How the asking front end spells its two inputs, for its error messages.
struct ControllerLookupWords {
  std::string name_option = "--controller";  // the input holding NAME
  std::string file_option = "--config FILE";  // how a config file is given instead
};

/// InputError unless `name` is a plain name (no path): it picks `configs_dir`/NAME.yaml and the
/// default record folder results/NAME.
void checkControllerName(const std::string& name, const ControllerLookupWords& words = {});

/// The names a run takes: the configs in `configs_dir` (sorted), then the controller types
/// that no config there shadows.
std::vector<std::string> controllerNames(const std::filesystem::path& configs_dir);

/// The file the controller config comes from: `config_file` if given, else
/// `configs_dir`/NAME.yaml if it exists; empty for a bare type (its defaults).
std::filesystem::path controllerConfigFile(const std::string& name, const std::filesystem::path& config_file,
                                           const std::filesystem::path& configs_dir);

/// The controller config: `config_file`, else `configs_dir`/NAME.yaml, else the type NAME with
/// its defaults. InputError for a path given as a name, or an unknown name (listing the known
/// ones, and the nearest as "did you mean" when it is a near miss).
core::ConfigNode controllerConfigNode(const std::string& name, const std::filesystem::path& config_file,
                                      const std::filesystem::path& configs_dir, const ControllerLookupWords& words = {});

}  // namespace barn::bench
