#include "barn/core/text_io.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
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

}  // namespace
}  // namespace barn::core
