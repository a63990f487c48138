#include "barn/core/text_io.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <stdexcept>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "barn/core/errors.hpp"

namespace barn::core {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

fs::path scratch(const std::string& stem) {
  const fs::path dir = fs::temp_directory_path() / (stem + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(TextIo, HexRoundTripsEveryWidthAndRefusesWhatIsNotHex) {
  for (const std::uint64_t value : {std::uint64_t{0}, std::uint64_t{0x1f}, std::uint64_t{0xd746bee9593fcd1bull},
                                    ~std::uint64_t{0}}) {
    std::uint64_t back = 1;
    ASSERT_TRUE(parseHex(formatHex(value), back)) << formatHex(value);
    EXPECT_EQ(back, value);
  }
  EXPECT_EQ(formatHex(0xabcull), "0xabc");
  std::uint64_t value = 7;
  EXPECT_TRUE(parseHex("ff", value));  // the prefix is optional
  EXPECT_EQ(value, 255u);
  for (const char* bad : {"", "0x", "0xg1", "12 ", "-1", "0x10000000000000000"}) EXPECT_FALSE(parseHex(bad, value)) << bad;
}

TEST(TextIo, AFolderIsNotReadAsAnEmptyFile) {
  const fs::path dir = scratch("barn_text_io_folder");
  try {
    readTextFile(dir);
    FAIL() << "a folder was read as a file";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("is a folder"));
  }
  fs::remove_all(dir);
}

TEST(TextIo, AtomicWritesLandWholeAndLeaveNoStagingBehind) {
  const fs::path dir = scratch("barn_text_io_atomic");
  writeFileAtomic(dir / "a.txt", "first");
  writeFileAtomic(dir / "a.txt", "second");
  EXPECT_EQ(readTextFile(dir / "a.txt"), "second");
  writeFilesAtomic(dir / "set", {{"x", "1"}, {"y", "22"}});
  EXPECT_EQ(readTextFile(dir / "set" / "y"), "22");
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir / "set")) ++entries;
  EXPECT_EQ(entries, 2);  // x and y, no staging folder
  fs::remove_all(dir);
}

TEST(TextIo, AtomicSetsMayHoldSubfolders) {
  const fs::path dir = scratch("barn_text_io_subfolders");
  writeFilesAtomic(dir, {{"top.txt", "t"}, {"a/one.txt", "1"}, {"a/b/two.txt", "2"}});
  EXPECT_EQ(readTextFile(dir / "top.txt"), "t");
  EXPECT_EQ(readTextFile(dir / "a" / "one.txt"), "1");
  EXPECT_EQ(readTextFile(dir / "a" / "b" / "two.txt"), "2");
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 2);  // top.txt and a/, no staging folder
  // Names that leave the folder are a programming error, refused before anything is written.
  EXPECT_THROW(writeFilesAtomic(dir, {{"ok.txt", "x"}, {"../out.txt", "x"}}), std::invalid_argument);
  EXPECT_THROW(writeFilesAtomic(dir, {{"/tmp/abs.txt", "x"}}), std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir / "ok.txt"));
  fs::remove_all(dir);
}

TEST(TextIo, AnAtomicSetWhoseSubfolderCannotBeMadeWritesNothing) {
  // "a" is a file, so "a/x.txt" cannot land: the error comes before "first.txt" is in place.
  const fs::path dir = scratch("barn_text_io_subfolder_fail");
  writeFileAtomic(dir / "a", "file");
  EXPECT_THROW(writeFilesAtomic(dir, {{"first.txt", "1"}, {"a/x.txt", "2"}}), IoError);
  EXPECT_FALSE(fs::exists(dir / "first.txt"));
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 1);  // just "a"
  fs::remove_all(dir);
}

TEST(TextIo, AFailedWriteIsAnIoErrorWithTheSystemsReason) {
  // A path below a regular file cannot be created: the error names it and says why.
  const fs::path dir = scratch("barn_text_io_fail");
  writeFileAtomic(dir / "file", "x");
  try {
    writeFileAtomic(dir / "file" / "below", "data");
    FAIL() << "no error";
  } catch (const IoError& e) {
    EXPECT_THAT(e.what(), HasSubstr("below"));
    EXPECT_THAT(e.what(), HasSubstr("Not a directory"));
  }
  fs::remove_all(dir);
}

// ---------------------------------------------------------------------------------------------
// Sets committed through a note, completed after a kill

TEST(TextIo, ASetKilledAfterItsCommitNoteIsCompletedByTheNextWriter) {
  // The state a kill leaves between the commit and its end: the note lists a, b and c to move
  // in and d to remove; a has already moved (staging no longer holds it), b and c have not.
  const fs::path dir = scratch("barn_text_io_commit");
  writeFileAtomic(dir / "a", "old a");
  writeFileAtomic(dir / "b", "old b");
  writeFileAtomic(dir / "d", "old d");
  fs::create_directories(dir / ".staging.tmp-777" / "sub");
  writeFileAtomic(dir / ".staging.tmp-777" / "b", "new b");
  writeFileAtomic(dir / ".staging.tmp-777" / "sub" / "c", "new c");
  writeFileAtomic(dir / "a", "new a");
  writeFileAtomic(dir / kCommitNote, "staging .staging.tmp-777\nrename a\nrename b\nrename sub/c\nremove d\n");
  // Readers see a mix of two versions: they refuse the folder, naming it.
  EXPECT_THAT([&] { checkNoInterruptedWrite(dir); }, ::testing::ThrowsMessage<InputError>(HasSubstr("interrupted")));
  EXPECT_TRUE(finishInterruptedWrite(dir));
  EXPECT_EQ(readTextFile(dir / "a"), "new a");
  EXPECT_EQ(readTextFile(dir / "b"), "new b");
  EXPECT_EQ(readTextFile(dir / "sub" / "c"), "new c");
  EXPECT_FALSE(fs::exists(dir / "d"));
  EXPECT_FALSE(fs::exists(dir / kCommitNote));
  EXPECT_FALSE(fs::exists(dir / ".staging.tmp-777"));
  EXPECT_NO_THROW(checkNoInterruptedWrite(dir));
  EXPECT_FALSE(finishInterruptedWrite(dir));  // nothing left to complete
  fs::remove_all(dir);
}

TEST(TextIo, RemovalsLandWithTheSetAndNoteAndStagingAreGone) {
  const fs::path dir = scratch("barn_text_io_removals");
  writeFilesAtomic(dir, {{"keep", "1"}, {"old", "1"}});
  writeFilesAtomic(dir, {{"keep", "2"}, {"new", "2"}}, {"old", "never_there"});
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"keep", "new"}));
  EXPECT_EQ(readTextFile(dir / "keep"), "2");
  fs::remove_all(dir);
}

TEST(TextIo, FinishingRemovesWhatKilledWritersLeftButNothingElse) {
  const fs::path dir = scratch("barn_text_io_leftovers");
  fs::create_directories(dir / ".staging.tmp-123" / "x");
  writeFileAtomic(dir / "manifest.yaml.tmp-456", "half");
  fs::create_directories(dir / "trajectories");
  writeFileAtomic(dir / "trajectories" / "world_0_trial_0.csv.tmp-789", "half");
  writeFileAtomic(dir / "trajectories" / "world_0_trial_0.csv", "whole");
  writeFileAtomic(dir / "notes.tmp-draft", "mine");  // not a pid: a user's file
  EXPECT_FALSE(finishInterruptedWrite(dir));
  EXPECT_FALSE(fs::exists(dir / ".staging.tmp-123"));
  EXPECT_FALSE(fs::exists(dir / "manifest.yaml.tmp-456"));
  EXPECT_FALSE(fs::exists(dir / "trajectories" / "world_0_trial_0.csv.tmp-789"));
  EXPECT_EQ(readTextFile(dir / "trajectories" / "world_0_trial_0.csv"), "whole");
  EXPECT_EQ(readTextFile(dir / "notes.tmp-draft"), "mine");
  fs::remove_all(dir);
}

TEST(TextIo, AWriteThatFailsMidwayLeavesTheOldFileAndNoTemporary) {
  // A file size limit of 100 bytes (a full disk's EFBIG): 1000 bytes cannot be written. In a
  // child process, so the limit stays there.
  const fs::path dir = scratch("barn_text_io_full");
  writeFileAtomic(dir / "f.txt", "old");
  const pid_t child = ::fork();
  if (child == 0) {
    ::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{100, 100};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    try {
      writeFileAtomic(dir / "f.txt", std::string(1000, 'x'));
    } catch (const IoError&) {
      ::_exit(0);
    }
    ::_exit(1);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "no IoError";
  EXPECT_EQ(readTextFile(dir / "f.txt"), "old");
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 1);  // f.txt alone: no f.txt.tmp-PID
  fs::remove_all(dir);
}

TEST(TextIo, AFileDigestReadsInPiecesAsTheWholeTextWould) {
  const fs::path dir = scratch("barn_text_io_digest");
  const std::string text(200000, 'q');  // longer than one 64 KiB piece
  writeFileAtomic(dir / "big", text);
  EXPECT_EQ(fnv1a64File(dir / "big"), fnv1a64(text));
  EXPECT_THROW(fnv1a64File(dir / "missing"), InputError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace barn::core
