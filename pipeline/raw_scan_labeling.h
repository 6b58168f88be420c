// Raw-scan labelling: assigns each point of an unlabelled scan (docs/formats/points.md: "a file with
// no labels at all is a raw scan"; coordinates in the CMM frame, the part anywhere, in any
// orientation) to a nominal feature of the test piece, or leaves it unlabelled (outlier, a
// surface the piece does not inspect).
//
// Method (all geometry in double; PCL only for the k-d tree over the nominal sampling):
//  1. Nominal model: the piece's probing plan at a dense density (`nominal_density`), i.e. points
//     and outward normals on every feature's probe-able band in the PART frame, each carrying its
//     feature. A k-d tree over these samples.
//  2. Coarse registration: principal frames of the scan and of the nominal sampling are matched
//     (the points' principal axes, and with normals the principal axes of the normals' orientation
//     tensor sum(n n^T), which stray points with the piece's normal directions do not tilt), in
//     both sign choices, then rotated about each nominal principal axis in `coarse_step_deg` steps
//     (covers pieces whose two principal moments are equal, like a turned part, and axes whose
//     order differs between scan and nominal density). Translation: per axis, the midpoint of the
//     5 % and 95 % quantiles matched (a few percent of stray points on one side do not move it).
//     Each candidate is scored on a subsample by the number of points within
//     `coarse_tolerance_mm` of the tangent plane of their nearest nominal sample, normals agreeing.
//  3. Refinement: point-to-plane ICP (Gauss-Newton on a 6-dof twist) from the best distinct
//     candidates, with a shrinking correspondence gate; for the best two, a fine sweep of
//     +/- coarse_step_deg in 1 degree steps about each principal axis (to seat features that
//     break a rotational symmetry, e.g. holes), ICP again, and three ICP steps against the exact
//     nominal surfaces (testpieces::ProjectOnto of the labelled feature). The candidate labelling
//     more points of the ICP subsample wins.
//  4. Labelling: for each point, the features of its `neighbours` nearest nominal samples are
//     candidates; the point takes the candidate whose exact surface is nearest, provided the
//     distance is <= label_tolerance_mm, the projection lies in the feature's patch and (when the
//     scan has normals) the normals agree within normal_tolerance_deg. Otherwise unlabelled.
//  5. Symmetry: if the nominal piece is invariant under rotations about one of its principal axes
//     that permute feature labels (the turning piece: 16 identical holes, order 16), geometry alone
//     cannot tell H1 from H2. The placements related by the symmetry all fit equally well; the one
//     chosen is the one whose labels, read in FILE ORDER, come first in the piece's feature order
//     (a CMM program scans features in plan order, H1 first), unless an anchor is given
//     (RawScanLabelingOptions::anchor_feature near anchor_near_mm: the placement putting that
//     feature nearest the point). RawScanLabeling::symmetry_order says when this choice was needed
//     and symmetry_resolved_by how; a scan in random point order without an anchor gets a
//     consistent but arbitrary choice among the equivalent labellings.
// Cost: a fixed ~0.3 s (nominal sampling of ~45k points, 432 coarse candidates) plus ~4 us per
// point, labelled on all cores from 20000 points. Deterministic (no randomness).
// Failure: kTooFewPoints (fewer than min_points), kNotConverged when the best placement labels
// less than min_labelled_fraction of the points or their RMS distance exceeds max_rms_um (the
// scan is not this piece, or the part is too far from nominal). Messages name the scan's source.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "core/frames.h"
#include "core/point_set.h"
#include "core/status.h"
#include "pipeline/io/point_io.h"
#include "testpieces/test_piece.h"

namespace tpcal::pipeline {

struct RawScanLabelingOptions {
  // A point is labelled when within this distance of a nominal feature surface. 0.2 mm: much
  // larger than machine errors (~50 um) and CMM noise, much smaller than feature spacing (>= 5 mm).
  double label_tolerance_mm = 0.2;
  double normal_tolerance_deg = 30.0;  // scan normal vs nominal normal (ignored without normals)
  double coarse_step_deg = 10.0;       // rotation sweep step of the coarse search
  double coarse_tolerance_mm = 2.0;    // inlier distance when scoring coarse candidates
  int coarse_sample_points = 300;      // scan points used to score candidates (and quick ICP)
  int icp_sample_points = 2000;        // scan points used by the final ICP
  int refine_candidates = 4;           // distinct coarse candidates refined by a quick ICP (the
                                       // best two by a fine sweep and full ICP)
  int neighbours = 8;                  // nominal samples consulted per point when labelling
  // Below this labelled fraction the registration is declared failed. A scan also covers surfaces
  // the piece does not inspect (top face, flange, fixture), so this is low; random points reach
  // ~0.1 %, a correct placement of a clean simulated scan 100 %.
  double min_labelled_fraction = 0.5;
  double max_rms_um = 100.0;           // RMS distance of labelled points above this: failed
  std::size_t min_points = 20;
  // Density of the nominal sampling (part frame): many points per circle and levels so that
  // every scanned point has samples of its feature within a few mm.
  testpieces::ProbingOptions nominal_density = DefaultNominalDensity();
  // A symmetric piece (the turning piece's 16 holes) has several equivalent labellings. With an
  // anchor, the one placing feature `anchor_feature` nearest `anchor_near_mm` (scan frame, e.g.
  // H1's approximate centre) is chosen; without, the one listing features in plan order in the
  // file (a scanner's file in arbitrary order then gets an arbitrary but consistent H1).
  std::string anchor_feature;
  std::optional<Eigen::Vector3d> anchor_near_mm;

  static testpieces::ProbingOptions DefaultNominalDensity();
  Status Validate() const;
};

struct FeatureLabelCount {
  std::string feature;
  std::size_t points = 0;
};

struct RawScanLabeling {
  // Only the labelled points, with their labels (feature names in the piece's order), normals
  // and source lines kept; source unchanged. What the rest of the pipeline reads.
  PointSet labelled;
  // Per input point: index into piece.features, or PointSet::kUnlabelled (rejected).
  std::vector<int> piece_feature;
  Rigid3 part_from_cmm = Rigid3::Identity();  // p_in_part = part_from_cmm * p_in_cmm
  std::vector<FeatureLabelCount> counts;      // per piece feature (piece order), zeros included
  std::size_t num_points = 0;
  std::size_t num_rejected = 0;
  double labelled_fraction = 0.0;
  double rms_distance_um = 0.0;  // RMS distance of labelled points to their nominal surface
  int candidates_scored = 0;     // coarse placements scored
  int symmetry_order = 1;        // order of the label-permuting rotational symmetry found (1: none)
  std::string symmetry_resolved_by;  // "file order" or "anchor <feature>" (empty without symmetry)
  std::string message;           // how the placement was chosen (symmetry rule when applied)

  // "5248 points: 5248 labelled (100.0 %), 0 rejected, RMS 12.3 um; S_R 320, B_R 320, ..."
  std::string BriefReport() const;
};

// `scan` in the CMM frame (labels ignored; normals used when present). Errors as described above.
Result<RawScanLabeling> LabelRawScan(const testpieces::TestPiece& piece, const PointSet& scan,
                                     const RawScanLabelingOptions& options = {});

// What every command does with a point file: if `points` carries no labels (a raw scan), it is
// replaced by its labelled points and the labelling summary is returned (its `labelled` and
// `piece_feature` emptied); a labelled file is left as it is (std::nullopt). Errors: LabelRawScan's.
Result<std::optional<RawScanLabeling>> LabelIfRawScan(const testpieces::TestPiece& piece, PointSet* points,
                                                      const RawScanLabelingOptions& options = {});

struct LabelledPoints {
  PointSet points;                          // labelled (a raw scan: its labelled points)
  std::optional<RawScanLabeling> raw_scan;  // set when the file was a raw scan (LabelIfRawScan)
};
// Reads a point file (ReadPoints with `read`) and labels it if it is a raw scan (LabelIfRawScan).
// Errors: theirs.
Result<LabelledPoints> ReadLabelledPoints(const std::string& path, const testpieces::TestPiece& piece,
                                          const RawScanLabelingOptions& options = {}, const PointReadOptions& read = {});

}  // namespace tpcal::pipeline
