// --column ROLE=NAME: see column_option.h.
#include "pipeline/cli/column_option.h"

#include <CLI/CLI.hpp>

namespace tpcal::cli {

void AddColumnOption(CLI::App* sub, std::vector<std::string>* columns) {
  sub->add_option("--column", *columns,
                  "ROLE=NAME: the point table's column NAME holds ROLE (feature, x, y, z, i, j or k), over the "
                  "contract names and their aliases; repeat per role, e.g. --column \"feature=Point ID\" "
                  "(CSV and TSV tables only; names match case-insensitively)")
      ->take_all()
      ->allow_extra_args(false);
}

}  // namespace tpcal::cli
