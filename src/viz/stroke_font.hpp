#pragma once
// A small built-in monoline stroke font for the PNG renderers (world pictures, line plots):
// why it exists, and what it covers, is in stroke_font.cpp.

#include <string>

#include <cairo.h>

namespace barn::viz::detail {

/// Advance of `text` at font size `size`. [px]
double textWidth(const std::string& text, double size);

/// Strokes `text` with its baseline starting at (x, baseline) in device pixels, in the current
/// source colour.
void drawText(cairo_t* cr, const std::string& text, double x, double baseline, double size);

}  // namespace barn::viz::detail
