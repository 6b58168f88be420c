// report.html of `tpcal run`: one self-contained file (inline CSS and SVG, no external resource,
// opens offline) with the run summary, the identified machine errors (value, u by every
// uncertainty method side by side, 95 % interval, identifiable), the identifiability table
// (rank, condition number, singular values, estimable combinations, null directions), the gap
// diagnosis (verdict, where, candidate effects with shrink, unobservable families), the GD&T tables and the figures (svg_figures.h), and the effective configuration.
//
// The page carries a small self-check script (no other script): on load it sets document.title
// to "tpcal report: OK (N figures)" if every embedded <svg> has drawn content and their number
// is the one the page announces (body data-figures), "tpcal report: EMPTY FIGURE ..." otherwise,
// and "tpcal report: SCRIPT ERROR ..." on any script error. Headless browsers read the title
// (tests/cli/run_report_chromium_test.sh).
#pragma once

#include <string>

#include "pipeline/report/run_report.h"

namespace tpcal::pipeline {

// The title the self-check script sets when the page is sound, for `figures` figures.
std::string ReportOkTitle(std::size_t figures);

std::string RenderReportHtml(const RunReport& report);

}  // namespace tpcal::pipeline
