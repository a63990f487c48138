// The defects of the reliability audit of 2026-11-27, each as the behaviour a user relies on,
// end to end through the barn executable: a kill or a full disk never leaves a record that
// reads as something it is not, two writers of one folder never silently lose one's work, and
// bad input is refused with the file and field named.
//
// Exit codes (src/cli/main.cpp): 0 ok, 1 the work failed (a run, a write), 2 bad usage or input.
// Kills at an exact system call use strace's fault injection (skipped where strace is missing).
// Most tests run pure_pursuit on 10 worlds (0:300:30) x 1 trial, ~0.2 s.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"

namespace {

using namespace barn::test;

namespace fs = std::filesystem;
using testing::AllOf;
using testing::AnyOf;
using testing::HasSubstr;
using testing::Not;

const fs::path kRepo = BARN_SOURCE_DIR;

// 10 worlds x 1 trial: worlds 0, 30, ..., 270.
const std::string kSmallRun = "run --controller pure_pursuit --worlds 0:300:30 --jobs 2";

/// Runs `command` through the shell; stdout and stderr interleaved.
RunResult shell(const std::string& command) {
  const fs::path capture = uniqueTempPath("barn_shell_output");
  const int status = std::system((command + " > " + quote(capture) + " 2>&1").c_str());
  RunResult result;
  result.output = readFile(capture);
  std::error_code ec;
  fs::remove(capture, ec);
  if (status != -1 && WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
  return result;
}

bool haveStrace() { return std::system("command -v strace > /dev/null 2>&1") == 0; }
bool havePython() { return std::system("command -v python3 > /dev/null 2>&1") == 0; }

/// `barn ARGS` under strace, killed (SIGKILL) at the system call `inject` selects, e.g.
/// "-e inject=rename:signal=SIGKILL:when=3". Only the named calls stop the process.
RunResult killedAt(const std::string& trace, const std::string& barn_args) {
  return shell("strace -f -o /dev/null " + trace + " " + quote(kBarn) + " " + barn_args);
}

/// The first `lines` lines of `text`.
std::string firstLines(const std::string& text, int lines) {
  std::size_t end = 0;
  for (int i = 0; i < lines && end != std::string::npos; ++i) {
    end = text.find('\n', end);
    if (end != std::string::npos) ++end;
  }
  return text.substr(0, end);
}

/// The names in `dir` (recursively, relative), sorted.
std::vector<std::string> namesBelow(const fs::path& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::recursive_directory_iterator(dir, ec)) names.push_back(fs::relative(entry.path(), dir).string());
  std::sort(names.begin(), names.end());
  return names;
}

/// Holds `dir`'s lock as a running barn does (flock on .barn.lock) until destroyed.
class HeldLock {
 public:
  explicit HeldLock(const fs::path& dir) {
    fs::create_directories(dir);
    fd_ = ::open((dir / ".barn.lock").c_str(), O_RDWR | O_CREAT, 0644);
    if (fd_ >= 0 && ::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      ::close(fd_);
      fd_ = -1;
    }
  }
  ~HeldLock() {
    if (fd_ >= 0) ::close(fd_);
  }
  bool held() const { return fd_ >= 0; }

 private:
  int fd_ = -1;
};

class Reliability : public testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(fs::exists(kBarn)) << kBarn << " not built";
    dir_ = uniqueTempPath("barn_reliability_test");
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  /// A complete small record (10 worlds x 1 trial) in dir_/name.
  fs::path smallRecord(const std::string& name, const std::string& extra = "") {
    const fs::path out = dir_ / name;
    const RunResult r = run(kSmallRun + " --out " + quote(out) + " " + extra);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return out;
  }

  /// A copy of the committed baseline's `name` reference in dir_/baseline/name.
  fs::path baselineCopy(const std::string& name) {
    const fs::path to = dir_ / "baseline" / name;
    std::error_code ec;
    fs::remove_all(to, ec);
    fs::create_directories(to);
    for (const char* file : {"manifest.yaml", "episodes.csv", "summary.json"})
      fs::copy_file(kRepo / "results" / "baseline" / name / file, to / file);
    return to;
  }

  /// Writes `text` as dir_/name and returns its path.
  fs::path file(const std::string& name, const std::string& text) {
    writeFile(dir_ / name, text);
    return dir_ / name;
  }

  fs::path dir_;
};

// ---------------------------------------------------------------------------------------------
// D1, D12: regress --update

TEST_F(Reliability, RegressUpdateKilledMidCopyLeavesTheOldBaseline) {
  if (!haveStrace()) GTEST_SKIP() << "needs strace";
  const std::string original = readFile(kRepo / "results" / "baseline" / "pure_pursuit" / "episodes.csv");
  const fs::path record = dir_ / "baseline" / "pure_pursuit";
  const std::string update = "regress --baseline " + quote(dir_ / "baseline") + " --controllers pure_pursuit --jobs 2 --work " +
                             quote(dir_ / "work") + " --update";
  // Killed in the middle of writing the baseline's episodes.csv (a copy's second sendfile), and
  // at the first rename of the new files into the baseline.
  const std::vector<std::string> kills = {
      "-e trace=sendfile -e inject=sendfile:signal=SIGKILL:when=2",
      "-P " + quote(record / "manifest.yaml") + " -e trace=rename,renameat,renameat2 " +
          "-e inject=rename,renameat,renameat2:signal=SIGKILL:when=1"};
  for (const std::string& kill : kills) {
    SCOPED_TRACE(kill);
    baselineCopy("pure_pursuit");
    std::error_code ec;
    fs::remove_all(dir_ / "work", ec);
    killedAt(kill, update);
    // Either the reference reads whole, with every one of its rows, or every reader refuses it
    // (and so does the gate): never a baseline of fewer rows that makes any rerun pass.
    const RunResult shown = run("show " + quote(record));
    if (shown.exit_code == 0) {
      EXPECT_EQ(readFile(record / "episodes.csv"), original);
      EXPECT_THAT(shown.output, HasSubstr("episodes 100"));
    } else {
      EXPECT_EQ(shown.exit_code, 2) << shown.output;
      EXPECT_THAT(shown.output, HasSubstr("interrupted"));
      const RunResult gate = run("regress --baseline " + quote(dir_ / "baseline") + " --controllers pure_pursuit --work " +
                                 quote(dir_ / "work"));
      EXPECT_EQ(gate.exit_code, 2) << gate.output;
      // The next update completes the interrupted one: the reference is whole again.
      EXPECT_EQ(run(update).exit_code, 0);
      EXPECT_EQ(readFile(record / "episodes.csv"), original);
    }
  }
}

TEST_F(Reliability, RegressUpdateWithADeeperWorkFolderKeepsTheBaselinesPaths) {
  // The rerun in a/b/c/work is three folders deeper than the baseline: the manifest written
  // into the baseline still finds the worlds (its paths are relative to the baseline).
  const fs::path record = baselineCopy("pure_pursuit");
  const RunResult r = run("regress --baseline " + quote(dir_ / "baseline") + " --controllers pure_pursuit --jobs 2 --work " +
                          quote(dir_ / "a" / "b" / "c" / "work") + " --update");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const RunResult shown = run("show " + quote(record));
  EXPECT_EQ(shown.exit_code, 0) << shown.output;
  EXPECT_THAT(readFile(record / "manifest.yaml"),
              HasSubstr("worlds_folder: \"" + fs::relative(kRepo / "worlds", fs::weakly_canonical(record)).string() + "\""));
}

// ---------------------------------------------------------------------------------------------
// D2: the one reader of a finished record

TEST_F(Reliability, EveryReaderRefusesARecordWithMissingRows) {
  const fs::path full = smallRecord("full");
  const fs::path cut = dir_ / "cut";
  fs::create_directories(cut);
  for (const char* name : {"manifest.yaml", "summary.json"}) fs::copy_file(full / name, cut / name);
  // The header and the rows of worlds 0, 30 and 60: the manifest says 10 episodes.
  writeFile(cut / "episodes.csv", firstLines(readFile(full / "episodes.csv"), 4));
  const std::vector<std::string> readers = {
      "show " + quote(cut),
      "compare " + quote(full) + " " + quote(cut),
      "export-out " + quote(cut) + " --out " + quote(dir_ / "out.txt"),
      "report " + quote(cut) + " -o " + quote(dir_ / "r.html") + " --max-failures 0",
      "plot scores " + quote(cut) + " -o " + quote(dir_ / "s.png")};
  for (const std::string& reader : readers) {
    const RunResult r = run(reader);
    EXPECT_EQ(r.exit_code, 2) << reader << "\n" << r.output;
    EXPECT_THAT(r.output, HasSubstr("episodes.csv: 3 rows, the manifest says 10 (world 90 trial 0 missing)")) << reader;
  }
  EXPECT_FALSE(fs::exists(dir_ / "out.txt"));
  // An empty file is not a record of no episodes.
  writeFile(cut / "episodes.csv", "");
  const RunResult empty = run("show " + quote(cut));
  EXPECT_EQ(empty.exit_code, 2) << empty.output;
  EXPECT_THAT(empty.output, HasSubstr("episodes.csv"));
}

TEST_F(Reliability, MergeRefusesAShardWithMissingRows) {
  for (const char* k : {"1", "2"}) {
    const RunResult r = run(kSmallRun + " --shard " + std::string(k) + "/2 --out " + quote(dir_ / ("s" + std::string(k))));
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  // Shard 2 of 2 holds worlds 30, 90, ..., 270 (every other episode): one row removed.
  writeFile(dir_ / "s2" / "episodes.csv", firstLines(readFile(dir_ / "s2" / "episodes.csv"), 5));
  const RunResult r = run("merge " + quote(dir_ / "s1") + " " + quote(dir_ / "s2") + " --out " + quote(dir_ / "m"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("4 rows, the manifest says 5 (world 270 trial 0 missing)"));
  EXPECT_FALSE(fs::exists(dir_ / "m" / "manifest.yaml"));
}

// ---------------------------------------------------------------------------------------------
// D3, D10: one writer per folder

TEST_F(Reliability, RunForceRefusesARecordAnotherProcessIsWriting) {
  const fs::path record = smallRecord("r");
  const std::string before = readFile(record / "manifest.yaml");
  HeldLock lock(record);  // a process still writing the record (a run, a resume, Python)
  ASSERT_TRUE(lock.held());
  const RunResult r = run("run --controller straight --worlds 0:5 --out " + quote(record) + " --force");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("another barn process is writing this folder"));
  EXPECT_EQ(readFile(record / "manifest.yaml"), before);
  EXPECT_FALSE(fs::exists(record.string() + ".new"));
}

TEST_F(Reliability, RunForceRefusesToDiscardAnUnfinishedRecord) {
  const fs::path record = dir_ / "r";
  ASSERT_EQ(run(kSmallRun + " --out " + quote(record) + " --stop-after 3").exit_code, 1);
  const std::string journal = readFile(record / "episodes.partial.csv");
  const RunResult r = run("run --controller straight --worlds 0:5 --out " + quote(record) + " --force");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, AllOf(HasSubstr("unfinished run"), HasSubstr("--resume")));
  EXPECT_EQ(readFile(record / "episodes.partial.csv"), journal);  // the finished episodes are kept
  EXPECT_EQ(run("run --resume " + quote(record)).exit_code, 0);
}

TEST_F(Reliability, MergeAndImportOutRefuseAnOutAnotherProcessIsWriting) {
  for (const char* k : {"1", "2"})
    ASSERT_EQ(run(kSmallRun + " --shard " + std::string(k) + "/2 --out " + quote(dir_ / ("s" + std::string(k)))).exit_code, 0);
  const fs::path out = dir_ / "out";
  HeldLock lock(out);
  ASSERT_TRUE(lock.held());
  const RunResult merged = run("merge " + quote(dir_ / "s1") + " " + quote(dir_ / "s2") + " --out " + quote(out));
  EXPECT_EQ(merged.exit_code, 2) << merged.output;
  EXPECT_THAT(merged.output, HasSubstr("another barn process is writing this folder"));
  const fs::path results = file("a.txt", "0 1 0 0 19.2 0.25\n30 0 1 0 3.0 0\n");
  const RunResult imported = run("import-out " + quote(results) + " --world-dir " + quote(kRepo / "worlds") + " --out " + quote(out));
  EXPECT_EQ(imported.exit_code, 2) << imported.output;
  EXPECT_THAT(imported.output, HasSubstr("another barn process is writing this folder"));
  EXPECT_FALSE(fs::exists(out / "manifest.yaml"));
}

// ---------------------------------------------------------------------------------------------
// D6, D16: a kill at any rename leaves something a rerun or --resume finishes

TEST_F(Reliability, ASweepKilledDuringStartUpResumesOrRunsAgain) {
  if (!haveStrace()) GTEST_SKIP() << "needs strace";
  const std::string sweep = "sweep --controller pure_pursuit --param speed=0.4,0.6 --worlds 0:4 --jobs 2 --out ";
  for (int when = 1; when <= 6; ++when) {
    SCOPED_TRACE("killed at rename " + std::to_string(when));
    const fs::path out = dir_ / ("sw" + std::to_string(when));
    killedAt("-e trace=rename,renameat,renameat2 -e inject=rename,renameat,renameat2:signal=SIGKILL:when=" +
                 std::to_string(when),
             sweep + quote(out));
    // What a requeued Slurm task does (tools/slurm/barn_array.sbatch): resume if sweep.yaml or
    // a commit note (an interrupted write) is there, else start it again.
    const bool resume = fs::exists(out / "sweep.yaml") || fs::exists(out / ".barn.commit");
    const RunResult again = resume ? run("sweep --resume " + quote(out) + " --jobs 2") : run(sweep + quote(out));
    EXPECT_EQ(again.exit_code, 0) << again.output;
    EXPECT_TRUE(fs::exists(out / "sweep.csv"));
  }
}

TEST_F(Reliability, AWorldSetKilledDuringItsRenamesIsNeverReadMixed) {
  if (!haveStrace()) GTEST_SKIP() << "needs strace";
  const fs::path one = dir_ / "one", two = dir_ / "two", out = dir_ / "gm";
  ASSERT_EQ(run("generate --out " + quote(one) + " --worlds-per-set 1 --seed 1").exit_code, 0);
  ASSERT_EQ(run("generate --out " + quote(two) + " --worlds-per-set 1 --seed 2").exit_code, 0);
  for (int when : {2, 3, 8}) {
    SCOPED_TRACE("killed at rename " + std::to_string(when));
    std::error_code ec;
    fs::remove_all(out, ec);
    ASSERT_EQ(run("generate --out " + quote(out) + " --worlds-per-set 1 --seed 1").exit_code, 0);
    killedAt("-e trace=rename,renameat,renameat2 -e inject=rename,renameat,renameat2:signal=SIGKILL:when=" +
                 std::to_string(when),
             "generate --out " + quote(out) + " --worlds-per-set 1 --seed 2 --force");
    const RunResult r = run("run --controller straight --world-dir " + quote(out) + " --worlds all --jobs 2 --out " +
                            quote(dir_ / ("g" + std::to_string(when))));
    if (r.exit_code == 0) {
      // Read: then it is one whole set, either the old one or the new one.
      const std::string index = readFile(out / "index.csv");
      EXPECT_TRUE(index == readFile(one / "index.csv") || index == readFile(two / "index.csv"));
      const fs::path& whole = index == readFile(one / "index.csv") ? one : two;
      for (const auto& entry : fs::directory_iterator(whole)) {
        if (entry.path().filename() == ".barn.lock") continue;
        EXPECT_EQ(readFile(out / entry.path().filename()), readFile(entry.path())) << entry.path().filename();
      }
    } else {
      EXPECT_EQ(r.exit_code, 2) << r.output;
      EXPECT_THAT(r.output, HasSubstr("interrupted"));
      // Any writer of the folder completes the set it had committed to.
      EXPECT_EQ(run("generate --out " + quote(out) + " --worlds-per-set 1 --seed 2 --force").exit_code, 0);
      EXPECT_EQ(readFile(out / "index.csv"), readFile(two / "index.csv"));
    }
  }
}

// ---------------------------------------------------------------------------------------------
// D7, D8, D9: what a run reads is exactly what it runs

TEST_F(Reliability, AControllerConfigWithADuplicateKeyOrASecondDocumentIsRefused) {
  const std::vector<std::pair<std::string, std::string>> configs = {
      {"type: pure_pursuit\ntype: straight\n", "type: duplicate key"},
      {"type: pure_pursuit\npure_pursuit:\n  speed: 0.5\npure_pursuit:\n  speed: 1.9\n", "pure_pursuit: duplicate key"},
      {"type: pure_pursuit\n---\ntype: straight\n", "a second YAML document"},
      {"type: pure_pursuit\n...\ngarbage: [\n", "not valid YAML"}};
  for (std::size_t i = 0; i < configs.size(); ++i) {
    const fs::path config = file("c" + std::to_string(i) + ".yaml", configs[i].first);
    const RunResult r = run("run --controller x --config " + quote(config) + " --worlds 0 --out " + quote(dir_ / "r"));
    EXPECT_EQ(r.exit_code, 2) << configs[i].first << r.output;
    EXPECT_THAT(r.output, AllOf(HasSubstr(config.string()), HasSubstr(configs[i].second))) << configs[i].first;
    EXPECT_FALSE(fs::exists(dir_ / "r" / "manifest.yaml"));
  }
  // The sim config and world files go through the same reader.
  const fs::path sim = file("sim.yaml", readFile(kRepo / "configs" / "sim" / "barn.yaml") + "---\nprotocol: barn2024\n");
  const RunResult r = run("run --controller pure_pursuit --sim-config " + quote(sim) + " --worlds 0 --out " + quote(dir_ / "r"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("a second YAML document"));
}

TEST_F(Reliability, ASweepRefusesTheSameSettingUnderTwoNames) {
  const RunResult r = run("sweep --controller pure_pursuit --param speed=0.3,0.9 --param pure_pursuit.speed=0.6 --worlds 0:3 "
                          "--out " + quote(dir_ / "s"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("the same setting (pure_pursuit.speed)"));
  EXPECT_FALSE(fs::exists(dir_ / "s" / "sweep.yaml"));
}

TEST_F(Reliability, ResumeAndMergeRefuseAChangedPolicyFile) {
  // The config names a copy of one policy; between the sessions it is replaced by another of
  // the same shape (a retrain): going on would mix the two in one record.
  const fs::path policy = dir_ / "p.policy";
  fs::copy_file(kRepo / "configs" / "policies" / "lflh_1ms.policy", policy);
  const fs::path config = file("lflh.yaml", "type: lflh\nlflh:\n  policy: p.policy\n");
  const std::string lflh = "run --controller lflh --config " + quote(config) + " --worlds 0:300:60 --jobs 1 --out ";
  ASSERT_EQ(run(lflh + quote(dir_ / "r") + " --stop-after 2").exit_code, 1);
  ASSERT_EQ(run(lflh + quote(dir_ / "s1") + " --shard 1/2").exit_code, 0);
  EXPECT_THAT(readFile(dir_ / "r" / "manifest.yaml"), HasSubstr("  - path: \"../p.policy\"\n    digest: "));
  fs::copy_file(kRepo / "configs" / "policies" / "lflh_2ms.policy", policy, fs::copy_options::overwrite_existing);
  const RunResult resumed = run("run --resume " + quote(dir_ / "r"));
  EXPECT_EQ(resumed.exit_code, 2) << resumed.output;
  EXPECT_THAT(resumed.output, AllOf(HasSubstr("p.policy: changed since the run started")));
  ASSERT_EQ(run(lflh + quote(dir_ / "s2") + " --shard 2/2").exit_code, 0);
  const RunResult merged = run("merge " + quote(dir_ / "s1") + " " + quote(dir_ / "s2") + " --out " + quote(dir_ / "m"));
  EXPECT_EQ(merged.exit_code, 2) << merged.output;
  EXPECT_THAT(merged.output, HasSubstr("config_files differs"));
}

TEST_F(Reliability, RegressRefusesAPolicyThatIsNotTheOneTheReferenceRan) {
  // The reference names dir_/p.policy (as the committed one names configs/policies/...) with
  // the digest of the policy it ran; the file there now is another policy of the same shape.
  const fs::path record = baselineCopy("lflh");
  std::string manifest = readFile(record / "manifest.yaml");
  for (std::size_t at; (at = manifest.find("../../../configs/policies/lflh_1ms.policy")) != std::string::npos;)
    manifest.replace(at, std::string("../../../configs/policies/lflh_1ms.policy").size(), "../../p.policy");
  writeFile(record / "manifest.yaml", manifest);
  fs::copy_file(kRepo / "configs" / "policies" / "lflh_2ms.policy", dir_ / "p.policy");
  const RunResult r = run("regress --baseline " + quote(dir_ / "baseline") + " --controllers lflh --work " + quote(dir_ / "w"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("p.policy is not the file the reference run used"));
  EXPECT_THAT(r.output, Not(HasSubstr("rerunning")));
}

// ---------------------------------------------------------------------------------------------
// D11, D13, D14: outputs

TEST_F(Reliability, AReportNeverTouchesAnotherReportsScratchFigures) {
  // A report drawing into this folder's .barn_report.tmp (the old fixed scratch): another
  // report into the same folder must leave its figure alone.
  const fs::path record = smallRecord("r");
  const fs::path other = dir_ / "out" / ".barn_report.tmp";
  fs::create_directories(other);
  writeFile(other / "scores.png", "another report's figure");
  const RunResult r = run("report " + quote(record) + " -o " + quote(dir_ / "out" / "a.html") + " --max-failures 0");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(readFile(other / "scores.png"), "another report's figure");
  // Two at once into one folder: both whole.
  const RunResult both = shell(quote(kBarn) + " report " + quote(record) + " -o " + quote(dir_ / "out" / "b.html") +
                               " --max-failures 0 & " + quote(kBarn) + " report " + quote(record) + " -o " +
                               quote(dir_ / "out" / "c.html") + " --max-failures 0 & wait");
  EXPECT_EQ(readFile(dir_ / "out" / "b.html"), readFile(dir_ / "out" / "a.html")) << both.output;
  EXPECT_EQ(readFile(dir_ / "out" / "c.html"), readFile(dir_ / "out" / "a.html"));
}

TEST_F(Reliability, AFullStdoutIsAnErrorNotAShortFile) {
  const fs::path record = smallRecord("r");
  const std::vector<std::string> commands = {"config " + quote(record), "show " + quote(record),
                                             "world info " + quote(kRepo / "worlds" / "world_000.yaml") + " --json"};
  for (const std::string& command : commands) {
    const RunResult r = shell("(" + quote(kBarn) + " " + command + " > /dev/full)");
    EXPECT_EQ(r.exit_code, 1) << command << "\n" << r.output;
    EXPECT_THAT(r.output, HasSubstr("stdout: write failed: No space left on device")) << command;
  }
}

TEST_F(Reliability, AFailedWriteLeavesNoTemporaryAndResumeClearsWhatKillsLeft) {
  const fs::path record = dir_ / "r";
  ASSERT_EQ(run(kSmallRun + " --out " + quote(record) + " --stop-after 3").exit_code, 1);
  // A file size limit of 1 KiB: the config (about 2 KiB of lflh settings) cannot be written.
  const fs::path lflh = dir_ / "lflh";
  ASSERT_EQ(run("run --controller lflh --worlds 0 --out " + quote(lflh)).exit_code, 0);
  const RunResult full = shell("trap '' XFSZ; ulimit -f 1; " + quote(kBarn) + " config " + quote(lflh) + " --out " + quote(dir_ / "cfg.yaml"));
  EXPECT_EQ(full.exit_code, 1) << full.output;
  EXPECT_THAT(full.output, HasSubstr("cfg.yaml"));
  for (const std::string& name : namesBelow(dir_)) EXPECT_THAT(name, Not(HasSubstr("cfg.yaml"))) << "left behind";
  // What writers killed in the middle leave in a record is removed by the next writer of it.
  fs::create_directories(record / ".staging.tmp-99999999");
  writeFile(record / ".staging.tmp-99999999" / "episodes.csv", "half");
  writeFile(record / "manifest.yaml.tmp-99999999", "half");
  ASSERT_EQ(run("run --resume " + quote(record)).exit_code, 0);
  EXPECT_EQ(namesBelow(record), (std::vector<std::string>{".barn.lock", "episodes.csv", "manifest.yaml", "summary.json"}));
}

// ---------------------------------------------------------------------------------------------
// D15: trajectories

TEST_F(Reliability, TrajectoriesOfAnInterruptedRunAreCompleteAfterResume) {
  const fs::path record = dir_ / "r";
  ASSERT_EQ(run(kSmallRun + " --trajectories --out " + quote(record) + " --stop-after 4").exit_code, 1);
  EXPECT_THAT(readFile(record / "manifest.yaml"), HasSubstr("trajectories: true"));
  // The record keeps trajectories: resume writes them asked or not; one started without them
  // cannot get them midway.
  const fs::path without = dir_ / "without";
  ASSERT_EQ(run(kSmallRun + " --out " + quote(without) + " --stop-after 2").exit_code, 1);
  const RunResult flagged = run("run --resume " + quote(without) + " --trajectories");
  EXPECT_EQ(flagged.exit_code, 2) << flagged.output;
  EXPECT_THAT(flagged.output, HasSubstr("was started without trajectories"));
  // A journaled episode whose file is lost runs again.
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(record / "trajectories")) files.push_back(entry.path());
  ASSERT_FALSE(files.empty());
  fs::remove(files.front());
  ASSERT_EQ(run("run --resume " + quote(record)).exit_code, 0);
  int count = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(record / "trajectories")) ++count;
  EXPECT_EQ(count, 10);
  // The same bytes as an uninterrupted run's.
  const fs::path whole = smallRecord("whole", "--trajectories");
  EXPECT_EQ(readFile(record / "episodes.csv"), readFile(whole / "episodes.csv"));
  for (const auto& entry : fs::directory_iterator(whole / "trajectories"))
    EXPECT_EQ(readFile(record / "trajectories" / entry.path().filename()), readFile(entry.path())) << entry.path();
}

TEST_F(Reliability, MergedShardsCarryTheirTrajectories) {
  for (const char* k : {"1", "2"})
    ASSERT_EQ(run(kSmallRun + " --trajectories --shard " + std::string(k) + "/2 --out " + quote(dir_ / ("s" + std::string(k))))
                  .exit_code,
              0);
  ASSERT_EQ(run("merge " + quote(dir_ / "s1") + " " + quote(dir_ / "s2") + " --out " + quote(dir_ / "m")).exit_code, 0);
  const fs::path whole = smallRecord("whole", "--trajectories");
  EXPECT_THAT(readFile(dir_ / "m" / "manifest.yaml"), HasSubstr("trajectories: true"));
  EXPECT_EQ(namesBelow(dir_ / "m" / "trajectories"), namesBelow(whole / "trajectories"));
  for (const auto& entry : fs::directory_iterator(whole / "trajectories"))
    EXPECT_EQ(readFile(dir_ / "m" / "trajectories" / entry.path().filename()), readFile(entry.path())) << entry.path();
}

// ---------------------------------------------------------------------------------------------
// D5, D17, D18: external programs

class ReliabilityExternal : public Reliability {
 protected:
  void SetUp() override {
    Reliability::SetUp();
    if (!havePython()) GTEST_SKIP() << "needs python3";
  }
  /// A config running `script` (written beside it) at 10 Hz.
  fs::path external(const std::string& name, const std::string& script) {
    file(name + ".py", script);
    return file(name + ".yaml", "type: external\nexternal: {command: [python3, " + name + ".py], rate: 10}\n");
  }
  /// The episodes.csv rows of `record` by world id.
  std::map<int, std::string> rows(const fs::path& record) {
    std::map<int, std::string> out;
    std::istringstream in(readFile(record / "episodes.csv"));
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) out[std::stoi(line.substr(0, line.find(',')))] = line;
    return out;
  }
};

// Stands still, answering its n-th observation with the state label `label` (Python, of n).
std::string labelling(const std::string& label) {
  return "import json, sys\n"
         "n = 0\n"
         "for line in sys.stdin:\n"
         "    if json.loads(line)['type'] == 'reset':\n"
         "        n = 0\n"
         "        print('{\"ok\": true}', flush=True)\n"
         "        continue\n"
         "    n += 1\n"
         "    print(json.dumps({'v': 0.0, 'w': 0.0, 'state': " + label + "}), flush=True)\n";
}

TEST_F(ReliabilityExternal, AControllerFloodingStateLabelsFailsOnlyItsEpisodes) {
  // 100 distinct labels, and a 300-byte one: each ends its episode as an error naming the
  // limit (64 labels, 64 bytes); the run completes and the rows stay small.
  const fs::path many = external("many", labelling("'s%d' % n"));
  const fs::path wide = external("wide", labelling("'y' * 300"));
  for (const fs::path& config : {many, wide}) {
    const fs::path out = dir_ / config.stem();
    const RunResult r = run("run --controller x --config " + quote(config) + " --worlds 2,3 --jobs 1 --out " + quote(out));
    EXPECT_EQ(r.exit_code, 1) << r.output;  // error episodes
    for (const auto& [world, row] : rows(out)) {
      EXPECT_THAT(row, AllOf(HasSubstr(",error,"), AnyOf(HasSubstr("more than 64 distinct state labels"),
                                                          HasSubstr("(the limit is 64 bytes)")))) << row;
      EXPECT_LT(row.size(), 8000u);
    }
  }
}

TEST_F(ReliabilityExternal, AnExtraAnswerLineFailsItsOwnEpisode) {
  // The program answers observation 3 twice: that episode fails (it would otherwise go on with
  // every command one tick late), and the next one runs normally on a fresh process.
  // (Only once, marked by a file: the next episode's fresh process answers normally.) Both
  // lines go out in one write, so they reach barn together: a line written later, after barn
  // has sent the next message, cannot be told from the next answer (docs/external_controller.md).
  const fs::path config = external("twice", "import json, os, sys\n"
                                            "n = 0\n"
                                            "for line in sys.stdin:\n"
                                            "    if json.loads(line)['type'] == 'reset':\n"
                                            "        n = 0\n"
                                            "        print('{\"ok\": true}', flush=True)\n"
                                            "        continue\n"
                                            "    n += 1\n"
                                            "    answer = json.dumps({'v': 0.5, 'w': 0.0, 'state': 'obs%d' % n})\n"
                                            "    if n == 3 and not os.path.exists('twice.done'):\n"
                                            "        open('twice.done', 'w').close()\n"
                                            "        answer += '\\n' + answer\n"
                                            "    print(answer, flush=True)\n");
  const fs::path out = dir_ / "tw";
  const RunResult r = run("run --controller t --config " + quote(config) + " --worlds 2:4 --jobs 1 --out " + quote(out));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  const auto by_world = rows(out);
  ASSERT_EQ(by_world.size(), 2u);
  EXPECT_THAT(by_world.at(2), AllOf(HasSubstr(",error,"), AnyOf(HasSubstr("answer no message"), HasSubstr("more than one line"))));
  EXPECT_THAT(by_world.at(3), Not(HasSubstr(",error,")));
}

TEST_F(ReliabilityExternal, HelpersOfAFailedProgramDoNotOutliveIt) {
  // The program starts a helper that keeps its stdout open, then exits with status 4 at its
  // first observation: the helper goes with it, and the error says the program exited.
  const fs::path pid_file = dir_ / "helper.pid";
  const fs::path config = external("forker", "import json, os, subprocess, sys\n"
                                             "for line in sys.stdin:\n"
                                             "    if json.loads(line)['type'] == 'reset':\n"
                                             "        print('{\"ok\": true}', flush=True)\n"
                                             "        continue\n"
                                             "    helper = subprocess.Popen(['sleep', '60'])\n"
                                             "    open(" + ("'" + pid_file.string() + "'") + ", 'w').write(str(helper.pid))\n"
                                             "    os._exit(4)\n");
  const RunResult r = run("run --controller f --config " + quote(config) + " --worlds 0 --jobs 1 --out " + quote(dir_ / "fk"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  const std::string row = readFile(dir_ / "fk" / "episodes.csv");
  EXPECT_THAT(row, AllOf(HasSubstr("exited without answering"), HasSubstr("exited with status 4")));
  ASSERT_TRUE(fs::exists(pid_file));
  const pid_t helper = std::stoi(readFile(pid_file));
  // Killed: gone, or a zombie until whoever adopted it reaps it (the signal takes a moment).
  bool alive = true;
  for (int wait = 0; wait < 100 && alive; ++wait) {
    const std::string stat = readFile("/proc/" + std::to_string(helper) + "/stat");
    alive = !stat.empty() && stat.find(") Z ") == std::string::npos;
    if (alive) ::usleep(20000);
  }
  if (alive) ::kill(helper, SIGKILL);
  EXPECT_FALSE(alive) << "helper " << helper << " survived";
}

// ---------------------------------------------------------------------------------------------
// D19: Slurm submission

TEST_F(Reliability, SubmitRefusesItsOwnOptionsAfterTheModeAndBadBarnArguments) {
  const std::string submit = quote(kRepo / "tools" / "slurm" / "submit.sh");
  // --dry-run after `run` would have been passed to barn, and the job array submitted for real.
  const RunResult late = shell(submit + " run " + quote(dir_ / "out") + " --shards 3 --controller pure_pursuit --dry-run");
  EXPECT_EQ(late.exit_code, 2) << late.output;
  EXPECT_THAT(late.output, HasSubstr("--shards"));
  EXPECT_THAT(late.output, Not(HasSubstr("submitted")));
  // barn's own arguments are checked once before anything is queued.
  const RunResult unknown = shell(submit + " --dry-run run " + quote(dir_ / "out") + " --controller nosuch");
  EXPECT_EQ(unknown.exit_code, 2) << unknown.output;
  EXPECT_THAT(unknown.output, HasSubstr("nosuch"));
  EXPECT_THAT(unknown.output, Not(HasSubstr("sbatch")));
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

// ---------------------------------------------------------------------------------------------
// D20: provenance

TEST_F(Reliability, TheRecordedCommitIsTheOneBuiltFromWhateverTheEnvironment) {
  // Another repository in GIT_DIR (or none on PATH) does not change what barn says it is.
  const fs::path other = dir_ / "other";
  fs::create_directories(other);
  ASSERT_EQ(shell("cd " + quote(other) + " && git init -q . && git -c user.name=t -c user.email=t@t commit -q --allow-empty -m x")
                .exit_code,
            0);
  const RunResult plain = run("--version");
  const RunResult elsewhere = shell("GIT_DIR=" + quote(other / ".git") + " " + quote(kBarn) + " --version");
  const RunResult no_git = shell("PATH=/nonexistent " + quote(kBarn) + " --version");
  EXPECT_EQ(elsewhere.output, plain.output);
  EXPECT_EQ(no_git.output, plain.output);
}

// ---------------------------------------------------------------------------------------------
// D23, D24, D25, D27: messages, coercions, bounds, paths

TEST_F(Reliability, FailedWritesExitOneAndBadOutputPathsAreNamed) {
  const fs::path record = smallRecord("r");
  const RunResult figure = run("plot scores " + quote(record) + " -o " + quote(dir_ / "missing" / "s.png"));
  EXPECT_EQ(figure.exit_code, 1) << figure.output;
  EXPECT_THAT(figure.output, HasSubstr("s.png: cannot write"));
  const fs::path a_file = file("a_file", "x");
  const RunResult out_file = run("run --controller straight --worlds 0 --out " + quote(a_file));
  EXPECT_EQ(out_file.exit_code, 2) << out_file.output;
  EXPECT_THAT(out_file.output, HasSubstr("--out " + a_file.string() + ": is a file, expected a folder"));
  const RunResult to_folder = run("export-out " + quote(record) + " --out " + quote(dir_));
  EXPECT_EQ(to_folder.exit_code, 2) << to_folder.output;
  EXPECT_THAT(to_folder.output, AllOf(HasSubstr("is a folder"), Not(HasSubstr("Success"))));
  const RunResult long_name = run("run --controller straight --worlds 0 --out " + quote(dir_ / std::string(300, 'x')));
  EXPECT_EQ(long_name.exit_code, 2) << long_name.output;
  EXPECT_THAT(long_name.output, AllOf(HasSubstr("File name too long"), Not(HasSubstr("filesystem error"))));
}

TEST_F(Reliability, NumbersAreReadExactlyNeverWrappedOrSaturated) {
  for (const std::string seed : {"18446744073709551616", "0x10", "-1"}) {
    const RunResult r = run("run --controller straight --worlds 0 --seed " + seed + " --out " + quote(dir_ / "r"));
    EXPECT_EQ(r.exit_code, 2) << seed << r.output;
  }
  EXPECT_EQ(run("run --controller straight --worlds 0 --stop-after -1 --out " + quote(dir_ / "r")).exit_code, 2);
  // A quoted " -1" seed in a world file is not 2^64 - 1.
  const fs::path worlds = dir_ / "w";
  fs::create_directories(worlds);
  std::string world = readFile(kRepo / "worlds" / "world_000.yaml");
  world = replaceLine(world, "seed:", "seed: \" -1\"");
  writeFile(worlds / "world_000.yaml", world);
  const RunResult quoted = run("run --controller straight --world-dir " + quote(worlds) + " --worlds all --out " + quote(dir_ / "r"));
  EXPECT_EQ(quoted.exit_code, 2) << quoted.output;
  EXPECT_THAT(quoted.output, HasSubstr("seed"));
  // A file whose name says another world than its id.
  writeFile(worlds / "world_000.yaml", replaceLine(readFile(kRepo / "worlds" / "world_000.yaml"), "id:", "id: 7"));
  const RunResult renamed = run("run --controller straight --world-dir " + quote(worlds) + " --worlds all --out " + quote(dir_ / "r"));
  EXPECT_EQ(renamed.exit_code, 2) << renamed.output;
  EXPECT_THAT(renamed.output, HasSubstr("world_000.yaml: id: 7, but the file's name says world 0"));
  // Journal rows: a world id past INT_MAX, a NaN score.
  const fs::path record = dir_ / "j";
  ASSERT_EQ(run(kSmallRun + " --out " + quote(record) + " --stop-after 2").exit_code, 1);
  const std::string journal = readFile(record / "episodes.partial.csv");
  const std::string header_and_first = firstLines(journal, 2);
  const std::string first_row = header_and_first.substr(header_and_first.find('\n') + 1);
  writeFile(record / "episodes.partial.csv", journal + "4294967296" + first_row.substr(first_row.find(',')));
  const RunResult wrapped = run("run --resume " + quote(record));
  EXPECT_EQ(wrapped.exit_code, 2) << wrapped.output;
  EXPECT_THAT(wrapped.output, HasSubstr("world: '4294967296' is not a whole number from 0 to 1000000000"));
  std::vector<std::string> fields;
  std::istringstream split(first_row.substr(0, first_row.size() - 1));
  for (std::string f; std::getline(split, f, ',');) fields.push_back(f);
  fields[5] = "nan";
  std::string nan_row;
  for (std::size_t i = 0; i < fields.size(); ++i) nan_row += (i ? "," : "") + fields[i];
  writeFile(record / "episodes.partial.csv", firstLines(journal, 1) + nan_row + ",\n");
  const RunResult nan = run("run --resume " + quote(record));
  EXPECT_EQ(nan.exit_code, 2) << nan.output;
  EXPECT_THAT(nan.output, HasSubstr("score: 'nan' is not a finite number"));
  // sweep --resume takes nothing but how to run.
  const RunResult sweep = run("sweep --resume " + quote(dir_ / "s") + " --param speed=9");
  EXPECT_EQ(sweep.exit_code, 2) << sweep.output;
  EXPECT_THAT(sweep.output, HasSubstr("--param"));
}

TEST_F(Reliability, UnboundedSimAndExternalValuesAreRefused) {
  const std::string sim = readFile(kRepo / "configs" / "sim" / "barn.yaml");
  const fs::path heavy = file("heavy.yaml", replaceLine(sim, "  velocity_iterations:", "  velocity_iterations: 100000000"));
  const RunResult r = run("run --controller straight --sim-config " + quote(heavy) + " --worlds 0 --out " + quote(dir_ / "r"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("physics.velocity_iterations: must be in [1, 1000]"));
  const fs::path slow = file("slow.yaml", "type: external\nexternal: {command: [python3, x.py], timeout: 1e19}\n");
  file("x.py", "");
  const RunResult e = run("run --controller x --config " + quote(slow) + " --worlds 0 --out " + quote(dir_ / "r"));
  EXPECT_EQ(e.exit_code, 2) << e.output;
  EXPECT_THAT(e.output, HasSubstr("external.timeout: must be <= 86400"));
}

TEST_F(Reliability, ARecordReachedThroughASymlinkAtAnotherDepthResumes) {
  // The record's paths are relative to where it is (dir_/rec); the link is three folders
  // deeper, so its "../" lead elsewhere when read from the link's name.
  const fs::path record = dir_ / "rec";
  ASSERT_EQ(run(kSmallRun + " --out " + quote(record) + " --stop-after 2").exit_code, 1);
  fs::create_directories(dir_ / "a" / "b" / "c");
  fs::create_directory_symlink(record, dir_ / "a" / "b" / "c" / "link");
  const RunResult r = run("run --resume " + quote(dir_ / "a" / "b" / "c" / "link"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(run("show " + quote(dir_ / "a" / "b" / "c" / "link")).exit_code, 0);
}

TEST_F(Reliability, AControllerNameIsNotAPath) {
  const RunResult r = run("run --controller ../../../../../etc/x --worlds 0");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("not a path"));
}

}  // namespace
