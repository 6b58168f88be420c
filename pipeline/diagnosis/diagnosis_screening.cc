#include "pipeline/diagnosis/diagnosis_screening.h"

#include <algorithm>
#include <memory>
#include <utility>

#include "kinematics/slot_linearisation.h"

namespace tpcal::pipeline::diagnosis_internal {

ScreenedInput ScreenBaseFit(const BaseFit& fit, const testpieces::MeasuredObservations& mo,
                            const DiagnosisOptions& options, const Eigen::VectorXd* reference_dev_um,
                            const Eigen::MatrixXd* effect) {
  ScreenedInput in;
  OutlierScreenOptions screen = options.screen;
  screen.min_sigma_um = std::max(screen.min_sigma_um, options.noise_um);
  if (effect) {
    Eigen::MatrixXd X(fit.basis.U.rows(), fit.basis.U.cols() + effect->cols());
    X << fit.basis.U, *effect;
    in.screen = ScreenOutliers(X, fit.y, mo.observations, screen, fit.reference_remaining_um, options.neighbour_graph);
  } else {
    in.screen =
        ScreenOutliers(fit.basis.U, fit.y, mo.observations, screen, fit.reference_remaining_um, options.neighbour_graph);
  }
  in.left_out = options.screen_outliers && in.screen.CountFlagged() > 0;
  if (!in.left_out) return in;
  const std::vector<int> rows = in.screen.KeptIndices();
  in.observations = ObservationRows(mo, rows);
  if (reference_dev_um) {
    in.reference_dev_um.resize(static_cast<Eigen::Index>(rows.size()));
    for (std::size_t k = 0; k < rows.size(); ++k) in.reference_dev_um(static_cast<Eigen::Index>(k)) = (*reference_dev_um)(rows[k]);
  }
  in.options = options;
  in.options.neighbour_graph = nullptr;  // of every observation, not of those kept
  const auto& given = options.nominal_slot_design;
  in.options.nominal_slot_design = nullptr;
  if (given && given->dslot_um.rows() == static_cast<Eigen::Index>(mo.observations.size()))
    in.options.nominal_slot_design = std::make_shared<const kinematics::SlotDesign>(kinematics::RowsOf(*given, rows));
  return in;
}

void ReportScreen(const ScreenedInput& in, const testpieces::MeasuredObservations& mo, DiagnosisResult* out) {
  out->neighbour_sigma_um = in.screen.sigma_um;
  ListFlagged(in.screen, mo, in.left_out, &out->outliers, &out->local_defects);
}

}  // namespace tpcal::pipeline::diagnosis_internal
