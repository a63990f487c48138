#pragma once
/// The controllers barnbench knows, as an explicit list (no self-registration).

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "barn/controllers/controller.hpp"
#include "barn/core/config.hpp"

namespace barn::controllers {

/// Makes a fresh controller; safe to call from several threads (it only copies a validated config).
using ControllerFactory = std::function<std::unique_ptr<Controller>()>;

/// Controller types, in the order `barn run --help` lists them.
std::vector<std::string> controllerTypes();

/// A controller config, read: the factory of its controllers and its effective config (type
/// plus every field with its value, paths resolved) as YAML text, for manifests.
struct PreparedController {
  ControllerFactory factory;
  std::string effective_config;
};

/// Reads and validates a controller config node of the form
///     type: pure_pursuit
///     pure_pursuit: {speed: 0.5}
/// before any episode runs (InputError names the key); a policy file is loaded once, here.
PreparedController prepareController(const core::ConfigNode& config);
/// Every field of the config's controller block (the file's values, defaults for the rest) with
/// its unit, range and doc, keys relative to the block ("nav.planner.rate"): `barn config
/// <controller>`. InputError as prepareController for a missing or unknown type or a bad value.
std::vector<core::FieldRow> controllerSchema(const core::ConfigNode& config);
/// The unit controller type `type`'s config states for `key` (relative to the type's block, or
/// starting with the type: "safety.front_pad_x", "inventec.safety.front_pad_x"): a sweep
/// axis's unit. "" if the key is dimensionless, states no unit or is not a key of the type.
std::string controllerKeyUnit(const std::string& type, const std::string& key);
/// prepareController's factory alone.
ControllerFactory makeControllerFactory(const core::ConfigNode& config);
/// prepareController's effective config alone.
std::string effectiveControllerConfig(const core::ConfigNode& config);

/// A path mapped to another form of it (absolute to relative to a record, and back).
using PathMap = std::function<std::string(const std::string&)>;
/// A controller config (effectiveControllerConfig's, or a record's) as YAML text with every
/// field that is a path passed through `map`: a policy file (lflh, inventec, e2e, applr_dwa,
/// lics), an external program's working_dir and arguments, a Python class's python.source;
/// the other fields as they are (not read: a record of an older version, or whose policy file
/// is gone, still maps). InputError as prepareController for an unknown type or key.
std::string mapControllerPaths(const core::ConfigNode& config, const PathMap& map);

}  // namespace barn::controllers
