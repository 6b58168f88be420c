// Where an instrument's machine errors (a probing test: datum ball, ...) and a test piece's agree
// (issue 22). Per parameter: the instrument's value +- u, the piece's, and z = (piece -
// instrument) / sqrt(u_i^2 + u_p^2). A row disagrees when its two-sided normal p-value
// erfc(|z| / sqrt 2) is below alpha / (rows compared) (Bonferroni: the family-wise false-alarm
// probability when the two agree is at most alpha). A parameter one side cannot identify gets no
// z; the piece's estimable combinations of its unidentifiable parameters are compared with the
// same combination of the instrument's values (their u combined as independent).
#pragma once

#include <span>
#include <string>
#include <vector>

#include "kinematics/identification.h"
#include "pipeline/diagnosis/outlier_screen.h"

namespace tpcal::pipeline {

struct AgreementRow {
  std::string name;              // ISO 230-1 parameter, or the combination's text
  std::vector<std::string> members;  // the parameter, or the combination's parameters
  std::string unit;              // "um" or "urad"
  bool instrument_known = false, piece_known = false;
  double instrument_value = 0.0, instrument_u = 0.0;  // display units, k = 1
  double piece_value = 0.0, piece_u = 0.0;
  bool compared = false;         // both known, and a u on at least one side
  double z = 0.0;                // (piece - instrument) / combined u; 0 unless compared
  double p_value = 1.0;          // two-sided; 1 unless compared
  bool agree = true;             // not compared counts as agreeing
  std::string note;              // why a row is not compared
};

struct ReferenceAgreement {
  std::string instrument;        // "datum_ball"
  std::string source;            // the instrument's file
  double alpha = 0.01;
  double p_threshold = 0.0;      // alpha / compared
  int compared = 0, disagreeing = 0;
  std::vector<AgreementRow> rows;  // the instrument's parameters in its order, then combinations
  // The reference the piece's gap is measured against: the instrument's errors updated by the
  // piece within the instrument's u (kinematics/prior_update.h), largest change named.
  std::string reference_note;
  // The points the outlier screen of the piece's identification behind the rows flagged (its
  // parameters are fitted without those left out), with their patches; empty when it flagged none.
  std::vector<ScreenedPoint> piece_outliers;
  std::vector<LocalDefect> piece_local_defects;
};

// The table. `instrument` and `piece` by parameter name (units must match: a mismatch is not
// compared, noted); combinations from `piece_identifiability.estimable`.
ReferenceAgreement CompareWithReference(std::span<const kinematics::ParameterEstimate> instrument,
                                        std::span<const kinematics::ParameterEstimate> piece,
                                        const kinematics::Identifiability& piece_identifiability, double alpha);

}  // namespace tpcal::pipeline
