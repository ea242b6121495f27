#include "base/text_format.h"

#include <cstdarg>
#include <cstdio>

namespace hb {

std::string format(const char* fmt, ...) {
  char buf[512];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, args);
  va_end(args);
  return buf;
}

std::string countOf(unsigned long long n, const std::string& singular, const std::string& plural) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural.empty() ? singular + "s" : plural);
}

std::string formatNear1(double v) {
  for (int digits = 3; digits < 9; ++digits) {
    const std::string text = format("%.*f", digits, v);
    if (v == 1.0 || (text != format("%.*f", digits, 1.0) && text != format("%.*f", digits, -1.0))) return text;
  }
  return format("%.9f", v);
}

std::string escapeXml(const std::string& s) {
  std::string out;
  for (char ch : s) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default:
        // Control characters other than tab/newline are not allowed in XML 1.0.
        if (static_cast<unsigned char>(ch) < 0x20 && ch != '\t' && ch != '\n')
          out += ' ';
        else
          out += ch;
    }
  }
  return out;
}

std::string asciiLower(std::string s) {
  for (char& c : s) c = asciiLower(c);
  return s;
}

}  // namespace hb
