// history --html: one self-contained page of a history (report/history.h), in the style of
// report.html (inline CSS and SVG, no JavaScript, no network): the changes' table, then one plot
// per series, its runs' medians in order as circles (each with a <title> naming its revision, date
// and file) and each change as a dashed vertical line before its first run.
#pragma once
#include <string>

#include "report/history.h"

namespace hb {

// The page: the series with changes, or every series with allSeries. Deterministic (the same report
// gives the same bytes).
std::string historyHtml(const HistoryReport& report, bool allSeries);

// One series' plot, an inline <svg>: for the page and for tests.
std::string historySeriesSvg(const HistorySeries& series);

}  // namespace hb
