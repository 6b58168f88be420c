// What the reader of an identification must know from the gap diagnosis of the same data
// (diagnosis.h): the verdict, and a warning when it names an effect the identified model does not
// hold (the identified errors may be biased by it). `tpcal identify` reports it.
#pragma once

#include <string>
#include <vector>

#include "pipeline/diagnosis/diagnosis.h"

namespace tpcal::pipeline {

// What the identification's reader must know from its diagnosis: the verdict, and a warning
// when it names an effect the identified model does not hold (the errors may be biased by it).
struct GapCheck {
  std::string family = "none";        // the verdict's family
  std::vector<std::string> families;  // every family the verdict names
  std::string name;                   // the verdict's candidate
  double cv_shrink_pct = 0.0;         // cross-validated shrink of the gap by the verdict
  std::string warning;                // "" when the verdict is none
};

// The check from a diagnosis: a warning for every verdict but none.
GapCheck GapCheckOf(const DiagnosisResult& diagnosis);

}  // namespace tpcal::pipeline
