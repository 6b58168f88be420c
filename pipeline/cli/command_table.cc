#include <algorithm>
#include <utility>
#include <vector>

#include "pipeline/cli/commands.h"

namespace tpcal::cli {
namespace {
std::vector<std::pair<int, Registrar>>& Table() {
  static std::vector<std::pair<int, Registrar>> table;  // filled before main, read in main
  return table;
}
}  // namespace

bool AddCommand(int order, Registrar registrar) {
  Table().emplace_back(order, registrar);
  return true;
}

std::vector<Registrar> RegisteredCommands() {
  auto sorted = Table();
  std::stable_sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Registrar> out;
  for (const auto& [order, reg] : sorted) out.push_back(reg);
  return out;
}

}  // namespace tpcal::cli
