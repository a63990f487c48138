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
/// prepareController's factory alone.
ControllerFactory makeControllerFactory(const core::ConfigNode& config);
/// prepareController's effective config alone.
std::string effectiveControllerConfig(const core::ConfigNode& config);

}  // namespace barn::controllers
