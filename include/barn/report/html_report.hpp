#pragma once
/// A self-contained static HTML page: titled sections of text, tables (sortable by a click on
/// a column header) and figures embedded as data URIs. No server, no network, no external file:
/// the page can be mailed or archived with a paper's results.

#include <filesystem>
#include <string>
#include <vector>

namespace barn::report {

struct HtmlTable {
  std::string id;                              // element id (tests and scripts find it by this)
  std::vector<std::string> header;             // (n_columns)
  std::vector<std::vector<std::string>> rows;  // (n_rows x n_columns) cell text, escaped on output
  std::vector<bool> numeric;                   // (n_columns) sort as numbers ("-" last)
  bool sortable = true;
};

struct HtmlFigure {
  std::string caption;
  std::filesystem::path file;  // .png or .svg, embedded
};

struct HtmlSection {
  std::string title;
  std::vector<std::string> paragraphs;  // plain text, escaped on output
  std::vector<HtmlTable> tables;
  std::vector<HtmlFigure> figures;
};

struct HtmlReport {
  std::string title;
  std::string subtitle;
  std::vector<HtmlSection> sections;
};

/// The page's text. Its script sorts tables and, once it has run without error, marks
/// <body data-ready="1"> (a browser test can tell a page whose script failed).
/// InputError if a figure file cannot be read or is neither .png nor .svg.
std::string renderHtml(const HtmlReport& report);

}  // namespace barn::report
