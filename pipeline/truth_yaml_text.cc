#include "pipeline/truth_yaml_text.h"

#include <fmt/format.h>

#include <sstream>

namespace tpcal::pipeline {

std::string TruthNum(double v) { return fmt::format("{:.17g}", v == 0.0 ? 0.0 : v); }

std::string TruthStr(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out.push_back('\\');
    out.push_back(c);
  }
  return out + "\"";
}

std::string IndentLines(const std::string& text, const std::string& pad) {
  std::istringstream in(text);
  std::string line, out;
  while (std::getline(in, line)) out += line.empty() ? "\n" : pad + line + "\n";
  return out;
}

}  // namespace tpcal::pipeline
