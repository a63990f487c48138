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

/// A factory for a controller config node of the form
///     type: pure_pursuit
///     pure_pursuit: {speed: 0.5}
/// The config is read and validated here, before any episode runs; InputError names the key.
ControllerFactory makeControllerFactory(const core::ConfigNode& config);

/// The effective config (type plus every field with its value) as YAML text, for manifests.
std::string effectiveControllerConfig(const core::ConfigNode& config);

}  // namespace barn::controllers
