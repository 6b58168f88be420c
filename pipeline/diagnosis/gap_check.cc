#include "pipeline/diagnosis/gap_check.h"

#include <fmt/format.h>

namespace tpcal::pipeline {

GapCheck GapCheckOf(const DiagnosisResult& diagnosis) {
  const Verdict& v = diagnosis.verdict;
  GapCheck check{.family = v.family, .families = v.families, .name = v.name, .cv_shrink_pct = v.cv_shrink_pct, .warning = ""};
  if (v.family == "none") return check;
  std::string named = v.family;
  for (std::size_t i = 1; i < v.families.size(); ++i) named += " + " + v.families[i];
  if (v.family == "local_defect")
    check.warning = fmt::format("the gap holds a local defect ({}): its points are listed and left out unless "
                                "--keep-outliers; see tpcal diagnose",
                                v.name);
  else if (v.family == "unexplained")
    check.warning = "the gap stands out beyond noise where no candidate effect explains it: the errors above "
                    "may be biased by an effect tpcal does not model; see tpcal diagnose";
  else
    check.warning = fmt::format("the gap diagnosis names {} ({}, cross-validated shrink {:.0f} %), which the "
                                "identified model does not hold: the errors above may be biased by it; "
                                "tpcal diagnose re-identifies them with it modelled (base_shift)",
                                named, v.name, v.cv_shrink_pct);
  return check;
}

}  // namespace tpcal::pipeline
