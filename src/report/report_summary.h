// The story of a results file in a few sentences, for the top of report.html: which variant is the
// fastest (median frame time), which the most accurate (by the accuracy report's measure,
// accuracy_report.h), what that accuracy costs in time against the fastest, and the Pareto front of
// time against error from fast to accurate. Every figure is read from the results; none is written
// in. Runs that failed take no part (the page lists them); groups of the accuracy front (AO's d_max,
// indirect light's bounce count) are summarised one by one, each against its own reference.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace hb {

// The summary as an HTML <section id="summary">, its names and figures escaped. Throws InputError
// when `results` is not a schema-1 results file.
std::string reportSummaryHtml(const nlohmann::json& results);

}  // namespace hb
