#include "gcode/nc_format.h"

#include <cctype>
#include <cmath>
#include <cstdio>

namespace tpcal::gcode {

std::string FormatNumber(double v, int decimals, NumberStyle style) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  std::string s = buf;
  if (s.find('.') != std::string::npos) {
    while (!s.empty() && s.back() == '0') s.pop_back();
  }
  bool integral = false;
  if (!s.empty() && s.back() == '.') {
    s.pop_back();
    integral = true;
  }
  if (s == "-0") s = "0";
  if (style == NumberStyle::kPoint && integral) s += '.';
  if (style == NumberStyle::kPoint && s.find('.') == std::string::npos) s += '.';
  if (style == NumberStyle::kSigned && s[0] != '-') s = "+" + s;
  return s;
}

std::string SanitizeComment(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char ch : text) {
    const unsigned char u = static_cast<unsigned char>(ch);
    if (ch == '(') {
      out += '[';
    } else if (ch == ')') {
      out += ']';
    } else if (ch == '\n' || ch == '\r' || ch == '\t') {
      out += ' ';
    } else if (u < 32 || u > 126) {
      out += '?';
    } else {
      out += ch;
    }
  }
  return out;
}

std::string Upper(std::string_view text) {
  std::string out(text);
  for (char& ch : out) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  return out;
}

}  // namespace tpcal::gcode
