// Small text helpers shared by the report writers.
#pragma once
#include <string>

namespace hb {

// printf into a std::string (at most 511 characters; longer output is cut).
std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

// Text for XML character data and attribute values: & < > " ' as entities, control characters
// other than tab and newline (not allowed in XML 1.0) as spaces.
std::string escapeXml(const std::string& s);

}  // namespace hb
