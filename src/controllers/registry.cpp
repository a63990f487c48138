#include "barn/controllers/registry.hpp"

#include "barn/controllers/dwa.hpp"
#include "barn/controllers/e2e.hpp"
#include "barn/controllers/eband.hpp"
#include "barn/controllers/external.hpp"
#include "barn/controllers/global_plan_feed.hpp"
#include "barn/controllers/in2bot.hpp"
#include "barn/controllers/inventec.hpp"
#include "barn/controllers/kulfm.hpp"
#include "barn/controllers/lflh.hpp"
#include "barn/controllers/pure_pursuit.hpp"
#include "barn/controllers/rrsl_vfh.hpp"
#include "barn/controllers/straight.hpp"
#include "barn/controllers/ut_amrl.hpp"

namespace barn::controllers {

namespace {

// One entry per controller type: reads and validates its block, returns a factory and the
// effective config text.
struct Entry {
  const char* type;
  std::function<ControllerFactory(const core::ConfigNode&, std::string&)> make;
};

template <class Config, class ControllerType>
Entry entry(const char* type) {
  return {type, [type](const core::ConfigNode& block, std::string& effective) -> ControllerFactory {
            Config config = core::readConfig<Config>(block);
            core::Errors errors;
            validate(config, errors, block.where());
            errors.throwIfAny();
            core::ConfigWriter writer(2);
            config.visit(writer);
            effective = std::string("type: ") + type + "\n" + type + ":\n" + writer.text();
            return [config] { return std::make_unique<ControllerType>(config); };
          }};
}

// A controller that runs a learned policy: the policy file (resolved against the config file's
// folder) is loaded once here and shared, read-only, by every episode's controller.
template <class Config, class ControllerType>
Entry policyEntry(const char* type) {
  return {type, [type](const core::ConfigNode& block, std::string& effective) -> ControllerFactory {
            Config config = core::readConfig<Config>(block);
            config.policy = resolvePolicyPath(config.policy, block.source());
            core::Errors errors;
            validate(config, errors, block.where());
            errors.throwIfAny();
            auto policy = std::make_shared<const learning::Policy>(learning::Policy::load(config.policy));
            core::ConfigWriter writer(2);
            config.visit(writer);
            effective = std::string("type: ") + type + "\n" + type + ":\n" + writer.text();
            return [config, policy] { return std::make_unique<ControllerType>(config, policy); };
          }};
}

// The End-to-End actor (an MLP policy file, resolved against the config file's folder), loaded
// once and shared by every episode's controller.
Entry e2eEntry() {
  return {"e2e", [](const core::ConfigNode& block, std::string& effective) -> ControllerFactory {
            E2eConfig config = core::readConfig<E2eConfig>(block);
            config.policy = resolvePolicyPath(config.policy, block.source());
            core::Errors errors;
            validate(config, errors, block.where());
            errors.throwIfAny();
            auto policy = std::make_shared<const learning::MlpPolicy>(learning::MlpPolicy::load(config.policy));
            core::ConfigWriter writer(2);
            config.visit(writer);
            effective = "type: e2e\ne2e:\n" + writer.text();
            return [config, policy] { return std::make_unique<E2eController>(config, policy); };
          }};
}

// A controller program run as a child process: paths resolved against the config file's folder
// (the effective config records them absolute), one process pool per factory, shared by every
// episode's controller so each worker thread reuses its process.
Entry externalEntry() {
  return {"external", [](const core::ConfigNode& block, std::string& effective) -> ControllerFactory {
            ExternalConfig config = resolveExternalPaths(core::readConfig<ExternalConfig>(block), block.source());
            core::Errors errors;
            validate(config, errors, block.where());
            errors.throwIfAny();
            core::ConfigWriter writer(2);
            config.visit(writer);
            effective = "type: external\nexternal:\n" + writer.text();
            auto pool = std::make_shared<ChildProcessPool>(ChildCommand{config.command, config.working_dir});
            return [config, pool] { return std::make_unique<ExternalController>(config, pool); };
          }};
}

const std::vector<Entry>& entries() {
  static const std::vector<Entry> kEntries = {
      entry<StraightConfig, StraightController>("straight"),
      entry<PurePursuitConfig, PurePursuitController>("pure_pursuit"),
      entry<DwaConfig, DwaController>("dwa"),
      entry<EbandConfig, EbandController>("eband"),
      entry<UtAmrlConfig, UtAmrlController>("ut_amrl"),
      policyEntry<LflhConfig, LflhController>("lflh"),
      policyEntry<InventecConfig, InventecController>("inventec"),
      entry<RrslVfhConfig, RrslVfhController>("rrsl_vfh"),
      entry<In2botConfig, In2botController>("in2bot"),
      entry<KulfmConfig, KulfmController>("kulfm"),
      e2eEntry(),
      externalEntry(),
  };
  return kEntries;
}

// The optional block that runs move_base's stack beside any controller (global_plan_feed.hpp).
constexpr const char* kGlobalPlanKey = "global_plan";

const Entry& findEntry(const core::ConfigNode& config, std::string& type) {
  if (!config.isMap() || !config.has("type")) throw core::InputError(config.where("type") + ": missing (the controller type)");
  if (!config.child("type").read(type)) throw core::InputError(config.where("type") + ": expected a string");
  for (const Entry& e : entries())
    if (type == e.type) {
      core::Errors errors;
      for (const std::string& key : config.keys())
        if (key != "type" && key != type && key != kGlobalPlanKey)
          errors.add(config.where(key), "unknown key (expected 'type', '" + type + "' and optionally '" + kGlobalPlanKey + "')");
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
    auto plan = core::readConfig<GlobalPlanConfig>(block);
    core::Errors errors;
    validate(plan, errors, block.where());
    errors.throwIfAny();
    core::ConfigWriter writer(2);
    plan.visit(writer);
    prepared.effective_config += std::string(kGlobalPlanKey) + ":\n" + writer.text();
    prepared.factory = [plan, inner = std::move(prepared.factory)] {
      return std::make_unique<GlobalPlanFedController>(plan, inner());
    };
  }
  return prepared;
}

ControllerFactory makeControllerFactory(const core::ConfigNode& config) { return prepareController(config).factory; }

std::string effectiveControllerConfig(const core::ConfigNode& config) { return prepareController(config).effective_config; }

}  // namespace barn::controllers
