#include "stroke_font.hpp"

#include <charconv>
#include <cstring>
#include <numbers>

namespace barn::viz::detail {
namespace {

// ---------------------------------------------------------------------------
// Stroke font
//
// Text is drawn with a small built-in monoline font instead of Cairo's toy text API. The toy
// API goes through fontconfig, whose caches hold offset-encoded pointers that LeakSanitizer
// reports as leaks in every ASan test that renders; it also makes the PNG depend on which
// fonts the machine has installed. A stroke font has neither problem: the picture is the same
// bytes everywhere. It covers printable ASCII except "$ & @ \\ ^ ` { } ~"; any other character
// leaves a blank 4 units wide.
//
// Glyph space: baseline y = 0, x-height 4, cap height 6, descender -2, y up; one font "em" is
// kEmUnits units. A glyph is strokes separated by '|'; a stroke is a list of
//   L x y                    line to (x, y); the first command of a stroke only moves there
//   A cx cy rx ry a0 a1      elliptic arc from a0 to a1 [deg], counter-clockwise if a1 > a0

struct Glyph {
  char c;               // character drawn
  double width;         // [glyph units] ink width; the advance adds kGlyphGap
  const char* strokes;  // see above
};

constexpr double kEmUnits = 8.0;     // [glyph units] per font size
constexpr double kGlyphGap = 1.3;    // [glyph units] between glyphs
constexpr double kStrokeUnits = 0.7; // [glyph units] pen width

constexpr Glyph kGlyphs[] = {
    {' ', 1.6, ""},
    {'.', 0.6, "L0.3 0 L0.3 0.05"},
    {'-', 3.0, "L0 2.5 L3 2.5"},
    {'+', 4.0, "L0 2.5 L4 2.5|L2 0.5 L2 4.5"},
    {',', 0.6, "L0.45 0.1 L-0.1 -1.2"},
    {':', 0.6, "L0.3 0 L0.3 0.05|L0.3 3.5 L0.3 3.55"},
    {';', 0.6, "L0.3 3.5 L0.3 3.55|L0.45 0.1 L-0.1 -1.2"},
    {'!', 0.6, "L0.3 6 L0.3 1.8|L0.3 0 L0.3 0.05"},
    {'?', 3.6, "A1.8 4.5 1.8 1.5 160 -60 L1.8 2.3 L1.8 1.6|L1.8 0 L1.8 0.05"},
    {'\'', 0.6, "L0.3 6 L0.3 4.5"},
    {'"', 1.8, "L0.3 6 L0.3 4.5|L1.5 6 L1.5 4.5"},
    {'_', 4.0, "L0 -1 L4 -1"},
    {'/', 3.0, "L0 -0.5 L3 6.5"},
    {'|', 0.6, "L0.3 -1.5 L0.3 7"},
    {'(', 1.2, "A2.6 2.75 2.5 4.5 125 235"},
    {')', 1.2, "A-1.4 2.75 2.5 4.5 55 -55"},
    {'[', 1.6, "L1.6 7 L0 7 L0 -1.5 L1.6 -1.5"},
    {']', 1.6, "L0 7 L1.6 7 L1.6 -1.5 L0 -1.5"},
    {'*', 3.0, "L1.5 2.5 L1.5 5.5|L0.2 4.75 L2.8 3.25|L0.2 3.25 L2.8 4.75"},
    {'=', 3.5, "L0 1.7 L3.5 1.7|L0 3.3 L3.5 3.3"},
    {'<', 3.5, "L3.5 4.5 L0 2.5 L3.5 0.5"},
    {'>', 3.5, "L0 4.5 L3.5 2.5 L0 0.5"},
    {'%', 5.0, "A1 5 1 1 0 360|A4 1 1 1 0 360|L0.3 0 L4.7 6"},
    {'#', 5.0, "L1.3 0 L2 6|L3 0 L3.7 6|L0.2 2 L4.6 2|L0.4 4 L4.8 4"},
    {'0', 4.0, "A2 3 2 3 0 360"},
    {'1', 4.0, "L0.8 4.8 L2.2 6 L2.2 0"},
    {'2', 4.0, "A2 4.1 2 1.9 165 -35 L0 0 L4 0"},
    {'3', 4.0, "A2 4.5 1.8 1.5 150 -90 A2 1.5 2 1.5 90 -150"},
    {'4', 4.0, "L3 0 L3 6 L0 2 L4 2"},
    {'5', 4.0, "L3.8 6 L0.5 6 L0.2 3.4 A2 1.9 2 1.9 125 -150"},
    {'6', 4.0, "A2 1.9 2 1.9 0 360|L0 1.9 L0 4 A2 4 2 2 180 40"},
    {'7', 4.0, "L0 6 L4 6 L1.5 0"},
    {'8', 4.0, "A2 4.5 1.7 1.5 0 360|A2 1.5 2 1.5 0 360"},
    {'9', 4.0, "A2 4.1 2 1.9 0 360|L4 4.1 L4 2 A2 2 2 2 0 -140"},
    {'A', 5.0, "L0 0 L2.5 6 L5 0|L0.9 2 L4.1 2"},
    {'B', 4.2, "L0 0 L0 6 L2.6 6 A2.6 4.55 1.45 1.45 90 -90 L0 3.1|L2.7 3.1 A2.7 1.55 1.5 1.55 90 -90 L0 0"},
    {'C', 5.0, "A2.6 3 2.6 3 45 315"},
    {'D', 4.6, "L0 0 L0 6 L1.6 6 A1.6 3 3 3 90 -90 L0 0"},
    {'E', 4.0, "L4 6 L0 6 L0 0 L4 0|L0 3 L3.2 3"},
    {'F', 4.0, "L4 6 L0 6 L0 0|L0 3 L3.2 3"},
    {'G', 5.0, "A2.5 3 2.5 3 45 360 L3 3"},
    {'H', 4.0, "L0 0 L0 6|L4 0 L4 6|L0 3 L4 3"},
    {'I', 1.0, "L0.5 0 L0.5 6"},
    {'J', 3.0, "L3 6 L3 1.5 A1.5 1.5 1.5 1.5 0 -180"},
    {'K', 4.0, "L0 6 L0 0|L4 6 L0 2|L1.4 3.2 L4 0"},
    {'L', 3.5, "L0 6 L0 0 L3.5 0"},
    {'M', 5.0, "L0 0 L0 6 L2.5 2 L5 6 L5 0"},
    {'N', 4.0, "L0 0 L0 6 L4 0 L4 6"},
    {'O', 5.0, "A2.5 3 2.5 3 0 360"},
    {'P', 4.1, "L0 0 L0 6 L2.5 6 A2.5 4.4 1.6 1.6 90 -90 L0 2.8"},
    {'Q', 5.0, "A2.5 3 2.5 3 0 360|L3 1.2 L5 -0.5"},
    {'R', 4.2, "L0 0 L0 6 L2.5 6 A2.5 4.4 1.6 1.6 90 -90 L0 2.8|L2.2 2.8 L4.2 0"},
    {'S', 4.0, "A2 4.5 2 1.5 10 270 A2 1.5 2 1.5 90 -170"},
    {'T', 5.0, "L0 6 L5 6|L2.5 6 L2.5 0"},
    {'U', 4.0, "L0 6 L0 2 A2 2 2 2 180 360 L4 6"},
    {'V', 5.0, "L0 6 L2.5 0 L5 6"},
    {'W', 6.0, "L0 6 L1.5 0 L3 4.5 L4.5 0 L6 6"},
    {'X', 4.0, "L0 6 L4 0|L0 0 L4 6"},
    {'Y', 5.0, "L0 6 L2.5 3 L5 6|L2.5 3 L2.5 0"},
    {'Z', 4.0, "L0 6 L4 6 L0 0 L4 0"},
    {'a', 4.0, "A2 2 2 2 0 360|L4 4 L4 0"},
    {'b', 4.0, "L0 6 L0 0|A2 2 2 2 0 360"},
    {'c', 4.0, "A2 2 2 2 45 315"},
    {'d', 4.0, "A2 2 2 2 0 360|L4 6 L4 0"},
    {'e', 4.0, "L0 2 L4 2 A2 2 2 2 0 315"},
    {'f', 3.0, "L1 0 L1 5 A2.5 5 1.5 1 180 20|L0 4 L3 4"},
    {'g', 4.0, "A2 2 2 2 0 360|L4 4 L4 -0.5 A2 -0.5 2 1.5 0 -160"},
    {'h', 4.0, "L0 6 L0 0|L0 2 A2 2 2 2 180 0 L4 0"},
    {'i', 1.0, "L0.5 0 L0.5 4|L0.5 5.5 L0.5 5.55"},
    {'j', 1.5, "L1.5 4 L1.5 -0.5 A0 -0.5 1.5 1.5 0 -150|L1.5 5.5 L1.5 5.55"},
    {'k', 3.5, "L0 6 L0 0|L3.5 4 L0 1.5|L1.2 2.4 L3.5 0"},
    {'l', 1.0, "L0.5 6 L0.5 0"},
    {'m', 6.0, "L0 0 L0 4|L0 2.5 A1.5 2.5 1.5 1.5 180 0 L3 0|L3 2.5 A4.5 2.5 1.5 1.5 180 0 L6 0"},
    {'n', 4.0, "L0 0 L0 4|L0 2 A2 2 2 2 180 0 L4 0"},
    {'o', 4.0, "A2 2 2 2 0 360"},
    {'p', 4.0, "L0 4 L0 -2|A2 2 2 2 0 360"},
    {'q', 4.0, "A2 2 2 2 0 360|L4 4 L4 -2"},
    {'r', 3.0, "L0 0 L0 4|L0 2 A2 2 2 2 180 45"},
    {'s', 3.4, "A1.7 3 1.7 1 10 270 A1.7 1 1.7 1 90 -170"},
    {'t', 3.0, "L1 5.5 L1 1 A2 1 1 1 180 300|L0 4 L3 4"},
    {'u', 4.0, "L0 4 L0 2 A2 2 2 2 180 360|L4 4 L4 0"},
    {'v', 4.0, "L0 4 L2 0 L4 4"},
    {'w', 5.5, "L0 4 L1.3 0 L2.75 3 L4.2 0 L5.5 4"},
    {'x', 4.0, "L0 4 L4 0|L0 0 L4 4"},
    {'y', 4.0, "L0 4 L2 0|L4 4 L1 -2"},
    {'z', 4.0, "L0 4 L4 4 L0 0 L4 0"},
};

const Glyph* findGlyph(char c) {
  for (const Glyph& glyph : kGlyphs) {
    if (glyph.c == c) return &glyph;
  }
  return nullptr;
}

}  // namespace

/// Advance of `text` at font size `size`. [px]
double textWidth(const std::string& text, double size) {
  double units = 0.0;
  for (char c : text) {
    const Glyph* glyph = findGlyph(c);
    units += (glyph ? glyph->width : 4.0) + kGlyphGap;
  }
  if (!text.empty()) units -= kGlyphGap;
  return units * size / kEmUnits;
}

/// Adds one glyph's strokes to the current path; the current matrix maps glyph units.
static void addGlyphPath(cairo_t* cr, const Glyph& glyph) {
  const char* p = glyph.strokes;
  bool first = true;
  while (*p != '\0') {
    const char op = *p++;
    if (op == '|') {
      first = true;
      continue;
    }
    // from_chars, not strtod: a process locale with a decimal comma must not break glyphs.
    double v[6] = {};
    const int count = op == 'A' ? 6 : 2;
    for (int i = 0; i < count; ++i) {
      while (*p == ' ') ++p;
      p = std::from_chars(p, p + std::strlen(p), v[i]).ptr;
    }
    if (op == 'L') {
      if (first) cairo_move_to(cr, v[0], v[1]);
      else cairo_line_to(cr, v[0], v[1]);
    } else {
      // Elliptic arc: scale a unit circle; the path keeps device coordinates, so restoring
      // the matrix afterwards does not undo it.
      if (first) cairo_new_sub_path(cr);
      const double a0 = v[4] * std::numbers::pi / 180.0;
      const double a1 = v[5] * std::numbers::pi / 180.0;
      cairo_save(cr);
      cairo_translate(cr, v[0], v[1]);
      cairo_scale(cr, v[2], v[3]);
      if (a1 > a0) cairo_arc(cr, 0.0, 0.0, 1.0, a0, a1);
      else cairo_arc_negative(cr, 0.0, 0.0, 1.0, a0, a1);
      cairo_restore(cr);
    }
    first = false;
    while (*p == ' ') ++p;
  }
}

/// Strokes `text` with its baseline starting at (x, baseline) in device pixels.
void drawText(cairo_t* cr, const std::string& text, double x, double baseline, double size) {
  const double unit = size / kEmUnits;  // [px per glyph unit]
  cairo_save(cr);
  cairo_translate(cr, x, baseline);
  cairo_scale(cr, unit, -unit);  // glyphs are drawn y up
  for (char c : text) {
    const Glyph* glyph = findGlyph(c);
    if (glyph) addGlyphPath(cr, *glyph);
    cairo_translate(cr, (glyph ? glyph->width : 4.0) + kGlyphGap, 0.0);
  }
  cairo_restore(cr);
  cairo_set_line_width(cr, kStrokeUnits * unit);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_stroke(cr);
}

}  // namespace barn::viz::detail
