#include "barn/bench/results_io.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "barn/core/errors.hpp"

namespace barn::bench {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;

// Bit patterns, so -0.0 vs 0.0 and the last ulp both count.
std::uint64_t bits(double value) { return std::bit_cast<std::uint64_t>(value); }

// Every field the CSV carries, compared exactly (the collision's time, rectangle and pose are
// not columns, so only its point is compared).
void expectSameRow(const EpisodeResult& a, const EpisodeResult& b) {
  EXPECT_EQ(a.world_id, b.world_id);
  EXPECT_EQ(a.trial, b.trial);
  EXPECT_EQ(a.seed, b.seed);
  EXPECT_EQ(a.outcome, b.outcome);
  EXPECT_EQ(bits(a.actual_time), bits(b.actual_time)) << a.actual_time << " vs " << b.actual_time;
  EXPECT_EQ(bits(a.score), bits(b.score)) << a.score << " vs " << b.score;
  EXPECT_EQ(bits(a.optimal_time), bits(b.optimal_time)) << a.optimal_time << " vs " << b.optimal_time;
  EXPECT_EQ(bits(a.path_length), bits(b.path_length)) << a.path_length << " vs " << b.path_length;
  EXPECT_EQ(bits(a.mean_speed), bits(b.mean_speed)) << a.mean_speed << " vs " << b.mean_speed;
  EXPECT_EQ(bits(a.sim_time), bits(b.sim_time)) << a.sim_time << " vs " << b.sim_time;
  ASSERT_EQ(a.collision.has_value(), b.collision.has_value());
  if (a.collision) {
    EXPECT_EQ(bits(a.collision->point.x()), bits(b.collision->point.x()));
    EXPECT_EQ(bits(a.collision->point.y()), bits(b.collision->point.y()));
  }
  EXPECT_EQ(a.state_entries, b.state_entries);
  EXPECT_EQ(a.error, b.error);
}

// A row with awkward doubles in every numeric column.
EpisodeResult awkwardRow() {
  EpisodeResult r;
  r.world_id = 123;
  r.trial = 7;
  r.seed = std::numeric_limits<std::uint64_t>::max();  // 18446744073709551615: beyond a double's 2^53
  r.outcome = Outcome::Collision;
  r.actual_time = 0.1 + 0.2;  // 0.30000000000000004
  r.score = 1.0 / 3.0;
  r.optimal_time = 1e-300;
  r.path_length = 12345.678901234567;
  r.mean_speed = std::nextafter(1.0, 2.0);  // 1 + 2^-52
  r.sim_time = 19.150000000000475;
  sim::CollisionInfo hit;
  hit.point = {-2.0000000000000004, 7.0 / 3.0};
  r.collision = hit;
  r.state_entries = {{"Heading", 3}, {"LfLH", 5}};
  return r;
}

EpisodeResult roundTrip(const EpisodeResult& r) {
  const std::string row = episodeCsvRow(r);
  EXPECT_EQ(row.back(), '\n');
  EXPECT_EQ(row.find('\n'), row.size() - 1) << "one line per row: " << row;
  return parseEpisodeRow(row.substr(0, row.size() - 1), "test");
}

TEST(EpisodeCsvRow, RoundTripsAwkwardDoublesBitForBit) {
  const EpisodeResult r = awkwardRow();
  expectSameRow(roundTrip(r), r);
}

TEST(EpisodeCsvRow, RoundTripsEachOutcome) {
  for (Outcome outcome : {Outcome::Success, Outcome::Collision, Outcome::Timeout, Outcome::Error}) {
    EpisodeResult r = awkwardRow();
    r.outcome = outcome;
    SCOPED_TRACE(std::string(toString(outcome)));
    expectSameRow(roundTrip(r), r);
  }
}

TEST(EpisodeCsvRow, RoundTripsExtremeDoubles) {
  // Negative zero, the smallest subnormal, the largest finite value and a negative number.
  EpisodeResult r = awkwardRow();
  r.actual_time = -0.0;
  r.score = std::numeric_limits<double>::denorm_min();  // 4.9406564584124654e-324
  r.optimal_time = std::numeric_limits<double>::max();
  r.path_length = -123.456;
  r.mean_speed = std::numeric_limits<double>::min();  // smallest normal, 2.2250738585072014e-308
  expectSameRow(roundTrip(r), r);
}

TEST(EpisodeCsvRow, RandomDoublesRoundTripBitForBit) {
  std::mt19937_64 rng(12345);
  for (int i = 0; i < 2000; ++i) {
    EpisodeResult r = awkwardRow();
    // Random finite bit patterns cover every exponent, not only "nice" magnitudes.
    auto finite = [&] {
      double v;
      do v = std::bit_cast<double>(rng()); while (!std::isfinite(v));
      return v;
    };
    r.actual_time = finite();
    r.score = finite();
    r.optimal_time = finite();
    r.path_length = finite();
    r.mean_speed = finite();
    r.sim_time = finite();
    r.collision->point = {finite(), finite()};
    const EpisodeResult back = roundTrip(r);
    ASSERT_EQ(bits(back.actual_time), bits(r.actual_time)) << episodeCsvRow(r);
    ASSERT_EQ(bits(back.sim_time), bits(r.sim_time)) << episodeCsvRow(r);
    ASSERT_EQ(bits(back.collision->point.y()), bits(r.collision->point.y())) << episodeCsvRow(r);
  }
}

TEST(EpisodeCsvRow, NoCollisionLeavesBothColumnsEmptyAndReadsBackAsNone) {
  EpisodeResult r = awkwardRow();
  r.outcome = Outcome::Success;
  r.collision.reset();
  const std::string row = episodeCsvRow(r);
  // ...,sim_time_s,collision_x,collision_y,states,error
  EXPECT_THAT(row, HasSubstr("19.150000000000475,,,Heading:3|LfLH:5,\n"));
  EXPECT_FALSE(roundTrip(r).collision.has_value());
}

TEST(EpisodeCsvRow, CollisionAtTheOriginIsStillACollisionPoint) {
  EpisodeResult r = awkwardRow();
  r.collision->point = {0.0, 0.0};
  const EpisodeResult back = roundTrip(r);
  ASSERT_TRUE(back.collision.has_value());
  EXPECT_EQ(back.collision->point.x(), 0.0);
  EXPECT_EQ(back.collision->point.y(), 0.0);
}

TEST(EpisodeCsvRow, StateEntriesKeepTheirOrderAndCounts) {
  EpisodeResult r = awkwardRow();
  r.state_entries = {{"LfLH", 5}, {"Heading", 3}, {"Backward", 0}, {"Recovery", 12345}};
  EXPECT_THAT(episodeCsvRow(r), HasSubstr(",LfLH:5|Heading:3|Backward:0|Recovery:12345,"));
  expectSameRow(roundTrip(r), r);
  r.state_entries.clear();
  expectSameRow(roundTrip(r), r);
}

TEST(EpisodeCsvRow, StateNamesKeepCommasAndQuotesAndLoseOnlyTheListSeparator) {
  EpisodeResult r = awkwardRow();
  // ',' and '"' are quoted (RFC 4180) and kept; '|' would split the list and becomes ';'. A ':'
  // in the name is kept (the count is after the last ':').
  r.state_entries = {{"a,b", 1}, {"c|d", 2}, {"ns:e", 3}, {"say \"hi\"", 4}};
  EXPECT_THAT(episodeCsvRow(r), HasSubstr(R"(,"a,b:1|c;d:2|ns:e:3|say ""hi"":4",)"));
  const EpisodeResult back = roundTrip(r);
  const std::vector<std::pair<std::string, int>> expected = {{"a,b", 1}, {"c;d", 2}, {"ns:e", 3}, {"say \"hi\"", 4}};
  EXPECT_EQ(back.state_entries, expected);
}

TEST(EpisodeCsvRow, ErrorTextWithCommasAndQuotesIsQuotedAndReadsBackExactly) {
  EpisodeResult r = awkwardRow();
  r.outcome = Outcome::Error;
  r.error = R"(external: bad answer '{"linear": 1, "angular": x}')";
  const std::string row = episodeCsvRow(r);
  // The field in quotes, each quote doubled: "external: bad answer '{""linear"": 1, ""angular"": x}'"
  EXPECT_THAT(row, HasSubstr(R"(,"external: bad answer '{""linear"": 1, ""angular"": x}'")" "\n"));
  expectSameRow(roundTrip(r), r);
}

TEST(EpisodeCsvRow, ALineBreakInTheErrorTextBecomesASemicolonSoTheRowStaysOneLine) {
  EpisodeResult r = awkwardRow();
  r.outcome = Outcome::Error;
  r.error = "controller threw: bad index 3, expected < 2\nsecond line\r";
  const EpisodeResult back = roundTrip(r);  // checks the row is one line
  EXPECT_EQ(back.error, "controller threw: bad index 3, expected < 2;second line;");
  EpisodeResult expected = r;
  expected.error = back.error;
  expectSameRow(back, expected);
}

TEST(EpisodeCsvRow, TextWithoutCommaOrQuoteIsWrittenAsItIs) {
  // What every row written before quoting existed looks like: it reads the same, and is
  // written again byte for byte.
  EpisodeResult r = awkwardRow();
  r.outcome = Outcome::Error;
  r.error = "controller threw: no map; world 100";
  const std::string row = episodeCsvRow(r);
  EXPECT_EQ(row.find('"'), std::string::npos) << row;
  EXPECT_THAT(row, HasSubstr(",Heading:3|LfLH:5,controller threw: no map; world 100\n"));
  EXPECT_EQ(episodeCsvRow(roundTrip(r)), row);
}

TEST(EpisodeColumnNames, AreTheHeaderInOrder) {
  const std::vector<std::string> names = episodeColumnNames();
  ASSERT_EQ(names.size(), 14u);
  std::string joined;
  for (const std::string& name : names) joined += (joined.empty() ? "" : ",") + name;
  EXPECT_EQ(joined + "\n", episodesCsvHeader());
  EXPECT_EQ(episodesCsvHeader(), "world,trial,seed,outcome,time_s,score,optimal_time_s,path_length_m,mean_speed_mps,"
                                 "sim_time_s,collision_x,collision_y,states,error\n");
}

TEST(EpisodesCsv, IsTheHeaderThenOneRowPerResultInTheGivenOrder) {
  EpisodeResult a = awkwardRow(), b = awkwardRow();
  a.world_id = 9;
  b.world_id = 2;
  EXPECT_EQ(episodesCsv({a, b}), episodesCsvHeader() + episodeCsvRow(a) + episodeCsvRow(b));
  EXPECT_EQ(episodesCsv({}), episodesCsvHeader());
}

TEST(ParseEpisodeRow, RejectsAWrongColumnCountNamingWhere) {
  std::string row = episodeCsvRow(awkwardRow());
  row.pop_back();
  try {
    parseEpisodeRow(row + ",extra", "episodes.csv:4");
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr("episodes.csv:4"), HasSubstr("columns")));
  }
}

TEST(ParseEpisodeRow, RejectsANegativeSeed) {
  // std::stoull("-1") wraps to 2^64-1 instead of failing; a seed column never holds a sign.
  std::string row = episodeCsvRow(awkwardRow());
  row.pop_back();
  const std::string seed = std::to_string(std::numeric_limits<std::uint64_t>::max());
  row.replace(row.find(seed), seed.size(), "-1");
  EXPECT_THROW(parseEpisodeRow(row, "x"), core::InputError) << row;
}

/// The InputError message of parsing `row`, or "" if it parses.
std::string rowErrorOf(const std::string& row) {
  try {
    parseEpisodeRow(row, "episodes.csv:5");
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ParseEpisodeRow, RejectsBadQuotingNamingWhere) {
  std::string row = episodeCsvRow(awkwardRow());
  row.pop_back();  // ...,Heading:3|LfLH:5,   (the error column is empty)
  EXPECT_THAT(rowErrorOf(row + "\"unclosed"), AllOf(HasSubstr("episodes.csv:5"), HasSubstr("not closed")));
  EXPECT_THAT(rowErrorOf(row + "\"closed\"x"), AllOf(HasSubstr("episodes.csv:5"), HasSubstr("after the closing quote of field 14")));
  EXPECT_THAT(rowErrorOf(row + "a\"b"), AllOf(HasSubstr("episodes.csv:5"), HasSubstr("quote in unquoted field 14")));
  EXPECT_EQ(rowErrorOf(row + "\"a \"\"b\"\", c\""), "");
}

TEST(ParseEpisodeRow, RejectsACollisionPointWithOneCoordinate) {
  EpisodeResult r = awkwardRow();
  r.collision->point = {1.5, 2.5};
  std::string row = episodeCsvRow(r);
  row.pop_back();
  std::string only_x = row, only_y = row;
  only_x.replace(only_x.find(",1.5,2.5,"), 9, ",1.5,,");
  only_y.replace(only_y.find(",1.5,2.5,"), 9, ",,2.5,");
  EXPECT_THAT(rowErrorOf(only_x), AllOf(HasSubstr("collision_y"), HasSubstr("'' is not a finite number")));
  EXPECT_THAT(rowErrorOf(only_y), AllOf(HasSubstr("collision_y"), HasSubstr("without a collision_x")));
}

// ---------------------------------------------------------------------------------------------
// readEpisodesCsv

class EpisodesFile : public testing::Test {
 protected:
  void SetUp() override {
    std::random_device device;
    dir_ = fs::temp_directory_path() / ("barn_results_io_test_" + std::to_string(device()) + "_" + std::to_string(device()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path write(const std::string& content) {
    const fs::path path = dir_ / "episodes.csv";
    std::ofstream(path, std::ios::binary | std::ios::trunc) << content;
    return path;
  }
  /// The InputError message of reading `content`, or "" if it reads.
  std::string errorOf(const std::string& content) {
    try {
      readEpisodesCsv(write(content));
    } catch (const core::InputError& e) {
      return e.what();
    }
    return "";
  }
  static std::vector<EpisodeResult> threeRows() {
    std::vector<EpisodeResult> rows(3, awkwardRow());
    for (int i = 0; i < 3; ++i) rows[static_cast<std::size_t>(i)].trial = i;
    return rows;
  }
  fs::path dir_;
};

TEST_F(EpisodesFile, ReadsBackWhatEpisodesCsvWrote) {
  const auto rows = threeRows();
  const auto back = readEpisodesCsv(write(episodesCsv(rows)));
  ASSERT_EQ(back.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) expectSameRow(back[i], rows[i]);
}

TEST_F(EpisodesFile, HeaderOnlyIsAnEmptyList) {
  EXPECT_TRUE(readEpisodesCsv(write(episodesCsvHeader())).empty());
}

TEST_F(EpisodesFile, IgnoresATruncatedLastLine) {
  const auto rows = threeRows();
  const std::string full = episodesCsv(rows);
  // The last row cut after 20 characters, no newline: an interrupted append.
  const std::string last = episodeCsvRow(rows.back());
  const std::string cut = full.substr(0, full.size() - last.size()) + last.substr(0, 20);
  const auto back = readEpisodesCsv(write(cut));
  ASSERT_EQ(back.size(), 2u);
  expectSameRow(back[1], rows[1]);
}

TEST_F(EpisodesFile, MissingFileIsAnErrorUnlessAllowed) {
  const fs::path missing = dir_ / "nothing.csv";
  EXPECT_TRUE(readEpisodesCsv(missing, /*allow_missing=*/true).empty());
  try {
    readEpisodesCsv(missing);
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("nothing.csv"));
  }
}

TEST_F(EpisodesFile, RejectsAWrongHeader) {
  std::string header = episodesCsvHeader();
  header.replace(header.find("score"), 5, "SCORE");
  const std::string message = errorOf(header + episodeCsvRow(awkwardRow()));
  EXPECT_THAT(message, AllOf(HasSubstr("episodes.csv"), HasSubstr("header")));
  // A file that is something else altogether.
  EXPECT_THAT(errorOf("id,file,source\n0,world_000.yaml,generated\n"), HasSubstr("header"));
}

TEST_F(EpisodesFile, RejectsABadOutcomeNamingFileAndLine) {
  const auto rows = threeRows();
  std::string text = episodesCsv(rows);
  // Row 2 is line 3 of the file.
  const std::string row = episodeCsvRow(rows[1]);
  std::string bad = row;
  bad.replace(bad.find(",collision,"), 11, ",crashed,");
  text.replace(text.find(row), row.size(), bad);
  const std::string message = errorOf(text);
  EXPECT_THAT(message, AllOf(HasSubstr("episodes.csv:3"), HasSubstr("outcome"), HasSubstr("crashed")));
}

TEST_F(EpisodesFile, RejectsANonNumberNamingFileLineAndColumn) {
  const auto rows = threeRows();
  std::string text = episodesCsv(rows);
  // Row 3 (line 4): the score 1/3 replaced by text.
  const std::string row = episodeCsvRow(rows[2]);
  std::string bad = row;
  const std::string third = "0.3333333333333333";
  ASSERT_NE(bad.find(third), std::string::npos);
  bad.replace(bad.find(third), third.size(), "0.33x");
  text.replace(text.rfind(row), row.size(), bad);
  EXPECT_THAT(errorOf(text), AllOf(HasSubstr("episodes.csv:4"), HasSubstr("score"), HasSubstr("0.33x")));
}

TEST_F(EpisodesFile, RejectsANonIntegerWorldNamingFileAndLine) {
  const auto rows = threeRows();
  std::string text = episodesCsvHeader() + episodeCsvRow(rows[0]) + "12a" + episodeCsvRow(rows[1]).substr(3);
  EXPECT_THAT(errorOf(text), AllOf(HasSubstr("episodes.csv:3"), HasSubstr("world"), HasSubstr("12a")));
}

TEST_F(EpisodesFile, RejectsABadRowInTheMiddleEvenIfTheLastLineIsTruncated) {
  const auto rows = threeRows();
  std::string text = episodesCsvHeader() + "garbage\n" + episodeCsvRow(rows[0]).substr(0, 15);
  EXPECT_THAT(errorOf(text), HasSubstr("episodes.csv:2"));
}

TEST(ParseEpisodeRow, RefusesWhatNoEpisodeWrites) {
  // Each field out of the range an episode can write, in a row that otherwise reads: a world
  // id past INT_MAX (would wrap to 1), a signed or hex seed, a non-finite score or time, a
  // state label longer than the bound, one label too many.
  EpisodeResult base = awkwardRow();
  base.state_entries.clear();
  const auto withField = [&](std::size_t index, const std::string& value) {
    std::string row = episodeCsvRow(base);
    row.pop_back();
    std::vector<std::string> fields;
    std::size_t start = 0;
    for (std::size_t comma; (comma = row.find(',', start)) != std::string::npos; start = comma + 1)
      fields.push_back(row.substr(start, comma - start));
    fields.push_back(row.substr(start));
    fields[index] = value;
    std::string out;
    for (std::size_t i = 0; i < fields.size(); ++i) out += (i ? "," : "") + fields[i];
    return out;
  };
  EXPECT_NO_THROW(parseEpisodeRow(withField(0, "1000000000"), "x"));
  for (const auto& [index, value] : std::vector<std::pair<std::size_t, std::string>>{
           {0, "4294967297"}, {0, "1000000001"}, {1, "-1"}, {2, "0x10"}, {2, "+5"}, {2, "18446744073709551616"},
           {5, "nan"}, {4, "inf"}, {6, "-inf"}, {7, "inf"}}) {
    EXPECT_THROW(parseEpisodeRow(withField(index, value), "x"), core::InputError) << index << " = " << value;
  }
  // An imported record does not know the path, speed or simulated time: nan there reads.
  EXPECT_NO_THROW(parseEpisodeRow(withField(7, "nan"), "x"));
  EXPECT_NO_THROW(parseEpisodeRow(withField(9, "nan"), "x"));
  EXPECT_NO_THROW(parseEpisodeRow(withField(12, std::string(kMaxStateLabelBytes, 'a') + ":1"), "x"));
  EXPECT_THROW(parseEpisodeRow(withField(12, std::string(kMaxStateLabelBytes + 1, 'a') + ":1"), "x"), core::InputError);
  std::string labels;
  for (std::size_t k = 0; k <= kMaxStateLabels; ++k) labels += (k ? "|s" : "s") + std::to_string(k) + ":1";
  EXPECT_THAT([&] { parseEpisodeRow(withField(12, labels), "x"); },
              ::testing::ThrowsMessage<core::InputError>(HasSubstr("more than 64 labels")));
}

TEST(ParseEpisodesCsv, ACompleteFileMustEndItsLastLineAJournalMayNot) {
  const std::string text = episodesCsv({awkwardRow()}) + "7,0,1,succ";
  EXPECT_EQ(parseEpisodesCsv(text, "j", true).size(), 1u);
  EXPECT_THAT([&] { parseEpisodesCsv(text, "episodes.csv", false); },
              ::testing::ThrowsMessage<core::InputError>(HasSubstr("episodes.csv:3: the last line is cut short")));
  EXPECT_THROW(parseEpisodesCsv("", "episodes.csv", false), core::InputError);
  EXPECT_TRUE(parseEpisodesCsv("", "episodes.partial.csv", true).empty());
}

}  // namespace
}  // namespace barn::bench
