// Association of measured points with the cuts that made them: every labelled point of a point
// set, moved into the nominal part frame through a datum frame, paired with the machine state of
// its cut (CutPointAtDatum). The one association of the chain: identification, diagnosis, scan
// cells and the validation all take its MeasuredObservations.
#pragma once

#include <string>
#include <vector>

#include "core/frames.h"
#include "core/point_set.h"
#include "core/status.h"
#include "kinematics/identification.h"
#include "testpieces/test_piece.h"

namespace tpcal::testpieces {

struct MeasuredObservations {
  std::vector<kinematics::Observation> observations;  // group = index into feature_names
  std::vector<std::string> feature_names;              // in order of first appearance in the file
  std::vector<std::size_t> point_index;                // index into the PointSet of each observation
};

// What a point that no cut of its feature reaches (e.g. at a face edge, pushed out of the
// machined band by errors and noise) does to the association.
enum class UnreachedPoint {
  kFail,  // the first such point in file order is the error (file:line)
  kSkip,  // it is left out and listed in *skipped as "file:line: why"
};

// Labelled points of `measured` (CMM frame, mm) as observations in the nominal part frame, using
// the datum frame `datum_from_cmm`. Errors (file:line): an unlabelled point, a feature the piece
// does not have, and with UnreachedPoint::kFail a point no cut of its feature reaches. Runs on
// all cores; the result does not depend on the thread count.
Result<MeasuredObservations> AssociatePoints(const TestPiece& piece, const PointSet& measured,
                                             const Rigid3& datum_from_cmm,
                                             UnreachedPoint unreached = UnreachedPoint::kFail,
                                             std::vector<std::string>* skipped = nullptr);

}  // namespace tpcal::testpieces
