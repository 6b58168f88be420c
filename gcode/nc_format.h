// Number and text formatting of NC words, shared by the posts and the readers.
#pragma once

#include <string>
#include <string_view>

namespace tpcal::gcode {

enum class NumberStyle {
  kPlain,       // "140", "-3.5" (LinuxCNC, Sinumerik)
  kPoint,       // "140.", "-3.5": Fanuc, where a number without a point counts least increments
  kSigned,      // "+140", "-3.5" (Heidenhain coordinates)
};

// `v` rounded to `decimals` places, trailing zeros dropped, "-0" written as 0.
std::string FormatNumber(double v, int decimals, NumberStyle style = NumberStyle::kPlain);

// Comment text safe in every dialect: printable ASCII, '(' ')' replaced by '[' ']', no newlines.
std::string SanitizeComment(std::string_view text);

// Upper-case copy (ASCII).
std::string Upper(std::string_view text);

}  // namespace tpcal::gcode
