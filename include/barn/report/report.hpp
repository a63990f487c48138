#pragma once
/// `barn report` and `barnbench.report()`: a finished run record or sweep as one self-contained
/// HTML page (html_report.hpp): the summary, the per-world table, the difficulty breakdown and
/// the figures, drawn into a scratch folder and embedded.

#include <filesystem>

#include "barn/report/html_report.hpp"

namespace barn::report {

struct ReportOptions {
  int max_failures = 12;  // [-] failed episodes drawn at most (recorded, else re-simulated); our choice
};

/// The page of the complete run record in `record`, its figures drawn into `scratch`.
HtmlReport runReport(const std::filesystem::path& record, const std::filesystem::path& scratch, int max_failures);

/// The page of the finished sweep in `sweep`, its figures drawn into `scratch`; axis units from
/// the controller config's schema.
HtmlReport sweepReport(const std::filesystem::path& sweep, const std::filesystem::path& scratch);

/// Writes the page of `input` (a run record, manifest.yaml, or a sweep, sweep.yaml) to `output`
/// (a .html file, written atomically). The figures go through a scratch folder of this call
/// alone, removed afterwards. InputError for an input that is neither, an incomplete record or
/// an output that is not a .html file.
void writeReport(const std::filesystem::path& input, const std::filesystem::path& output,
                 const ReportOptions& options = {});

}  // namespace barn::report
