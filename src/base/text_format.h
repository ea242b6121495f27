// Small text helpers shared by the report writers.
#pragma once
#include <string>

namespace hb {

// printf into a std::string (at most 511 characters; longer output is cut).
std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

// "1 light", "10 lights": n and the noun, plural unless n is 1 (plural: singular + "s" by default).
std::string countOf(unsigned long long n, const std::string& singular, const std::string& plural = "");

// A ratio near 1 (ray efficiency, B/A) with 3 decimals, or as many more as it takes (up to 9) to
// show that a value other than 1 is not 1: 1.0000015 is "1.0000015", never "1.000".
std::string formatNear1(double v);

// Text for XML character data and attribute values: & < > " ' as entities, control characters
// other than tab and newline (not allowed in XML 1.0) as spaces.
std::string escapeXml(const std::string& s);

// ASCII letters A-Z as a-z; every other byte (UTF-8 included) as it is. For extensions, names and
// UUIDs compared without case.
std::string asciiLower(std::string s);
inline char asciiLower(char c) { return c >= 'A' && c <= 'Z' ? char(c - 'A' + 'a') : c; }

}  // namespace hb
