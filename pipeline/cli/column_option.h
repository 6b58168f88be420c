// The --column ROLE=NAME option that `tpcal fit`, `identify`, `diagnose` and `run` share: a point
// table's own column name for a role (feature, x, y, z, i, j, k), over the contract names and
// their aliases; repeat it per role, e.g. --column "feature=Point ID" --column x=X_mm.
// pipeline/io/point_io.h, PointReadOptions::columns and ParsePointColumns. CLI layer only.
#pragma once

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace tpcal::cli {

// Adds --column to `sub`, its values kept as written in `columns` (checked by ParsePointColumns
// when the stage reads the file: an unknown role, a role twice or an empty name exits 2).
void AddColumnOption(CLI::App* sub, std::vector<std::string>* columns);

}  // namespace tpcal::cli
