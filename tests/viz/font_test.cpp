// Figure text: DejaVu Sans loaded from its one file (src/viz/font.cpp).

#include "viz/font.hpp"

#include <cairo.h>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "barn/core/errors.hpp"

namespace barn::viz::detail {
namespace {

using testing::AllOf;
using testing::HasSubstr;

TEST(Font, AMissingFontFileIsAnInputErrorNamingTheFileAndItsPackage) {
  try {
    FontFace face("/nonexistent/DejaVuSans.ttf");
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr("/nonexistent/DejaVuSans.ttf"), HasSubstr("fonts-dejavu-core")));
  }
}

TEST(Font, AWidthIsTheFontsUnhintedAdvanceScaledToTheSize) {
  // DejaVu Sans: '0' advances 1303 and '.' 651 units of 2048 to the em;
  // "0.0" at 20 px = (1303 + 651 + 1303) * 20 / 2048 = 31.806640625 px.
  EXPECT_DOUBLE_EQ(textWidth("0.0", 20.0), (1303.0 + 651.0 + 1303.0) * 20.0 / 2048.0);
  // Unhinted: twice the size is exactly twice the width.
  EXPECT_DOUBLE_EQ(textWidth("world 92", 24.0), 2.0 * textWidth("world 92", 12.0));
  EXPECT_EQ(textWidth("", 14.0), 0.0);
}

TEST(Font, MalformedUtf8IsMeasuredAndDrawnAsQuestionMarksAndLeavesTheContextUsable) {
  // 0xff never starts a sequence; 0xc3 starts one the string cut short; "\xc3\xa9" is é.
  EXPECT_DOUBLE_EQ(textWidth("a\xff" "b\xc3", 14.0), textWidth("a?b?", 14.0));
  EXPECT_NE(textWidth("\xc3\xa9", 14.0), textWidth("??", 14.0));
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, 40, 20);
  cairo_t* cr = cairo_create(surface);
  drawText(cr, "a\xff", 2.0, 15.0, 12.0);
  EXPECT_EQ(cairo_status(cr), CAIRO_STATUS_SUCCESS);  // Cairo would stop drawing on this context
  EXPECT_FALSE(cairo_has_current_point(cr));           // no path left behind for the next stroke
  cairo_destroy(cr);
  cairo_surface_destroy(surface);
}

}  // namespace
}  // namespace barn::viz::detail
