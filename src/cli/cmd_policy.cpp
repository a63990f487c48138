// barn policy act: run a network file (an LfLH policy, a transformer policy or an APPLR actor)
// on scans from stdin, one command per scan. `barn lflh act` is the same command.

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "barn/learning/applr_policy.hpp"
#include "barn/learning/policy.hpp"
#include "barn/learning/transformer_policy.hpp"
#include "commands.hpp"

namespace barn::cli {

namespace {

// The first lines of the formats.
const std::string kLflhMagic = "format: barnbench-lflh-policy";
const std::string kTransformerMagic = "format: barnbench-transformer-policy";
const std::string kApplrMagic = "format: barnbench-applr-policy";

struct PolicyActOptions {
  std::string policy;
  std::vector<double> goal = {1.0, 0.0};
};

bool startsWithLine(const std::string& text, const std::string& line) { return text.rfind(line + "\n", 0) == 0; }

}  // namespace

// One command per scan read from stdin: a line of the policy's beams ranges [m] in ROS order,
// separated by spaces or commas ("inf" for no return), gives the line "v w" (an LfLH policy),
// "v_hat w_hat" (a transformer policy, before the controller's scaling) or the actor's parameters
// in its action order (an APPLR actor, whose input is the goal's angle atan2(y, x)).
void runPolicyAct(const std::string& policy_path, const std::vector<double>& goal_xy) {
  const std::string bytes = core::readTextFile(policy_path);
  std::optional<learning::Policy> lflh;
  std::optional<learning::TransformerPolicy> transformer;
  std::optional<learning::ApplrPolicy> applr;
  int beams = 0;
  const Eigen::Vector2d goal(goal_xy.at(0), goal_xy.at(1));
  if (startsWithLine(bytes, kTransformerMagic)) {
    transformer.emplace(learning::TransformerPolicy::parse(bytes, policy_path));
    beams = transformer->info().shape.beams;  // any goal, (0, 0) included: the network takes it as given
  } else if (startsWithLine(bytes, kLflhMagic)) {
    lflh.emplace(learning::Policy::parse(bytes, policy_path));
    beams = lflh->info().beams;
    if (!(goal.norm() > 0.0)) throw core::InputError("--goal: must not be (0, 0)");
  } else if (startsWithLine(bytes, kApplrMagic)) {
    applr.emplace(learning::ApplrPolicy::parse(bytes, policy_path));
    beams = applr->info().beams;
  } else {
    throw core::InputError(policy_path + ": not a barnbench policy file (its first line must be '" + kLflhMagic + "', '" +
                           kTransformerMagic + "' or '" + kApplrMagic + "')");
  }
  std::string line;
  int number = 0;
  while (std::getline(std::cin, line)) {
    ++number;
    for (char& c : line)
      if (c == ',' || c == '\t' || c == '\r') c = ' ';
    core::LaserScan scan;
    std::istringstream fields(line);
    std::string field;
    while (fields >> field) {
      double r = 0.0;
      if (!core::parseDouble(field, r)) throw core::InputError("stdin line " + std::to_string(number) + ": '" + field + "' is not a number");
      scan.ranges.push_back(r);
    }
    if (scan.ranges.empty()) continue;
    if (scan.ranges.size() != static_cast<std::size_t>(beams))
      throw core::InputError("stdin line " + std::to_string(number) + ": " + std::to_string(scan.ranges.size()) +
                             " ranges, the policy takes " + std::to_string(beams));
    if (applr) {
      const std::vector<double> parameters = applr->act(scan, std::atan2(goal.y(), goal.x()));
      for (std::size_t i = 0; i < parameters.size(); ++i) std::printf(i ? " %.9g" : "%.9g", parameters[i]);
      std::printf("\n");
    } else if (transformer) {
      const Eigen::Vector2d command = transformer->act(scan, goal);
      std::printf("%.9g %.9g\n", command.x(), command.y());
    } else {
      const core::Twist command = lflh->act(scan, goal);
      std::printf("%.9g %.9g\n", command.linear, command.angular);
    }
  }
}

void addPolicyCommand(CLI::App& app, CommandContext&) {
  CLI::App* cmd = app.add_subcommand("policy", "Network files: run one on scans");
  cmd->require_subcommand(1);
  auto options = std::make_shared<PolicyActOptions>();
  CLI::App* act = cmd->add_subcommand(
      "act",
      "Run a policy file (LfLH, transformer or APPLR actor) on scans from stdin (one line of ranges each, ROS beam "
      "order) and print \"v w\" per scan (a transformer: \"v_hat w_hat\", before the controller's scaling; an APPLR "
      "actor: its parameters in its action order, scaled and clipped into their ranges)");
  act->add_option("--policy", options->policy, "Policy file, e.g. configs/policies/lflh_1ms.policy")->required();
  act->add_option("--goal", options->goal,
                  "Local goal in the robot frame, x forward, y left (default 1,0); an LfLH policy normalises it, a "
                  "transformer takes it as given, an APPLR actor reads its angle")
      ->expected(2)
      ->delimiter(',');
  act->callback([options] { runPolicyAct(options->policy, options->goal); });
}

}  // namespace barn::cli
