#include "barn/bench/world_selection.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <numeric>
#include <string>
#include <vector>

#include "barn/core/errors.hpp"

namespace barn::bench {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

// The canonical set: ids 0..299.
std::vector<int> canonicalIds() {
  std::vector<int> ids(300);
  std::iota(ids.begin(), ids.end(), 0);
  return ids;
}

/// The message of the InputError thrown by selectWorldIds, or "" if none was thrown.
std::string selectionError(const std::string& spec, const std::vector<int>& available = canonicalIds()) {
  try {
    selectWorldIds(spec, available);
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SelectWorldIds, AllSelectsEveryAvailableId) {
  EXPECT_EQ(selectWorldIds("all", canonicalIds()), canonicalIds());
  EXPECT_THAT(selectWorldIds("all", {4, 9, 17}), ElementsAre(4, 9, 17));
}

TEST(SelectWorldIds, Test50IsEverySixthWorld) {
  const std::vector<int> ids = selectWorldIds("test50", canonicalIds());
  ASSERT_EQ(ids.size(), 50u);
  // 0, 6, ..., 6 * 49 = 294.
  for (std::size_t i = 0; i < ids.size(); ++i) EXPECT_EQ(ids[i], static_cast<int>(6 * i));
  EXPECT_EQ(ids.back(), 294);
}

TEST(SelectWorldIds, RangeWithStepEqualsTest50) {
  EXPECT_EQ(selectWorldIds("0:300:6", canonicalIds()), selectWorldIds("test50", canonicalIds()));
}

TEST(SelectWorldIds, RangeExcludesItsEnd) {
  EXPECT_THAT(selectWorldIds("10:13", canonicalIds()), ElementsAre(10, 11, 12));
  // 5, 5 + 4 = 9; 13 is past the end 12.
  EXPECT_THAT(selectWorldIds("5:12:4", canonicalIds()), ElementsAre(5, 9));
}

TEST(SelectWorldIds, ListSelectsTheNamedIds) {
  EXPECT_THAT(selectWorldIds("3,7,9", canonicalIds()), ElementsAre(3, 7, 9));
  EXPECT_THAT(selectWorldIds("42", canonicalIds()), ElementsAre(42));
}

TEST(SelectWorldIds, ListIsSortedAndDeduplicated) {
  EXPECT_THAT(selectWorldIds("9,3,9,7", canonicalIds()), ElementsAre(3, 7, 9));
}

TEST(SelectWorldIds, UnknownIdIsAnErrorNamingIt) {
  const std::string error = selectionError("400");
  EXPECT_THAT(error, HasSubstr("unknown world id"));
  EXPECT_THAT(error, HasSubstr("400"));
  // A range reaching past the set names the missing ids.
  EXPECT_THAT(selectionError("298:302"), HasSubstr("300, 301"));
  // test50 on a set without world 294 fails too.
  EXPECT_THAT(selectionError("test50", {0, 6, 12}), HasSubstr("unknown world id"));
}

TEST(SelectWorldIds, MalformedSpecsAreErrors) {
  EXPECT_THAT(selectionError("a:b"), HasSubstr("'a' is not a world id"));
  EXPECT_THAT(selectionError("1:2:3:4"), HasSubstr("expected A:B or A:B:STEP"));
  EXPECT_THAT(selectionError("-1"), HasSubstr("'-1' is not a world id"));
  EXPECT_THAT(selectionError("3,,9"), HasSubstr("'' is not a world id"));
  EXPECT_THAT(selectionError("7x"), HasSubstr("'7x' is not a world id"));
  EXPECT_THAT(selectionError("0:10:0"), HasSubstr("step must be >= 1"));
  EXPECT_THAT(selectionError(""), HasSubstr("is not a world id"));
}

TEST(SelectWorldIds, EmptySelectionIsAnError) {
  EXPECT_THAT(selectionError("5:5"), HasSubstr("selects no world"));
  EXPECT_THAT(selectionError("9:3"), HasSubstr("selects no world"));
  EXPECT_THAT(selectionError("all", {}), HasSubstr("selects no world"));
}

TEST(SelectWorldIds, ErrorsQuoteTheSpec) {
  EXPECT_THAT(selectionError("1:2:3:4"), HasSubstr("--worlds '1:2:3:4'"));
  EXPECT_THAT(selectionError("400"), HasSubstr("--worlds '400'"));
}

}  // namespace
}  // namespace barn::bench
