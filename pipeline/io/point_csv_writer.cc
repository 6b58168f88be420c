// Writer for the contract point / plan CSV (point_io.h). Numbers use std::to_chars: shortest
// exact form by default (write -> read gives the identical doubles), or fixed decimals.
#include <fmt/format.h>

#include <charconv>
#include <cmath>

#include "core/ascii.h"
#include "pipeline/io/atomic_file.h"
#include "pipeline/io/point_io.h"

namespace tpcal::pipeline {
namespace {

constexpr std::size_t kFlushBytes = 1 << 20;
// A normal farther than this from unit length would be rejected (or silently renormalised)
// by the reader, so the writer refuses it: the caller has a bug.
constexpr double kWriteNormalTolerance = 1e-3;

void AppendNumber(std::string* out, double v, int fixed_decimals) {
  char buf[400];  // fixed notation of the largest double with 17 decimals fits
  const std::to_chars_result r =
      fixed_decimals < 0
          ? std::to_chars(buf, buf + sizeof(buf), v)
          : std::to_chars(buf, buf + sizeof(buf), v, std::chars_format::fixed, fixed_decimals);
  out->append(buf, r.ptr);
}

bool IsBlankCell(char c) { return c == ' ' || c == '\t'; }

// Appends a text cell, quoted when the reader would otherwise change it.
Status AppendText(std::string* out, std::string_view cell, const std::string& what) {
  if (cell.find_first_of("\"\r\n") != std::string_view::npos)
    return Status(StatusCode::kInvalidArgument,
                  fmt::format("{} '{}' contains a quote or line break, which the tpcal CSV "
                              "dialect cannot hold", what, cell));
  const bool quote = cell.find(',') != std::string_view::npos ||
                     (!cell.empty() && (cell.front() == '#' || IsBlankCell(cell.front()) ||
                                        IsBlankCell(cell.back())));
  if (quote) out->push_back('"');
  out->append(cell);
  if (quote) out->push_back('"');
  return Status::Ok();
}

class CsvFormatter {
 public:
  CsvFormatter(const PointSet& ps, const PointWriteOptions& options) : ps_(ps), options_(options) {}

  Status Check() const {
    TPCAL_RETURN_IF_ERROR(options_.Validate());
    const std::size_t n = ps_.size();
    auto invalid = [](std::string msg) { return Status(StatusCode::kInvalidArgument, std::move(msg)); };
    if (n == 0) return invalid("no points to write");
    if (!ps_.normal.empty() && ps_.normal.size() != n)
      return invalid(fmt::format("{} normals for {} points", ps_.normal.size(), n));
    if (!ps_.feature.empty() && ps_.feature.size() != n)
      return invalid(fmt::format("{} feature labels for {} points", ps_.feature.size(), n));
    if (options_.kind == PointFileKind::kPlan && ps_.normal.empty())
      return invalid("a plan file needs normals (columns feature,x,y,z,i,j,k come first)");
    std::vector<std::string> names = {"feature", "x", "y", "z", "i", "j", "k"};
    for (const PointAttribute& a : ps_.attributes) {
      if (a.name.empty()) return invalid("an attribute has an empty name");
      const std::string lname = AsciiLower(a.name);
      for (const std::string& other : names)
        if (lname == other)
          return invalid(fmt::format("attribute name '{}' clashes with another column", a.name));
      names.push_back(lname);
      const std::size_t size = a.is_numeric() ? a.values.size() : a.text.size();
      if (size != n)
        return invalid(fmt::format("attribute '{}' has {} values for {} points", a.name, size, n));
    }
    for (int f : ps_.feature)
      if (f != PointSet::kUnlabelled && (f < 0 || static_cast<std::size_t>(f) >= ps_.feature_names.size()))
        return invalid(fmt::format("feature index {} out of range (have {} names)", f,
                                   ps_.feature_names.size()));
    return Status::Ok();
  }

  Status AppendHeader(std::string* out) const {
    *out += options_.kind == PointFileKind::kPlan ? "# tpcal plan v1\n" : "# tpcal points v1\n";
    *out += "# units: mm\n";
    *out += ps_.has_normals() ? "feature,x,y,z,i,j,k" : "feature,x,y,z";
    for (const PointAttribute& a : ps_.attributes) {
      out->push_back(',');
      TPCAL_RETURN_IF_ERROR(AppendText(out, a.name, "attribute name"));
    }
    out->push_back('\n');
    return Status::Ok();
  }

  Status AppendRow(std::size_t i, std::string* out) const {
    const int f = ps_.feature.empty() ? PointSet::kUnlabelled : ps_.feature[i];
    if (f != PointSet::kUnlabelled)
      TPCAL_RETURN_IF_ERROR(AppendText(out, ps_.feature_names[static_cast<std::size_t>(f)], "feature name"));
    const Eigen::Vector3d& p = ps_.xyz_mm[i];
    if (!p.allFinite())
      return Status(StatusCode::kInvalidArgument, fmt::format("point {} has a non-finite coordinate", i));
    for (int c = 0; c < 3; ++c) {
      out->push_back(',');
      AppendNumber(out, p[c], options_.fixed_decimals);
    }
    if (ps_.has_normals()) {
      const Eigen::Vector3d& n = ps_.normal[i];
      if (!n.allFinite() || std::abs(n.norm() - 1.0) > kWriteNormalTolerance)
        return Status(StatusCode::kInvalidArgument,
                      fmt::format("point {} has a normal of length {:g}, expected a unit vector", i, n.norm()));
      for (int c = 0; c < 3; ++c) {
        out->push_back(',');
        AppendNumber(out, n[c], options_.fixed_decimals);
      }
    }
    for (const PointAttribute& a : ps_.attributes) {
      out->push_back(',');
      if (a.is_numeric()) {
        if (!std::isfinite(a.values[i]))
          return Status(StatusCode::kInvalidArgument,
                        fmt::format("attribute '{}' of point {} is not finite", a.name, i));
        AppendNumber(out, a.values[i], options_.fixed_decimals);
      } else {
        TPCAL_RETURN_IF_ERROR(AppendText(out, a.text[i], "attribute '" + a.name + "' text"));
      }
    }
    out->push_back('\n');
    return Status::Ok();
  }

 private:
  const PointSet& ps_;
  const PointWriteOptions& options_;
};

}  // namespace

Result<std::string> FormatPointCsv(const PointSet& points, const PointWriteOptions& options) {
  CsvFormatter formatter(points, options);
  TPCAL_RETURN_IF_ERROR(formatter.Check());
  std::string out;
  out.reserve(points.size() * (points.has_normals() ? 96 : 48));
  TPCAL_RETURN_IF_ERROR(formatter.AppendHeader(&out));
  for (std::size_t i = 0; i < points.size(); ++i) TPCAL_RETURN_IF_ERROR(formatter.AppendRow(i, &out));
  return out;
}

Status WritePointCsv(const std::string& path, const PointSet& points, const PointWriteOptions& options) {
  CsvFormatter formatter(points, options);
  if (Status s = formatter.Check(); !s.ok()) return s.WithLocation(path);
  Status s = WriteFileAtomic(path, [&](AtomicFileWriter& w) -> Status {
    std::string buf;
    buf.reserve(kFlushBytes + 4096);
    TPCAL_RETURN_IF_ERROR(formatter.AppendHeader(&buf));
    for (std::size_t i = 0; i < points.size(); ++i) {
      TPCAL_RETURN_IF_ERROR(formatter.AppendRow(i, &buf));
      if (buf.size() >= kFlushBytes) {
        TPCAL_RETURN_IF_ERROR(w.Write(buf));
        buf.clear();
      }
    }
    return w.Write(buf);
  });
  if (!s.ok() && s.file().empty()) return s.WithLocation(path);
  return s;
}

}  // namespace tpcal::pipeline
