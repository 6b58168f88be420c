// ASCII case folding for names read from files and command lines (units, keywords, column names,
// extensions): only A-Z change, whatever the locale, so a UTF-8 name keeps its other bytes.
#pragma once

#include <string>
#include <string_view>

namespace tpcal {

// `s` with A-Z lowered to a-z; every other byte unchanged. Never fails.
inline std::string AsciiLower(std::string_view s) {
  std::string out(s);
  for (char& c : out)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return out;
}

}  // namespace tpcal
