#include "pipeline/diagnosis/reference_agreement.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace tpcal::pipeline {
namespace {

using kinematics::ParameterEstimate;

std::map<std::string, const ParameterEstimate*> ByName(std::span<const ParameterEstimate> params) {
  std::map<std::string, const ParameterEstimate*> out;
  for (const ParameterEstimate& p : params) out[p.name] = &p;
  return out;
}

AgreementRow ParameterRow(const ParameterEstimate& inst, const ParameterEstimate* piece) {
  AgreementRow row;
  row.name = inst.name, row.unit = inst.unit;
  row.members = {inst.name};
  row.instrument_known = inst.identifiable;
  row.instrument_value = inst.value, row.instrument_u = inst.u;
  row.piece_known = piece && piece->identifiable && piece->unit == inst.unit;
  if (row.piece_known) row.piece_value = piece->value, row.piece_u = piece->u;
  if (!row.instrument_known) row.note = "not identifiable by the instrument's plan";
  else if (!piece) row.note = "not in the piece's model";
  else if (piece->unit != inst.unit) row.note = "units differ (" + piece->unit + ")";
  else if (!piece->identifiable) row.note = "not identifiable by the piece (see its combinations)";
  return row;
}

// The piece's combination against the same combination of the instrument's values; not compared
// when the instrument lacks one of its parameters.
AgreementRow CombinationRow(const kinematics::Combination& c, const std::map<std::string, const ParameterEstimate*>& inst) {
  AgreementRow row;
  row.name = c.text;
  row.members = c.names;
  row.piece_known = true, row.piece_value = c.value, row.piece_u = c.u;
  double value = 0.0, var = 0.0;
  row.instrument_known = true;
  for (std::size_t k = 0; k < c.names.size(); ++k) {
    auto it = inst.find(c.names[k]);
    if (it == inst.end() || !it->second->identifiable) {
      row.instrument_known = false;
      row.note = c.names[k] + " not identified by the instrument";
      break;
    }
    if (row.unit.empty()) row.unit = it->second->unit;
    value += c.coefficients[k] * it->second->value;
    var += c.coefficients[k] * c.coefficients[k] * it->second->u * it->second->u;
  }
  if (row.instrument_known) row.instrument_value = value, row.instrument_u = std::sqrt(var);
  return row;
}

// Without u on either side a difference has no scale: the row is not compared (noted).
void Score(AgreementRow* row) {
  const double u = std::hypot(row->instrument_u, row->piece_u);
  row->compared = row->instrument_known && row->piece_known && u > 0.0;
  if (row->instrument_known && row->piece_known && !(u > 0.0)) row->note = "no u on either side";
  if (!row->compared) return;
  row->z = (row->piece_value - row->instrument_value) / u;
  row->p_value = std::erfc(std::abs(row->z) / std::sqrt(2.0));
}

}  // namespace

ReferenceAgreement CompareWithReference(std::span<const ParameterEstimate> instrument,
                                        std::span<const ParameterEstimate> piece,
                                        const kinematics::Identifiability& piece_identifiability, double alpha) {
  ReferenceAgreement out;
  out.alpha = alpha;
  const auto piece_by_name = ByName(piece);
  const auto inst_by_name = ByName(instrument);
  for (const ParameterEstimate& p : instrument) {
    auto it = piece_by_name.find(p.name);
    out.rows.push_back(ParameterRow(p, it == piece_by_name.end() ? nullptr : it->second));
  }
  for (const kinematics::Combination& c : piece_identifiability.estimable)
    out.rows.push_back(CombinationRow(c, inst_by_name));
  for (AgreementRow& row : out.rows) {
    Score(&row);
    out.compared += row.compared ? 1 : 0;
  }
  out.p_threshold = out.compared > 0 ? alpha / out.compared : alpha;
  for (AgreementRow& row : out.rows) {
    row.agree = !row.compared || row.p_value >= out.p_threshold;
    out.disagreeing += row.agree ? 0 : 1;
  }
  return out;
}

}  // namespace tpcal::pipeline
