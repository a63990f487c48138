#include "barn/report/html_report.hpp"

#include <array>
#include <cstdint>

#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"

namespace barn::report {

namespace {

std::string escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char ch : text) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += ch;
    }
  }
  return out;
}

std::string base64(const std::string& bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t chunk = static_cast<std::uint8_t>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) chunk |= static_cast<std::uint8_t>(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) chunk |= static_cast<std::uint8_t>(bytes[i + 2]);
    out += kAlphabet[(chunk >> 18) & 63];
    out += kAlphabet[(chunk >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(chunk >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[chunk & 63] : '=';
  }
  return out;
}

std::string figureHtml(const HtmlFigure& figure) {
  const std::string extension = figure.file.extension().string();
  std::string mime;
  if (extension == ".png") mime = "image/png";
  else if (extension == ".svg") mime = "image/svg+xml";
  else throw core::InputError(figure.file.string() + ": a report embeds .png or .svg figures only");
  const std::string bytes = core::readTextFile(figure.file);
  return "<figure><img alt=\"" + escape(figure.caption) + "\" src=\"data:" + mime + ";base64," + base64(bytes) +
         "\"><figcaption>" + escape(figure.caption) + "</figcaption></figure>\n";
}

std::string tableHtml(const HtmlTable& table) {
  std::string html = "<table id=\"" + escape(table.id) + "\"" + (table.sortable ? " class=\"sortable\"" : "") + ">\n<thead><tr>";
  for (std::size_t c = 0; c < table.header.size(); ++c) {
    const bool numeric = c < table.numeric.size() && table.numeric[c];
    html += "<th" + std::string(numeric ? " data-numeric=\"1\"" : "") + ">" + escape(table.header[c]) + "</th>";
  }
  html += "</tr></thead>\n<tbody>\n";
  for (const auto& row : table.rows) {
    html += "<tr>";
    for (const auto& cell : row) html += "<td>" + escape(cell) + "</td>";
    html += "</tr>\n";
  }
  return html + "</tbody>\n</table>\n";
}

// Click a header to sort by it (again to reverse). Numbers sort numerically, "-" last.
constexpr const char* kScript = R"(
for (const table of document.querySelectorAll("table.sortable")) {
  const headers = table.tHead.rows[0].cells;
  for (let column = 0; column < headers.length; ++column) {
    headers[column].addEventListener("click", () => {
      const numeric = headers[column].dataset.numeric === "1";
      const descending = headers[column].dataset.order === "ascending";
      for (const h of headers) delete h.dataset.order;
      headers[column].dataset.order = descending ? "descending" : "ascending";
      const rows = Array.from(table.tBodies[0].rows);
      const key = row => {
        const text = row.cells[column].textContent.trim();
        if (!numeric) return text;
        const value = parseFloat(text);
        return Number.isNaN(value) ? Infinity : value;
      };
      rows.sort((a, b) => {
        const ka = key(a), kb = key(b);
        const order = ka < kb ? -1 : ka > kb ? 1 : 0;
        return descending ? -order : order;
      });
      for (const row of rows) table.tBodies[0].appendChild(row);
    });
  }
}
document.body.dataset.ready = "1";
)";

constexpr const char* kStyle = R"(
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 1100px; color: #222; padding: 0 1em; }
h1 { margin-bottom: 0.2em; } .subtitle { color: #555; margin-top: 0; }
table { border-collapse: collapse; margin: 1em 0; font-variant-numeric: tabular-nums; }
th, td { border-bottom: 1px solid #ddd; padding: 0.25em 0.7em; text-align: right; }
th { background: #f3f3f3; } table.sortable th { cursor: pointer; }
th[data-order="ascending"]::after { content: " \25B2"; } th[data-order="descending"]::after { content: " \25BC"; }
td:first-child, th:first-child { text-align: left; }
figure { margin: 1em 0; } img { max-width: 100%; border: 1px solid #eee; } figcaption { color: #555; }
)";

}  // namespace

std::string renderHtml(const HtmlReport& report) {
  std::string html = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" +
                     escape(report.title) + "</title>\n<style>" + kStyle + "</style>\n</head>\n<body>\n<h1>" +
                     escape(report.title) + "</h1>\n<p class=\"subtitle\">" + escape(report.subtitle) + "</p>\n";
  for (const auto& section : report.sections) {
    html += "<section>\n<h2>" + escape(section.title) + "</h2>\n";
    for (const auto& paragraph : section.paragraphs) html += "<p>" + escape(paragraph) + "</p>\n";
    for (const auto& table : section.tables) html += tableHtml(table);
    for (const auto& figure : section.figures) html += figureHtml(figure);
    html += "</section>\n";
  }
  return html + "<script>" + kScript + "</script>\n</body>\n</html>\n";
}

}  // namespace barn::report
