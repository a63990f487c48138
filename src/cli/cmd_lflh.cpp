// barn lflh collect|train|act: the LfLH pipeline (exploration logs, hallucinated demonstrations,
// behaviour cloning into a policy file).

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "barn/bench/record_session.hpp"
#include "barn/core/text_io.hpp"
#include "barn/learning/exploration.hpp"
#include "barn/learning/hallucination.hpp"
#include "barn/learning/lflh_config.hpp"
#include "barn/learning/policy.hpp"
#include "barn/learning/trainer.hpp"
#include "barn/viz/line_plot.hpp"
#include "commands.hpp"

namespace barn::cli {

namespace {

namespace fs = std::filesystem;

struct LflhOptions {
  std::string config;
  std::string sim_config;  // collect: the plant (default configs/sim/barn.yaml)
  std::string out;
  std::string data;
  int epochs = 0;  // 0: the config's
  std::string policy;
  std::vector<double> goal = {1.0, 0.0};
};

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// `policy.policy` -> `policy.<suffix>` beside it.
fs::path besidePolicy(const fs::path& policy, const std::string& suffix) {
  fs::path path = policy;
  path.replace_extension(suffix);
  return path;
}

void runCollect(const LflhOptions& options) {
  const learning::LflhPipelineConfig config = learning::readLflhPipelineConfig(options.config);
  const auto start = std::chrono::steady_clock::now();
  // The robot and physics of the sim config: the policy learns how that robot moves.
  const bench::EpisodeConfig plant = episodeConfigFor(options.sim_config, "");
  const learning::Recording recording =
      learning::collectExploration(config.collect, config.name, plant.robot, plant.physics);
  const fs::path path = learning::recordingPath(options.out, config.name);
  std::error_code ec;
  fs::create_directories(options.out, ec);
  if (ec) throw core::InputError(options.out + ": cannot create the folder: " + ec.message());
  learning::writeRecording(path, recording);
  const learning::ExplorationStats s = learning::explorationStats(recording);
  std::printf("%s: %zu records (%.1f s at %.0f Hz) in %.1f s\n", path.string().c_str(), s.records, s.duration,
              recording.rate, secondsSince(start));
  std::printf("  cmd v %.2f..%.2f m/s (%.0f %% at the top speed), cmd w %.2f..%.2f rad/s\n", s.cmd_v_min, s.cmd_v_max,
              100.0 * s.top_speed_share, s.cmd_w_min, s.cmd_w_max);
  std::printf("  mean speed %.2f m/s, %.0f m driven\n", s.mean_speed, s.distance);
}

void runTrain(const LflhOptions& options) {
  learning::LflhPipelineConfig config = learning::readLflhPipelineConfig(options.config);
  if (options.epochs > 0) config.train.epochs = options.epochs;
  // This config's recording, then those of the configs it also trains on, each checked against
  // the collect settings of its own config.
  const auto readChecked = [&](const learning::LflhPipelineConfig& c, const std::string& config_path) {
    const fs::path recording_path = learning::recordingPath(options.data, c.name);
    learning::Recording recording = learning::readRecording(recording_path);
    if (recording.name != c.name || recording.collect_hash != learning::collectHash(c.collect))
      throw core::InputError(recording_path.string() + ": recorded by '" + recording.name +
                             "' with other collect settings than " + config_path +
                             " (collect_hash differs); run `barn lflh collect` with that config again");
    return recording;
  };
  const learning::Recording recording = readChecked(config, options.config);

  const auto start = std::chrono::steady_clock::now();
  learning::Dataset data = learning::buildDataset(recording, config.hallucination, config.train.range_clip);
  std::size_t record_count = recording.records.size();
  for (const std::string& other_file : config.also_train_on) {
    const fs::path other_path = fs::path(options.config).parent_path() / other_file;
    const learning::LflhPipelineConfig other = learning::readLflhPipelineConfig(other_path);
    const learning::Recording other_recording = readChecked(other, other_path.string());
    // The other recording hallucinated with its own settings, encoded with this policy's clip.
    // One policy learns one plant: demonstrations of robots that move differently would teach it
    // commands that suit neither.
    if (other_recording.plant_hash != recording.plant_hash)
      throw core::InputError(learning::recordingPath(options.data, other.name).string() + " was recorded on another plant than " +
                             learning::recordingPath(options.data, config.name).string() +
                             " (plant_hash differs); collect both with the same --sim-config");
    learning::appendDataset(data, learning::buildDataset(other_recording, other.hallucination, config.train.range_clip));
    record_count += other_recording.records.size();
    std::printf("joined %s (%zu records)\n", other.name.c_str(), other_recording.records.size());
  }
  std::vector<std::size_t> train_columns, validation_columns;
  learning::splitDataset(data, config.train.validation_share, train_columns, validation_columns);
  std::printf("hallucinated %zu demonstrations from %zu records in %.1f s: %zu training, %zu validation\n", data.size(),
              record_count, secondsSince(start), train_columns.size(), validation_columns.size());

  const auto train_start = std::chrono::steady_clock::now();
  const learning::TrainingResult result =
      learning::trainPolicy(data, config.train, [&](const learning::EpochLoss& e) {
        std::printf("epoch %4d/%d  train %.5f  validation %.5f  %7.1f s\n", e.epoch, config.train.epochs, e.train,
                    e.validation, e.seconds);
        std::fflush(stdout);
      });
  const double mean_predictor = result.mean_predictor_loss;
  const double train_seconds = secondsSince(train_start);

  learning::PolicyInfo info;
  info.beams = data.beams;
  info.range_clip = config.train.range_clip;
  info.hidden = config.train.hidden;
  info.activation = config.train.activation;
  info.slope = config.train.leaky_slope;
  info.name = config.name;
  info.config_hash = learning::configHash(config);
  info.plant_hash = recording.plant_hash;
  info.trained = bench::utcNow();
  info.seed = config.train.seed;
  info.epochs = config.train.epochs;
  info.train_loss = result.history.back().train;
  info.validation_loss = result.history.back().validation;
  info.mean_predictor_loss = mean_predictor;
  const fs::path out(options.out);
  if (out.has_parent_path()) fs::create_directories(out.parent_path());
  learning::writePolicyFile(out, info, result.weights);
  const fs::path csv = besidePolicy(out, ".loss.csv");
  core::writeFileAtomic(csv, learning::lossCsv(result));

  viz::LinePlot plot;
  plot.title = config.name + " validation loss";
  plot.x_label = "epoch";
  plot.y_label = "loss  mean squared v and w error";
  viz::LineSeries train_series, validation_series;
  train_series.label = "train";
  validation_series.label = "validation";
  for (const learning::EpochLoss& e : result.history) {
    train_series.x.push_back(e.epoch);
    train_series.y.push_back(e.train);
    validation_series.x.push_back(e.epoch);
    validation_series.y.push_back(e.validation);
  }
  plot.series = {validation_series, train_series};
  plot.references = {{"predicting the mean command", mean_predictor}};
  const fs::path png = besidePolicy(out, ".loss.png");
  viz::renderLinePlot(plot, png);

  std::printf("trained %d epochs in %.1f s: train %.5f, validation %.5f, mean predictor %.5f (validation / mean %.3f)\n",
              config.train.epochs, train_seconds, info.train_loss, info.validation_loss, mean_predictor,
              info.validation_loss / mean_predictor);
  std::printf("wrote %s, %s, %s\n", out.string().c_str(), csv.string().c_str(), png.string().c_str());
}

}  // namespace

void addLflhCommand(CLI::App& app, CommandContext&) {
  CLI::App* cmd = app.add_subcommand("lflh", "LfLH: collect exploration data, train a policy on hallucinated obstacles");
  cmd->require_subcommand(1);
  auto options = std::make_shared<LflhOptions>();

  CLI::App* collect = cmd->add_subcommand("collect", "Drive the simulated Jackal randomly in open space and log it");
  collect->add_option("--config", options->config, "LfLH config, e.g. configs/lflh/1ms.yaml")->required();
  collect->add_option("--out", options->out, "Data folder (writes exploration_<name>.csv)")->required();
  collect->add_option("--sim-config", options->sim_config,
                      "Sim config whose robot and physics drive (default configs/sim/barn.yaml; train the policy on "
                      "the plant you will run it on)");
  collect->callback([options] { runCollect(*options); });

  CLI::App* train = cmd->add_subcommand("train", "Hallucinate obstacles around the log and train the policy");
  train->add_option("--config", options->config, "LfLH config, e.g. configs/lflh/1ms.yaml")->required();
  train->add_option("--data", options->data, "Data folder written by `barn lflh collect`")->required();
  train->add_option("--out", options->out, "Policy file, e.g. configs/policies/lflh_1ms.policy (.loss.csv/.loss.png beside)")
      ->required();
  train->add_option("--epochs", options->epochs, "Override train.epochs (part of the recorded config hash)")
      ->check(CLI::Range(1, 100000));
  train->callback([options] { runTrain(*options); });

  CLI::App* act = cmd->add_subcommand(
      "act", "Run a policy file on scans from stdin (one line of ranges each, ROS beam order) and print \"v w\" per scan "
             "(the same as `barn policy act`)");
  act->add_option("--policy", options->policy, "Policy file, e.g. configs/policies/lflh_1ms.policy")->required();
  act->add_option("--goal", options->goal, "Local goal direction in the robot frame, x forward, y left (default 1,0)")
      ->expected(2)
      ->delimiter(',');
  act->callback([options] { runPolicyAct(options->policy, options->goal); });
}

}  // namespace barn::cli
