// Test helper for the report writers' XML output (accuracy SVG, compare's JUnit report).
#pragma once
#include <string>
#include <vector>

namespace hb::testing {

// Checks XML (an SVG, a JUnit report) is well-formed enough: tags nest and balance, attribute quotes close, and every
// '&' starts an entity. Returns "" or what is wrong.
inline std::string xmlProblem(const std::string& s) {
  std::vector<std::string> stack;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '&') {
      const size_t semi = s.find(';', i);
      const std::string ent = s.substr(i, semi == std::string::npos ? 0 : semi - i + 1);
      if (ent != "&amp;" && ent != "&lt;" && ent != "&gt;" && ent != "&quot;" && ent != "&apos;")
        return "bare '&' at " + std::to_string(i);
      continue;
    }
    if (s[i] == '>') return "stray '>' at " + std::to_string(i);
    if (s[i] != '<') continue;
    size_t end = i + 1;
    bool inQuote = false;
    while (end < s.size() && (inQuote || s[end] != '>')) {
      if (s[end] == '"') inQuote = !inQuote;
      if (!inQuote && s[end] == '<') return "'<' inside tag at " + std::to_string(end);
      ++end;
    }
    if (end == s.size()) return "unclosed tag at " + std::to_string(i);
    const std::string tag = s.substr(i + 1, end - i - 1);
    i = end;
    if (tag[0] == '?' || tag[0] == '!') continue;
    if (tag[0] == '/') {
      if (stack.empty() || stack.back() != tag.substr(1)) return "mismatched </" + tag.substr(1) + ">";
      stack.pop_back();
    } else if (tag.back() != '/') {
      stack.push_back(tag.substr(0, tag.find_first_of(" \n\t")));
    }
  }
  return stack.empty() ? "" : "unclosed <" + stack.back() + ">";
}

}  // namespace hb::testing
