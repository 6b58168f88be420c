// FormatPointQif (qif_reader.h): a minimal QIF 3.0 results document for tpcal's own points.
#include <fmt/format.h>

#include <iterator>
#include <string>
#include <vector>

#include "core/xml_escape.h"
#include "pipeline/io/qif_reader.h"

namespace tpcal::pipeline {

std::string FormatPointQif(const PointSet& points) {
  // Features in order of first appearance; unlabelled points last.
  std::vector<int> order;
  std::vector<std::vector<std::size_t>> members(points.feature_names.size() + 1);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int f = i < points.feature.size() ? points.feature[i] : PointSet::kUnlabelled;
    const std::size_t slot = f == PointSet::kUnlabelled ? points.feature_names.size() : static_cast<std::size_t>(f);
    if (members[slot].empty()) order.push_back(static_cast<int>(slot));
    members[slot].push_back(i);
  }
  auto name_of = [&](int slot) {
    return static_cast<std::size_t>(slot) == points.feature_names.size() ? std::string("unlabelled")
                                                                         : points.feature_names[static_cast<std::size_t>(slot)];
  };
  std::string out;
  out.reserve(points.size() * 80 + 4096);
  auto app = std::back_inserter(out);
  const std::size_t nf = order.size();
  // ids: item 10+3k, measurement 11+3k, point set 12+3k
  fmt::format_to(app,
                 "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                 "<QIFDocument xmlns=\"http://qifstandards.org/xsd/qif3\" versionQIF=\"3.0.0\" idMax=\"{}\">\n"
                 "  <Header><Application><Name>tpcal</Name></Application></Header>\n"
                 "  <FileUnits><PrimaryUnits><LinearUnit><SIUnitName>meter</SIUnitName><UnitName>mm</UnitName>"
                 "<UnitConversion><Factor>0.001</Factor></UnitConversion></LinearUnit></PrimaryUnits></FileUnits>\n"
                 "  <Features>\n    <FeatureItems n=\"{}\">\n",
                 12 + 3 * nf, nf);
  for (std::size_t k = 0; k < nf; ++k)
    fmt::format_to(app, "      <OtherShapeFeatureItem id=\"{}\"><FeatureName>{}</FeatureName></OtherShapeFeatureItem>\n",
                   10 + 3 * k, XmlEscape(name_of(order[k])));
  fmt::format_to(app, "    </FeatureItems>\n  </Features>\n  <Results>\n    <MeasurementResultsSet n=\"1\">\n"
                      "      <MeasurementResults id=\"1\">\n        <MeasuredFeatures n=\"{}\">\n", nf);
  for (std::size_t k = 0; k < nf; ++k)
    fmt::format_to(app,
                   "          <OtherShapeFeatureMeasurement id=\"{}\"><FeatureItemId>{}</FeatureItemId>"
                   "<PointList n=\"1\"><WholePointSetId>{}</WholePointSetId></PointList></OtherShapeFeatureMeasurement>\n",
                   11 + 3 * k, 10 + 3 * k, 12 + 3 * k);
  fmt::format_to(app, "        </MeasuredFeatures>\n        <MeasuredPointSets n=\"{}\">\n", nf);
  for (std::size_t k = 0; k < nf; ++k) {
    const auto& idx = members[static_cast<std::size_t>(order[k])];
    fmt::format_to(app, "          <MeasuredPointSet id=\"{}\" count=\"{}\">\n            <Points>\n", 12 + 3 * k, idx.size());
    for (std::size_t i : idx) {
      const Eigen::Vector3d& p = points.xyz_mm[i];
      fmt::format_to(app, "{} {} {}\n", p.x(), p.y(), p.z());
    }
    out += "            </Points>\n";
    if (points.has_normals()) {
      out += "            <Normals>\n";
      for (std::size_t i : idx) {
        const Eigen::Vector3d& n = points.normal[i];
        fmt::format_to(app, "{} {} {}\n", n.x(), n.y(), n.z());
      }
      out += "            </Normals>\n";
    }
    out += "            <Compensated>true</Compensated>\n          </MeasuredPointSet>\n";
  }
  out += "        </MeasuredPointSets>\n      </MeasurementResults>\n    </MeasurementResultsSet>\n  </Results>\n"
         "</QIFDocument>\n";
  return out;
}

}  // namespace tpcal::pipeline
