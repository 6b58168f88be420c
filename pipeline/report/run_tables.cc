#include "pipeline/report/run_tables.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>

#include "core/units.h"

namespace tpcal::pipeline {

std::string CsvCell(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::string CsvNumber(double v) {
  if (!std::isfinite(v)) return "";
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof(buf), v);
  return ec == std::errc() ? std::string(buf, end) : std::string();
}

namespace {
std::string MethodU(const kinematics::ParameterEstimate& p, kinematics::UncertaintyMethod m) {
  for (const auto& u : p.uncertainties)
    if (u.method == m && u.available) return CsvNumber(u.u);
  return "";
}
}  // namespace

std::string IdentificationCsv(const kinematics::IdentificationResult& identification,
                              const std::map<std::string, double>& truth_by_name) {
  using kinematics::UncertaintyMethod;
  const bool truth = !truth_by_name.empty();
  std::string out =
      "name,iso_symbol,unit,identifiable,value,u,ci95_low,ci95_high,u_analytic,u_jackknife_points,"
      "u_jackknife_groups,u_monte_carlo";
  out += truth ? ",truth\n" : "\n";
  for (const auto& p : identification.parameters) {
    out += CsvCell(p.name) + "," + CsvCell(p.iso_symbol) + "," + p.unit + "," + (p.identifiable ? "true" : "false");
    if (p.identifiable) {
      out += "," + CsvNumber(p.value) + "," + CsvNumber(p.u) + "," + CsvNumber(p.ci95_low) + "," +
             CsvNumber(p.ci95_high);
    } else {
      out += ",,,,";
    }
    for (auto m : {UncertaintyMethod::kAnalytic, UncertaintyMethod::kJackknifePoints,
                   UncertaintyMethod::kJackknifeGroups, UncertaintyMethod::kMonteCarlo})
      out += "," + (p.identifiable ? MethodU(p, m) : std::string());
    if (truth) {
      auto it = truth_by_name.find(p.name);
      out += "," + (it != truth_by_name.end() ? CsvNumber(it->second) : std::string());
    }
    out += "\n";
  }
  return out;
}

std::string IdentifiabilityCsv(const kinematics::IdentificationResult& identification) {
  const auto& ia = identification.identifiability;
  std::string out = "kind,text,value,u\n";
  out += "summary,num_parameters," + std::to_string(ia.num_parameters) + ",\n";
  out += "summary,rank," + std::to_string(ia.rank) + ",\n";
  out += "summary,condition_number," + CsvNumber(ia.condition_number) + ",\n";
  for (std::size_t i = 0; i < ia.singular_values.size(); ++i)
    out += fmt::format("singular_value,s{},{},\n", i + 1, CsvNumber(ia.singular_values[i]));
  for (const auto& c : ia.estimable)
    out += "estimable," + CsvCell(c.text) + "," + CsvNumber(c.value) + "," + CsvNumber(c.u) + "\n";
  for (const auto& c : ia.null_directions) out += "null_direction," + CsvCell(c.text) + ",,\n";
  return out;
}

std::string CharacteristicsCsv(const gdt::InspectionResult& inspection) {
  std::string out = "characteristic,type,features,value_name,value,unit\n";
  for (const auto& c : inspection.characteristics) {
    std::string features;
    for (const auto& f : c.features) features += (features.empty() ? "" : " ") + f;
    for (const auto& v : c.values)
      out += CsvCell(c.name) + "," + gdt::CharacteristicTypeName(c.type) + "," + CsvCell(features) + "," +
             CsvCell(v.name) + "," + CsvNumber(v.value) + "," + v.unit + "\n";
  }
  return out;
}

std::string FeaturesCsv(const gdt::InspectionResult& inspection) {
  std::string out = "feature,kind,points,rms_um,form_um\n";
  for (const auto& f : inspection.features) {
    std::size_t n = 0;
    double rms_mm = 0;
    std::visit([&](const auto& fit) { n = fit.n_points; rms_mm = fit.stats.rms_mm; }, f.fit);
    const auto form = f.form_mm();
    out += CsvCell(f.name) + "," + gdt::FeatureKindName(f.kind) + "," + std::to_string(n) + "," +
           CsvNumber(MmToUm(rms_mm)) + "," + (form ? CsvNumber(MmToUm(*form)) : std::string()) + "\n";
  }
  return out;
}

}  // namespace tpcal::pipeline
