// CSV tables of a run (one header line, comma-separated, numbers printed with shortest
// round-trip precision, text cells quoted when they contain a comma or a quote):
//  - identification.csv: name,iso_symbol,unit,identifiable,value,u,ci95_low,ci95_high,
//      u_analytic,u_jackknife_points,u_jackknife_groups,u_monte_carlo[,truth]  (empty = n/a)
//  - identifiability.csv: kind,text,value,u  (kind: summary | singular_value | estimable | null_direction)
//  - characteristics.csv: characteristic,type,features,value_name,value,unit (one row per value)
//  - features.csv: feature,kind,points,rms_um,form_um
#pragma once

#include <map>
#include <string>

#include "gdt/inspection.h"
#include "kinematics/identification.h"

namespace tpcal::pipeline {

std::string CsvCell(const std::string& text);  // quoted if needed
std::string CsvNumber(double v);               // shortest round-trip, "" for NaN

// `truth`: the stated truth by parameter name (display units); empty: no truth column.
std::string IdentificationCsv(const kinematics::IdentificationResult& identification,
                              const std::map<std::string, double>& truth);
std::string IdentifiabilityCsv(const kinematics::IdentificationResult& identification);
std::string CharacteristicsCsv(const gdt::InspectionResult& inspection);
std::string FeaturesCsv(const gdt::InspectionResult& inspection);

}  // namespace tpcal::pipeline
