#include "barn/controllers/registry.hpp"

#include <algorithm>

#include "barn/controllers/almeria_tps.hpp"
#include "barn/controllers/applr_dwa.hpp"
#include "barn/controllers/dwa.hpp"
#include "barn/controllers/e2e.hpp"
#include "barn/controllers/eband.hpp"
#include "barn/controllers/global_plan_feed.hpp"
#include "barn/controllers/in2bot.hpp"
#include "barn/controllers/inventec.hpp"
#include "barn/controllers/kulfm.hpp"
#include "barn/controllers/lflh.hpp"
#include "barn/controllers/lics.hpp"
#include "barn/controllers/meco.hpp"
#include "barn/controllers/pure_pursuit.hpp"
#include "barn/controllers/rrsl_vfh.hpp"
#include "barn/controllers/straight.hpp"
#include "barn/controllers/ut_amrl.hpp"
#include "barn/external/external.hpp"

namespace barn::controllers {

namespace {

// The keys of a config block whose values are paths (scalars), and of a command list whose
// elements after the first (the program) are: what mapControllerPaths maps.
struct PathKeys {
  std::vector<std::string> paths;
  std::string arguments;
};

// One entry per controller type: reads and validates its block, returns a factory and the
// effective config text.
struct Entry {
  const char* type;
  std::function<ControllerFactory(const core::ConfigNode&, std::string&)> make;
  std::vector<core::FieldRow> (*schema)(const core::ConfigNode&);  // the block's fields, read
  PathKeys paths;  // the block's fields that are paths
};

// A block's fields as read (defaults for missing keys), with their schema.
template <class Config>
std::vector<core::FieldRow> blockSchema(const core::ConfigNode& block) {
  return core::schemaOf(core::readConfig<Config>(block));
}

// The effective config text of a block: every field with its value, as a manifest records it.
template <class Config>
std::string blockText(const char* key, Config& config) {
  core::ConfigWriter writer(2);
  config.visit(writer);
  return std::string(key) + ":\n" + writer.text();
}

// A block read through its config's field list, `resolve`d (paths made absolute against the
// config file's folder) and validated: InputError naming the file and every bad field.
template <class Config, class Resolve>
Config readValidated(const core::ConfigNode& block, const Resolve& resolve) {
  Config config = core::readConfig<Config>(block);
  resolve(config, block.source());
  core::Errors errors;
  validate(config, errors, block.where());
  errors.throwIfAny();
  return config;
}

// Reading a config file: a type's paths made absolute against the file's folder.
constexpr auto kNoPaths = [](auto&, const std::string&) {};
constexpr auto kPolicyPath = [](auto& config, const std::string& source) {
  config.policy = resolvePolicyPath(config.policy, source);
};
// The same for a config whose policy file is its PolicyDriveConfig's.
constexpr auto kDrivePolicyPath = [](auto& config, const std::string& source) { kPolicyPath(config.drive, source); };
// The same fields by key, for mapControllerPaths (functions, not globals: entries() may be
// first called during another file's static initialisation).
PathKeys noPathKeys() { return {}; }
PathKeys policyPathKeys() { return {{"policy"}, ""}; }
// An external program's folder and its arguments (the files resolveExternalPaths finds beside
// the config file). The program itself (command[0]) is left as it is: usually one of the
// system's (python3), not a file that travels with the record.
PathKeys externalPathKeys() { return {{"working_dir"}, "command"}; }
// A Python class's config (type python, which the Python front end writes and reads): its
// source file.
PathKeys pythonPathKeys() { return {{"source"}, ""}; }

// A controller made from its config alone.
template <class Config, class ControllerType>
Entry entry(const char* type) {
  return {type, [type](const core::ConfigNode& block, std::string& effective) -> ControllerFactory {
            Config config = readValidated<Config>(block, kNoPaths);
            effective = std::string("type: ") + type + "\n" + blockText(type, config);
            return [config] { return std::make_unique<ControllerType>(config); };
          },
          &blockSchema<Config>, noPathKeys()};
}

// A controller with something every episode's controller shares, read-only, made once here
// from the validated config by `share` (a loaded network, a precomputed table); `resolve`
// makes its paths (`paths`, by key) absolute first.
template <class Config, class ControllerType, class Resolve, class Share>
Entry sharedEntry(const char* type, Resolve resolve, const PathKeys& paths, Share share) {
  return {type, [type, resolve, share](const core::ConfigNode& block, std::string& effective) -> ControllerFactory {
            Config config = readValidated<Config>(block, resolve);
            auto shared = share(config);
            effective = std::string("type: ") + type + "\n" + blockText(type, config);
            return [config, shared] { return std::make_unique<ControllerType>(config, shared); };
          },
          &blockSchema<Config>, paths};
}

// The LfLH policy file at `path`, shared read-only.
std::shared_ptr<const learning::Policy> loadLflhPolicy(const std::string& path) {
  return std::make_shared<const learning::Policy>(learning::Policy::load(path));
}

const std::vector<Entry>& entries() {
  static const std::vector<Entry> kEntries = {
      entry<StraightConfig, StraightController>("straight"),
      entry<PurePursuitConfig, PurePursuitController>("pure_pursuit"),
      entry<DwaConfig, DwaController>("dwa"),
      entry<EbandConfig, EbandController>("eband"),
      entry<UtAmrlConfig, UtAmrlController>("ut_amrl"),
      sharedEntry<LflhConfig, LflhController>("lflh", kDrivePolicyPath, policyPathKeys(),
                                              [](const LflhConfig& c) { return loadLflhPolicy(c.drive.policy); }),
      sharedEntry<InventecConfig, InventecController>("inventec", kDrivePolicyPath, policyPathKeys(),
                                                      [](const InventecConfig& c) { return loadLflhPolicy(c.drive.policy); }),
      entry<RrslVfhConfig, RrslVfhController>("rrsl_vfh"),
      entry<In2botConfig, In2botController>("in2bot"),
      entry<KulfmConfig, KulfmController>("kulfm"),
      sharedEntry<E2eConfig, E2eController>(
          "e2e", kPolicyPath, policyPathKeys(),
          [](const E2eConfig& c) { return std::make_shared<const learning::MlpPolicy>(learning::MlpPolicy::load(c.policy)); }),
      entry<MecoConfig, MecoController>("meco"),
      // The PTG's collision grid, built once.
      sharedEntry<AlmeriaTpsConfig, AlmeriaTpsController>(
          "almeria_tps", kNoPaths, noPathKeys(), [](const AlmeriaTpsConfig& c) { return std::make_shared<const ArcPtg>(c.ptg); }),
      sharedEntry<ApplrDwaConfig, ApplrDwaController>("applr_dwa", kPolicyPath, policyPathKeys(), [](const ApplrDwaConfig& c) {
        auto policy = loadApplrPolicy(c.policy, "");
        ApplrDwaController check(c, policy);  // an actor whose actions the DWA cannot take fails here, once
        return policy;
      }),
      sharedEntry<LicsConfig, LicsController>("lics", kPolicyPath, policyPathKeys(),
                                              [](const LicsConfig& c) { return loadLicsPolicy(c.policy); }),
      // The program's processes, one pool shared by the factory's controllers (each worker
      // thread reuses its process); paths resolved against the config file's folder.
      sharedEntry<external::ExternalConfig, external::ExternalController>(
          "external", [](external::ExternalConfig& c, const std::string& source) { c = resolveExternalPaths(c, source); },
          externalPathKeys(),
          [](const external::ExternalConfig& c) {
            return std::make_shared<external::ChildProcessPool>(external::ChildCommand{c.command, c.working_dir});
          }),
  };
  return kEntries;
}

// The optional block that runs move_base's stack beside any controller (global_plan_feed.hpp).
constexpr const char* kGlobalPlanKey = "global_plan";
// The type of a Python class's config (the Python front end writes and reads it; the registry
// only maps its paths).
constexpr const char* kPythonType = "python";

const Entry& findEntry(const core::ConfigNode& config, std::string& type) {
  if (!config.isMap() || !config.has("type")) throw core::InputError(config.where("type") + ": missing (the controller type)");
  if (!config.child("type").read(type)) throw core::InputError(config.where("type") + ": expected a string");
  for (const Entry& e : entries())
    if (type == e.type) {
      core::Errors errors;
      std::vector<std::string> seen;
      for (const std::string& key : config.keys()) {
        if (std::find(seen.begin(), seen.end(), key) != seen.end())
          errors.add(config.where(key), "duplicate key");
        else if (key != "type" && key != type && key != kGlobalPlanKey)
          errors.add(config.where(key), "unknown key (expected 'type', '" + type + "' and optionally '" + kGlobalPlanKey + "')");
        seen.push_back(key);
      }
      errors.throwIfAny();
      return e;
    }
  std::string known;
  for (const auto& name : controllerTypes()) known += (known.empty() ? "" : ", ") + name;
  throw core::InputError(config.where("type") + ": unknown controller '" + type + "' (known: " + known + ")");
}

}  // namespace

std::vector<std::string> controllerTypes() {
  std::vector<std::string> names;
  for (const Entry& e : entries()) names.emplace_back(e.type);
  return names;
}

PreparedController prepareController(const core::ConfigNode& config) {
  std::string type;
  PreparedController prepared;
  prepared.factory = findEntry(config, type).make(config.child(type), prepared.effective_config);
  if (config.has(kGlobalPlanKey)) {
    const core::ConfigNode block = config.child(kGlobalPlanKey);
    auto plan = readValidated<GlobalPlanConfig>(block, kNoPaths);
    prepared.effective_config += blockText(kGlobalPlanKey, plan);
    prepared.factory = [plan, inner = std::move(prepared.factory)] {
      return std::make_unique<GlobalPlanFedController>(plan, inner());
    };
  }
  return prepared;
}

std::vector<core::FieldRow> controllerSchema(const core::ConfigNode& config) {
  std::string type;
  return findEntry(config, type).schema(config.child(type));
}

std::string controllerKeyUnit(const std::string& type, const std::string& key) {
  core::ConfigNode config;
  config.set("type", type);
  std::vector<core::FieldRow> rows;
  try {
    rows = controllerSchema(config);
  } catch (const core::InputError&) {
    return {};  // not a controller type
  }
  const std::string block_prefix = type + ".";
  const std::string relative = key.starts_with(block_prefix) ? key.substr(block_prefix.size()) : key;
  for (const core::FieldRow& row : rows)
    if (row.key == relative) return row.unit;
  return {};
}

ControllerFactory makeControllerFactory(const core::ConfigNode& config) { return prepareController(config).factory; }

std::string effectiveControllerConfig(const core::ConfigNode& config) { return prepareController(config).effective_config; }

std::string mapControllerPaths(const core::ConfigNode& config, const PathMap& map) {
  std::string type;
  const PathKeys keys = config.isMap() && config.child("type").read(type) && type == kPythonType
                             ? pythonPathKeys()
                             : findEntry(config, type).paths;  // (global_plan has no paths)
  // A copy, every other field as it is (older records keep the fields they had).
  core::ConfigNode mapped = core::ConfigNode::parseString(config.toYaml(), config.source());
  const core::ConfigNode block = config.child(type);
  for (const std::string& key : keys.paths) {
    std::string path;
    if (block.child(key).read(path)) mapped.setString(type + "." + key, map(path));
  }
  std::vector<std::string> command;
  if (!keys.arguments.empty() && block.child(keys.arguments).read(command)) {
    for (std::size_t i = 1; i < command.size(); ++i) command[i] = map(command[i]);
    mapped.setStrings(type + "." + keys.arguments, command);
  }
  return mapped.toYaml();
}

}  // namespace barn::controllers
