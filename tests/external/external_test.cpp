#include "barn/external/external.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <bit>
#include <csignal>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <sys/wait.h>
#include <thread>
#include <vector>

#include "barn/bench/batch.hpp"
#include "barn/controllers/registry.hpp"
#include "barn/core/config.hpp"
#include "barn/core/world_geometry.hpp"
#include "barn/external/external_protocol.hpp"
#include "tests/bench/empty_world.hpp"

namespace barn::external {
namespace {

namespace fs = std::filesystem;
using controllers::ControllerFactory;
using controllers::CostGrid;
using controllers::effectiveControllerConfig;
using controllers::EpisodeInfo;
using controllers::GlobalPlan;
using controllers::makeControllerFactory;
using controllers::Observation;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;

// ---------------------------------------------------------------------------------------------
// Controller programs, written to a temporary folder by each test

// Answers every observation with doubles it was sent, chosen by the whole second of "time",
// so the test can check that each travels barn -> program -> barn unchanged.
constexpr char kProbe[] = R"(
import json, sys
info = None
episodes = 0
for line in sys.stdin:
    msg = json.loads(line)
    if msg["type"] == "reset":
        info = msg
        episodes += 1
        print(json.dumps({"ok": True}), flush=True)
        continue
    k = int(msg["time"])
    pairs = [
        (msg["pose"][0], msg["pose"][1]),
        (msg["pose"][2], msg["twist"][0]),
        (msg["twist"][1], msg["scan"][0]),
        (msg["scan"][2], 1.0 if msg["scan"][1] is None else 0.0),
        (msg["goal"][0], msg["goal"][1]),
        (info["start"][2], info["goal_tolerance"]),
        (info["period"], info["lidar"]["angle_increment"]),
        (float(episodes), float(len(msg["scan"]))),
        (float(info["seed"] == 18446744073709551615), float("reference_path" in info)),
    ]
    v, w = pairs[k]
    print(json.dumps({"v": float(v), "w": float(w), "state": "probe %d" % k}), flush=True)
)";

// Drives straight at 0.5 m/s; its state label counts the episodes this process has seen.
constexpr char kStraight[] = R"(
import json, sys
episodes = 0
for line in sys.stdin:
    msg = json.loads(line)
    if msg["type"] == "reset":
        episodes += 1
        print('{"ok": true}', flush=True)
    else:
        print(json.dumps({"v": 0.5, "w": 0.0, "state": "episode %d" % episodes}), flush=True)
)";

// Drives straight, but the first process to run (no marker file yet) misbehaves as argv[1]
// says at t = 0.5 s (or at the reset for "quit"); the processes after it are healthy.
constexpr char kFaulty[] = R"(
import json, os, sys, time
mode, marker = sys.argv[1], sys.argv[2]
faulty = not os.path.exists(marker)
open(marker, "a").close()
for line in sys.stdin:
    msg = json.loads(line)
    if faulty and (mode == "quit" or (msg["type"] == "observation" and msg["time"] >= 0.5)):
        sys.stderr.write("faulty controller: about to %s\n" % mode)
        sys.stderr.flush()
        if mode in ("crash", "quit"):
            raise RuntimeError("boom")
        if mode == "hang":
            time.sleep(60)
        if mode == "garbage":
            print("this is not json", flush=True)
            continue
        if mode == "close_stdin":  # answer, but read no more: barn's next write meets a closed pipe
            os.close(0)
            print('{"v": 0.5, "w": 0.0}', flush=True)
            time.sleep(60)
    print('{"ok": true}' if msg["type"] == "reset" else '{"v": 0.5, "w": 0.0}', flush=True)
)";

class ExternalControllerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char pattern[] = "/tmp/barn_external_test_XXXXXX";
    ASSERT_NE(mkdtemp(pattern), nullptr);
    dir_ = pattern;
    write("probe.py", kProbe);
    write("straight.py", kStraight);
    write("faulty.py", kFaulty);
  }
  void TearDown() override { fs::remove_all(dir_); }

  void write(const std::string& name, const std::string& text) const { std::ofstream(dir_ / name) << text; }

  // A factory for `script` with extra arguments, at 10 Hz.
  ControllerFactory factory(const std::string& script, const std::string& args = "", double timeout = 5.0) const {
    const std::string yaml = "type: external\nexternal: {command: [/usr/bin/python3, " + (dir_ / script).string() +
                             (args.empty() ? "" : ", " + args) + "], rate: 10, timeout: " + std::to_string(timeout) +
                             ", working_dir: " + dir_.string() + "}";
    return makeControllerFactory(core::ConfigNode::parseString(yaml, "test.yaml"));
  }

  fs::path dir_;
};

// Two episodes (trials) of the empty world, one after another on one thread.
std::vector<bench::EpisodeResult> runTwoEpisodes(const ControllerFactory& make, bool record = false) {
  bench::BatchSpec spec;
  spec.worlds = {bench::emptyWorld(7)};
  spec.trials = 2;
  spec.make_controller = make;
  spec.record_trajectories = record;
  return bench::runBatch(spec, {.jobs = 1});
}

std::uint64_t bits(double value) { return std::bit_cast<std::uint64_t>(value); }

// ---------------------------------------------------------------------------------------------
// Healthy programs

TEST_F(ExternalControllerTest, EveryDoubleReachesTheProgramAndComesBackBitForBit) {
  const ControllerFactory make = factory("probe.py");
  auto controller = make();
  EpisodeInfo info;
  info.start = {0.0, 0.0, 1.5707963267948966};
  info.goal = {0.0, 10.0};
  info.goal_tolerance = 1.0 / 3.0;
  info.seed = std::numeric_limits<std::uint64_t>::max();
  controller->reset(info);
  EXPECT_EQ(controller->period(), 0.1);

  core::LaserScan scan;
  scan.ranges = {5e-324, std::numeric_limits<double>::infinity(), 0.30000000000000004, 29.999};
  Observation obs;
  obs.scan = &scan;
  obs.odom_pose = {0.1, -0.0, 3.141592653589793};
  obs.odom_twist = {9007199254740992.0, 1e300};
  obs.goal = {-2.2250738585072014e-308, 123456.789e-20};
  const std::vector<std::pair<double, double>> expected = {
      {0.1, -0.0},
      {3.141592653589793, 9007199254740992.0},
      {1e300, 5e-324},
      {0.30000000000000004, 1.0},  // beam 1 had no return: null
      {-2.2250738585072014e-308, 123456.789e-20},
      {1.5707963267948966, 1.0 / 3.0},
      {0.1, info.lidar.angleIncrement()},
      {1.0, 4.0},  // first episode of this process; 4 beams
      {1.0, 0.0},  // the 64-bit seed arrived exactly; no reference path was sent
  };
  for (std::size_t k = 0; k < expected.size(); ++k) {
    obs.time = static_cast<double>(k) + 0.25;
    const core::Twist cmd = controller->act(obs);
    EXPECT_EQ(bits(cmd.linear), bits(expected[k].first)) << "probe " << k << ": v = " << cmd.linear;
    EXPECT_EQ(bits(cmd.angular), bits(expected[k].second)) << "probe " << k << ": w = " << cmd.angular;
    EXPECT_EQ(controller->stateLabel(), "probe " + std::to_string(k));
  }
}

TEST_F(ExternalControllerTest, DrivesAnEpisodeAndReusesItsProcessForTheNext) {
  const std::vector<bench::EpisodeResult> results = runTwoEpisodes(factory("straight.py"), true);
  ASSERT_EQ(results.size(), 2u);
  for (const bench::EpisodeResult& r : results) {
    ASSERT_EQ(r.outcome, bench::Outcome::Success) << r.error;
    // 10 m to the goal at 0.5 m/s, 1 m tolerance: about 9 / 0.5 = 18 s at 10 Hz.
    EXPECT_NEAR(r.actual_time, 18.0, 0.5);
    ASSERT_FALSE(r.trajectory.empty());
    for (const bench::TrajectorySample& s : r.trajectory) {
      EXPECT_EQ(s.command.linear, 0.5);
      EXPECT_EQ(s.command.angular, 0.0);
    }
  }
  // One worker thread, one process: it saw both resets.
  EXPECT_EQ(results[0].trajectory.front().state, "episode 1");
  EXPECT_EQ(results[1].trajectory.front().state, "episode 2");
}

TEST_F(ExternalControllerTest, LeavesNoChildProcessBehind) {
  {
    const ControllerFactory make = factory("straight.py");
    runTwoEpisodes(make);
    runTwoEpisodes(factory("faulty.py", "crash, " + (dir_ / "marker").string()));
  }
  int status = 0;
  EXPECT_EQ(waitpid(-1, &status, WNOHANG), -1) << "a child process is left (running or a zombie)";
  EXPECT_EQ(errno, ECHILD);
}

// ---------------------------------------------------------------------------------------------
// Failing programs: each fails only its own episode, and the next one runs on a fresh process

struct Failure {
  const char* mode;
  const char* message;  // what the episode's error must say
};

class ExternalControllerFailureTest : public ExternalControllerTest, public ::testing::WithParamInterface<Failure> {};

TEST_P(ExternalControllerFailureTest, FailsOnlyItsEpisodeWithTheProgramsStderr) {
  const Failure failure = GetParam();
  const auto start = std::chrono::steady_clock::now();
  const std::vector<bench::EpisodeResult> results =
      runTwoEpisodes(factory("faulty.py", std::string(failure.mode) + ", " + (dir_ / "marker").string(), 0.5));
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(results.size(), 2u);
  EXPECT_EQ(results[0].outcome, bench::Outcome::Error);
  EXPECT_THAT(results[0].error, AllOf(HasSubstr("faulty.py"), HasSubstr(failure.message),
                                      HasSubstr(std::string("faulty controller: about to ") + failure.mode)));
  EXPECT_EQ(results[1].outcome, bench::Outcome::Success) << results[1].error;
  EXPECT_LT(wall, 4.0) << "a failure must not hold the batch up";
}

INSTANTIATE_TEST_SUITE_P(
    Modes, ExternalControllerFailureTest,
    ::testing::Values(Failure{"crash", "exited with status 1"}, Failure{"quit", "failed at reset"},
                      Failure{"hang", "no answer within 0.5 s"}, Failure{"garbage", "malformed answer"},
                      Failure{"close_stdin", "closed its stdin"}),
    [](const auto& test) { return std::string(test.param.mode); });

TEST_F(ExternalControllerTest, CrashMessageCarriesThePythonTraceback) {
  const std::vector<bench::EpisodeResult> results =
      runTwoEpisodes(factory("faulty.py", "crash, " + (dir_ / "marker").string()));
  EXPECT_THAT(results[0].error, AllOf(HasSubstr("Traceback"), HasSubstr("RuntimeError: boom"),
                                      HasSubstr("failed at the observation at t = 0.50 s")));
}

// ---------------------------------------------------------------------------------------------
// Config

std::string factoryError(const std::string& yaml) {
  try {
    makeControllerFactory(core::ConfigNode::parseString(yaml, "run.yaml"));
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "";
}

TEST_F(ExternalControllerTest, NamesEveryBadField) {
  const std::string error = factoryError(
      "type: external\nexternal: {command: [no_such_program_xyz], rate: 0, timeout: -1, reset_timeout: 0, "
      "working_dir: /no/such/folder}");
  EXPECT_THAT(error, HasSubstr("run.yaml: external.command: program 'no_such_program_xyz' not found on PATH"));
  EXPECT_THAT(error, HasSubstr("external.rate: must be > 0"));
  EXPECT_THAT(error, HasSubstr("external.timeout: must be > 0"));
  EXPECT_THAT(error, HasSubstr("external.reset_timeout: must be > 0"));
  EXPECT_THAT(error, HasSubstr("external.working_dir: '/no/such/folder' is not a folder"));
  EXPECT_THAT(factoryError("type: external"), HasSubstr("external.command: must name the program"));
  EXPECT_THAT(factoryError("type: external\nexternal: {command: python3}"),
              HasSubstr("external.command: expected a list of strings"));
  // straight.py was written without execute permission.
  EXPECT_THAT(factoryError("type: external\nexternal: {command: [" + (dir_ / "straight.py").string() + "]}"),
              HasSubstr("is not an executable file"));
}

TEST_F(ExternalControllerTest, ResolvesPathsAgainstTheConfigFilesFolder) {
  write("ctrl.yaml", "type: external\nexternal: {command: [python3, straight.py, --gain, '2']}\n");
  const core::ConfigNode node = core::ConfigNode::parseFile(dir_ / "ctrl.yaml");
  const std::string effective = effectiveControllerConfig(node);
  // straight.py exists beside the config: made absolute; python3 (on PATH) and the other
  // arguments stay as written; working_dir "" is the config's folder.
  EXPECT_THAT(effective, HasSubstr("command: [python3, " + (dir_ / "straight.py").string() + ", --gain, 2]"));
  EXPECT_THAT(effective, HasSubstr("working_dir: " + dir_.string()));
  EXPECT_THAT(effective, AllOf(HasSubstr("rate: 20"), HasSubstr("timeout: 5"), HasSubstr("reset_timeout: 30")));
}

// ---------------------------------------------------------------------------------------------
// Protocol pieces

TEST(ExternalProtocol, NumbersReadBackAsTheSameDoubles) {
  // Every double barn sends must parse back to itself bit for bit (shortest round-trip form);
  // beams without a return go out as null.
  core::LaserScan scan;
  const double tricky[] = {0.1, 1.0, -0.0, 1e300, 5e-324, 2.0 / 3.0, 0.1 + 0.2, std::numeric_limits<double>::max()};
  scan.ranges.assign(std::begin(tricky), std::end(tricky));
  scan.ranges.push_back(std::numeric_limits<double>::infinity());
  Observation obs;
  obs.scan = &scan;
  external::CostmapsSent sent;
  const std::string message = external::observationMessage(obs, sent);
  const std::size_t open = message.find("\"scan\":[") + 8, close = message.find(']', open);
  std::vector<std::string> tokens;
  for (std::size_t at = open; at < close;) {
    const std::size_t comma = std::min(message.find(',', at), close);
    tokens.push_back(message.substr(at, comma - at));
    at = comma + 1;
  }
  ASSERT_EQ(tokens.size(), std::size(tricky) + 1);
  for (std::size_t i = 0; i < std::size(tricky); ++i) {
    const double back = std::strtod(tokens[i].c_str(), nullptr);
    EXPECT_EQ(std::bit_cast<std::uint64_t>(back), std::bit_cast<std::uint64_t>(tricky[i])) << tokens[i];
  }
  EXPECT_EQ(tokens.back(), "null");
}

TEST(ExternalProtocol, CommandsMaySetParameters) {
  const external::CommandAnswer a =
      external::readCommandAnswer(R"({"v": 0.5, "w": 0, "params": {"global_costmap.inflation_radius": 0.55, "planner.rate": 10}})");
  ASSERT_EQ(a.params.size(), 2u);
  EXPECT_EQ(a.params[0].first, "global_costmap.inflation_radius");
  EXPECT_EQ(a.params[0].second, 0.55);
  EXPECT_EQ(a.params[1].second, 10.0);
  for (const char* bad : {R"({"v": 0, "w": 0, "params": {"a": "x"}})", R"({"v": 0, "w": 0, "params": {"a": 1, "a": 2}})",
                          R"({"v": 0, "w": 0, "params": 3})", R"({"v": 0, "w": 0, "params": {"a": {"b": 1}}})",
                          R"({"v": 0, "w": 0, "params": {}, "params": {}})"})
    EXPECT_THROW(external::readCommandAnswer(bad), external::ProtocolError) << bad;
  std::string many = R"({"v": 0, "w": 0, "params": {)";
  for (int i = 0; i < 65; ++i) many += (i ? ", " : "") + std::string("\"k") + std::to_string(i) + "\": 1";
  EXPECT_THAT([&] { external::readCommandAnswer(many + "}}"); },
              ::testing::ThrowsMessage<external::ProtocolError>(HasSubstr("more than 64 parameters")));
}

TEST(ExternalProtocol, AnswersAreParsedAsStrictJson) {
  for (const char* bad : {"", "{", "{\"v\": 1,}", "{\"v\": 01, \"w\": 0}", "{\"v\": +1, \"w\": 0}", "{\"v\": .5, \"w\": 0}",
                          "{\"v\": NaN, \"w\": 0}", "{\"v\": Infinity, \"w\": 0}", "{\"v\": 1e999, \"w\": 0}",
                          "{\"v\": 1, \"w\": 0} x", "{\"v\": [1], \"w\": 0}", "{\"v\": 1, \"v\": 2, \"w\": 0}",
                          "{'v': 1, 'w': 0}", "{\"v\": 1 \"w\": 2}", "[1, 2]", "1"})
    EXPECT_THROW(external::readCommandAnswer(bad), external::ProtocolError) << bad;
  // More members than any answer has is refused at once, however many follow.
  std::string wide = "{\"v\": 0, \"w\": 0";
  for (int i = 0; i < 90000; ++i) wide += ", \"k" + std::to_string(i) + "\": 0";
  EXPECT_THAT([&] { external::readCommandAnswer(wide + "}"); },
              ::testing::ThrowsMessage<external::ProtocolError>(HasSubstr("too many members")));
}

TEST(ExternalProtocol, ARefusalQuotesAtMostAFewHundredCharactersOfAHugeToken) {
  // The parser's reason ends with the token it last read: an unterminated string or a number of
  // 100000 digits is that long. The message (an episode's error cell) quotes the answer up to
  // 200 characters and the reason up to 200: with the fixed text, well under 600 bytes.
  const std::string huge(100000, '7');
  for (const std::string& bad : {"{\"v\": \"" + huge, "{\"v\": 1" + huge + ", \"w\": 0}"}) {
    try {
      external::readCommandAnswer(bad);
      ADD_FAILURE() << "accepted";
    } catch (const external::ProtocolError& e) {
      EXPECT_LT(std::string(e.what()).size(), 600u) << std::string(e.what()).substr(0, 300);
      EXPECT_THAT(e.what(), HasSubstr("malformed answer at byte"));
    }
  }
}

TEST(ExternalProtocol, AnswersAreCheckedStrictly) {
  EXPECT_NO_THROW(external::readResetAnswer(R"({"ok": true})"));
  EXPECT_THAT([] { external::readResetAnswer(R"({"ok": false, "error": "no GPU"})"); },
              ::testing::ThrowsMessage<external::ProtocolError>(HasSubstr("refused the episode: no GPU")));
  EXPECT_THROW(external::readResetAnswer(R"({"v": 1})"), external::ProtocolError);
  const external::CommandAnswer a = external::readCommandAnswer(R"({"w": -0.25, "v": 0.5, "state": "Forward"})");
  EXPECT_EQ(a.command.linear, 0.5);
  EXPECT_EQ(a.command.angular, -0.25);
  EXPECT_EQ(a.state, "Forward");
  EXPECT_THAT([] { external::readCommandAnswer(R"({"v": 0.5})"); },
              ::testing::ThrowsMessage<external::ProtocolError>(HasSubstr("lacks \"w\"")));
  EXPECT_THROW(external::readCommandAnswer(R"({"v": "0.5", "w": 0})"), external::ProtocolError);
  EXPECT_THROW(external::readCommandAnswer(R"({"v": 0.5, "w": 0, "x": 1})"), external::ProtocolError);
}

TEST(ExternalProtocol, ObservationsWriteNullForBeamsWithoutReturn) {
  core::LaserScan scan;
  scan.ranges = {1.5, std::numeric_limits<double>::infinity()};
  Observation obs;
  obs.time = 0.05;
  obs.scan = &scan;
  obs.odom_pose = {1.0, 2.0, 0.5};
  obs.scan_odom_pose = {0.75, 2.0, 0.25};
  obs.odom_twist = {0.25, -0.125};
  obs.goal = {0.0, 10.0};
  external::CostmapsSent sent;
  EXPECT_EQ(external::observationMessage(obs, sent),
            R"({"type":"observation","time":0.05,"scan":[1.5,null],"pose":[1.0,2.0,0.5],)"
            R"("scan_pose":[0.75,2.0,0.25],"twist":[0.25,-0.125],"goal":[0.0,10.0]})");
  EXPECT_THAT(external::resetMessage(EpisodeInfo{}, 0.05), AllOf(HasSubstr(R"({"type":"reset","protocol":1,)"),
                                                                  HasSubstr(R"("period":0.05)"),
                                                                  Not(HasSubstr("reference_path"))));
}

TEST(ExternalProtocol, CostmapsGoOutOnlyWhenTheyChanged) {
  core::LaserScan scan;
  const std::uint8_t costs[6] = {0, 1, 2, 253, 254, 255};
  CostGrid grid{{-1.0, 2.0}, 0.5, 3, 2, costs, 7};
  GlobalPlan plan{{{0.0, 0.0, 0.0}, {0.5, 0.25, 1.5}}, 0.25};
  Observation obs;
  obs.scan = &scan;
  obs.global_plan = &plan;
  obs.local_costmap = &grid;
  external::CostmapsSent sent;
  // Bytes 00 01 02 | FD FE FF in base64: AAEC and /f7/.
  EXPECT_THAT(external::observationMessage(obs, sent),
              AllOf(HasSubstr(R"("global_plan":{"stamp":0.25,"poses":[[0.0,0.0,0.0],[0.5,0.25,1.5]]})"),
                    HasSubstr(R"("local_costmap":{"origin":[-1.0,2.0],"resolution":0.5,"width":3,"height":2,"costs":"AAEC/f7/"})")));
  EXPECT_THAT(external::observationMessage(obs, sent), Not(HasSubstr("local_costmap")));
  grid.version = 8;
  EXPECT_THAT(external::observationMessage(obs, sent), HasSubstr("local_costmap"));
}

// ---------------------------------------------------------------------------------------------
// ChildProcess: lockstep and the process group

TEST(ChildProcess, ASecondLineForOneMessageFailsTheExchange) {
  // One printf writes two lines for the first message: taking the first as the answer would
  // leave the second to be read as the answer to the next message, and so on, one tick late.
  ChildProcess child(ChildCommand{{"/bin/sh", "-c", "read m; printf 'a\\nb\\n'; read m; echo c"}, ""});
  const auto deadline = ChildProcess::Clock::now() + std::chrono::seconds(5);
  child.writeLine("first", deadline);
  std::string error;
  try {
    child.readLine(deadline);
    child.writeLine("second", deadline);  // b arrived separately: found before this is sent
  } catch (const ChildProcessError& e) {
    error = e.what();
  }
  EXPECT_THAT(error, ::testing::AnyOf(HasSubstr("more than one line"), HasSubstr("bytes that answer no message")));
}

TEST(ChildProcess, WhatAProgramStartedGoesWithItWhenItExits) {
  // The program starts a helper that holds its stdout, then exits with status 3 without
  // answering: the wait ends at the exit (not the 10 s deadline), and the helper is killed.
  ChildProcess child(ChildCommand{{"/bin/sh", "-c", "sleep 60 & echo $! > /dev/stderr; read m; exit 3"}, ""});
  const auto start = ChildProcess::Clock::now();
  child.writeLine("observation", start + std::chrono::seconds(10));
  EXPECT_THAT([&] { child.readLine(start + std::chrono::seconds(10)); },
              ::testing::ThrowsMessage<ChildProcessError>(HasSubstr("exited without answering")));
  EXPECT_LT(ChildProcess::Clock::now() - start, std::chrono::seconds(5));
  EXPECT_EQ(child.stop(), "exited with status 3");
  const pid_t helper = std::stoi(child.stderrTail());
  // Killed: gone, or a zombie until whoever adopted it reaps it (the signal takes a moment).
  bool running = true;
  std::string text;
  for (int wait = 0; wait < 100 && running; ++wait) {
    std::ifstream stat("/proc/" + std::to_string(helper) + "/stat");
    text.assign(std::istreambuf_iterator<char>(stat), std::istreambuf_iterator<char>());
    running = !text.empty() && text.find(") Z ") == std::string::npos;
    if (running) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (running) ::kill(helper, SIGKILL);
  EXPECT_FALSE(running) << "helper " << helper << " outlived the program: " << text;
}

}  // namespace
}  // namespace barn::external
