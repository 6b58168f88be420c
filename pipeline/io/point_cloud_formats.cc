// PLY and PCD point clouds through PCL, and plain xyz text (through the shared text parser).
// PCL is included here only. Clouds go through pcl::PCLPointCloud2 so each field keeps its
// own type: a PLY with `property double x` is read at full double precision, and the writers
// store float64 fields (PCL's PointXYZ / PointNormal would round to float: 7.6 nm at 100 mm).
#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/exceptions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>

#include "core/units.h"
#include "pipeline/io/atomic_file.h"
#include "pipeline/io/cloud_file_check.h"
#include "pipeline/io/file_bytes.h"
#include "pipeline/io/point_io.h"
#include "pipeline/io/point_text_parser.h"

namespace tpcal::pipeline {
namespace {

constexpr double kCloudZeroNormalLength = 1e-12;  // as in the CSV reader
constexpr double kCloudAlreadyUnit = 1e-14;
constexpr double kCloudMaxAbsCoordinateMm = 1e9;  // as in the CSV reader

// PCL prints warnings and errors to the console; libraries here never print. Not thread-safe
// (PCL's verbosity is a global), like PCL's own I/O.
class QuietPcl {
 public:
  QuietPcl() : old_(pcl::console::getVerbosityLevel()) {
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  }
  ~QuietPcl() { pcl::console::setVerbosityLevel(old_); }

 private:
  pcl::console::VERBOSITY_LEVEL old_;
};

bool ReadScalar(const std::uint8_t* p, std::uint8_t datatype, double* out) {
  switch (datatype) {
#define TPCAL_FIELD(ENUM, TYPE)         \
  case pcl::PCLPointField::ENUM: {      \
    TYPE v;                             \
    std::memcpy(&v, p, sizeof(v));      \
    *out = static_cast<double>(v);      \
    return true;                        \
  }
    TPCAL_FIELD(INT8, std::int8_t)
    TPCAL_FIELD(UINT8, std::uint8_t)
    TPCAL_FIELD(INT16, std::int16_t)
    TPCAL_FIELD(UINT16, std::uint16_t)
    TPCAL_FIELD(INT32, std::int32_t)
    TPCAL_FIELD(UINT32, std::uint32_t)
    TPCAL_FIELD(INT64, std::int64_t)
    TPCAL_FIELD(UINT64, std::uint64_t)
    TPCAL_FIELD(FLOAT32, float)
    TPCAL_FIELD(FLOAT64, double)
#undef TPCAL_FIELD
    default:
      return false;
  }
}

const pcl::PCLPointField* FindField(const pcl::PCLPointCloud2& cloud, const char* name) {
  for (const auto& f : cloud.fields)
    if (f.name == name) return &f;
  return nullptr;
}

// Fields that are not per-point numbers: packed colours and PCD padding.
bool IsSkippedField(const std::string& name) {
  return name == "rgb" || name == "rgba" || name.empty() || name[0] == '_';
}

Result<PointFile> FromCloud(const pcl::PCLPointCloud2& cloud, const std::string& path,
                            PointFormat format, std::uint64_t bytes, const PointReadOptions& options,
                            const internal::CloudNotes& notes) {
  auto error = [&](std::string msg) { return Status(StatusCode::kParseError, std::move(msg), path); };
  const pcl::PCLPointField* fx = FindField(cloud, "x");
  const pcl::PCLPointField* fy = FindField(cloud, "y");
  const pcl::PCLPointField* fz = FindField(cloud, "z");
  if (!fx || !fy || !fz) return error("the cloud has no x, y and z fields");
  const pcl::PCLPointField* fn[3] = {FindField(cloud, "normal_x"), FindField(cloud, "normal_y"),
                                     FindField(cloud, "normal_z")};
  const bool has_normals = fn[0] && fn[1] && fn[2];
  std::vector<const pcl::PCLPointField*> attr_fields;
  for (const auto& f : cloud.fields) {
    if (f.name == "x" || f.name == "y" || f.name == "z") continue;
    if (has_normals && (f.name == "normal_x" || f.name == "normal_y" || f.name == "normal_z")) continue;
    if (IsSkippedField(f.name) || f.count != 1) continue;
    if (f.datatype < pcl::PCLPointField::INT8 || f.datatype > pcl::PCLPointField::UINT64) continue;
    attr_fields.push_back(&f);
  }
  const std::size_t n = static_cast<std::size_t>(cloud.width) * cloud.height;
  if (n == 0) return error("no points in the cloud");
  if (static_cast<std::size_t>(cloud.row_step) * cloud.height > cloud.data.size() ||
      static_cast<std::size_t>(cloud.point_step) * cloud.width > cloud.row_step)
    return error("inconsistent cloud layout (data shorter than width x height points)");

  const double scale = options.assumed_units == LengthUnit::kInch ? kMmPerInch : 1.0;
  PointFile file;
  file.info.format = format;
  file.info.source_units = options.assumed_units;
  file.info.bytes = bytes;
  PointSet& ps = file.points;
  ps.source = path;
  ps.xyz_mm.reserve(n);
  if (has_normals) ps.normal.reserve(n);
  for (const auto* f : attr_fields) {
    PointAttribute a;
    a.name = f->name;
    a.values.reserve(n);
    ps.attributes.push_back(std::move(a));
  }
  for (std::size_t r = 0; r < cloud.height; ++r) {
    for (std::size_t c = 0; c < cloud.width; ++c) {
      const std::size_t index = r * cloud.width + c;
      const std::uint8_t* pt = cloud.data.data() + r * cloud.row_step + c * cloud.point_step;
      double v[3];
      const pcl::PCLPointField* fxyz[3] = {fx, fy, fz};
      for (int k = 0; k < 3; ++k)
        if (!ReadScalar(pt + fxyz[k]->offset, fxyz[k]->datatype, &v[k]))
          return error(fmt::format("field '{}' has an unsupported data type", fxyz[k]->name));
      if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
        if (options.skip_nonfinite_points) continue;
        return error(fmt::format("point {} (0-based) has a NaN or infinite coordinate; expected "
                                 "finite x,y,z (set skip_nonfinite_points to drop such points)",
                                 index))
            .WithLocation(path, notes.first_nonfinite_xyz_line);  // its row, in ASCII data
      }
      if (std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])}) * scale > kCloudMaxAbsCoordinateMm)
        return error(fmt::format("point {} (0-based) is beyond {:g} mm from the origin; expected "
                                 "coordinates of a measured piece", index, kCloudMaxAbsCoordinateMm));
      if (has_normals) {
        Eigen::Vector3d nrm;
        for (int k = 0; k < 3; ++k)
          if (!ReadScalar(pt + fn[k]->offset, fn[k]->datatype, &nrm[k]))
            return error(fmt::format("field '{}' has an unsupported data type", fn[k]->name));
        const double len = nrm.norm();
        if (!std::isfinite(len) || len < kCloudZeroNormalLength)
          return error(fmt::format("point {} (0-based) has a normal of zero length or NaN; "
                                   "expected a unit vector", index));
        if (std::abs(len - 1.0) > options.normal_tolerance)
          return error(fmt::format("point {} (0-based) has a normal of length {:.6g}; expected a "
                                   "unit vector (within {:g})", index, len, options.normal_tolerance));
        if (std::abs(len - 1.0) > kCloudAlreadyUnit) nrm /= len;
        ps.normal.push_back(nrm);
      }
      ps.xyz_mm.emplace_back(v[0] * scale, v[1] * scale, v[2] * scale);
      for (std::size_t a = 0; a < attr_fields.size(); ++a) {
        double x = 0;
        ReadScalar(pt + attr_fields[a]->offset, attr_fields[a]->datatype, &x);
        ps.attributes[a].values.push_back(x);
      }
    }
  }
  if (ps.xyz_mm.empty()) return error("no points with finite coordinates in the cloud");
  ps.feature.assign(ps.xyz_mm.size(), PointSet::kUnlabelled);
  return file;
}

// PCL reads the file only after tpcal has checked all of it (cloud_file_check.h): PCL's readers
// trust header sizes and crash or allocate without bound on damaged files.
template <typename LoadFn>
Result<PointFile> LoadWithPcl(const std::string& path, PointFormat format,
                              const PointReadOptions& options, LoadFn load) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  std::uint64_t file_bytes = 0;
  internal::CloudNotes notes;
  {
    Result<FileBytes> bytes = ReadFileBytes(path);
    if (!bytes.ok()) return bytes.status();
    file_bytes = bytes->size;
    TPCAL_RETURN_IF_ERROR(format == PointFormat::kPly ? internal::CheckPlyBytes(bytes->view(), path, &notes)
                                                      : internal::CheckPcdBytes(bytes->view(), path, &notes));
  }
  pcl::PCLPointCloud2 cloud;
  int rc = -1;
  try {
    QuietPcl quiet;
    rc = load(path, cloud);
  } catch (const std::exception& e) {
    return Status(StatusCode::kParseError,
                  fmt::format("PCL could not read the {} file: {}", PointFormatName(format), e.what()),
                  path);
  }
  if (rc < 0)
    return Status(StatusCode::kParseError,
                  fmt::format("PCL could not read the file as {} (damaged or not a {} file)",
                              PointFormatName(format), PointFormatName(format)),
                  path);
  return FromCloud(cloud, path, format, file_bytes, options, notes);
}

// PCL's PLY writer declares fields named normal_x/y/z as `float nx/ny/nz` whatever their type
// (and then writes 8-byte doubles in binary mode: a corrupt file). Fields named nx/ny/nz are
// written as they are, and PCL's PLY reader maps them back to normal_x/y/z.
Result<pcl::PCLPointCloud2> ToCloud(const PointSet& ps, bool ply_normal_names) {
  const std::size_t n = ps.size();
  if (n == 0) return Status(StatusCode::kInvalidArgument, "no points to write");
  if (ps.has_normals() && ps.normal.size() != n)
    return Status(StatusCode::kInvalidArgument, fmt::format("{} normals for {} points", ps.normal.size(), n));
  std::vector<std::string> names = {"x", "y", "z"};
  if (ps.has_normals()) {
    if (ply_normal_names)
      names.insert(names.end(), {"nx", "ny", "nz"});
    else
      names.insert(names.end(), {"normal_x", "normal_y", "normal_z"});
  }
  std::vector<const PointAttribute*> attrs;
  for (const PointAttribute& a : ps.attributes) {
    if (!a.is_numeric()) continue;  // text attributes are not representable
    if (a.values.size() != n)
      return Status(StatusCode::kInvalidArgument,
                    fmt::format("attribute '{}' has {} values for {} points", a.name, a.values.size(), n));
    for (char ch : a.name)
      if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_'))
        return Status(StatusCode::kInvalidArgument,
                      fmt::format("attribute name '{}' is not a valid PLY/PCD field name", a.name));
    names.push_back(a.name);
    attrs.push_back(&a);
  }
  pcl::PCLPointCloud2 cloud;
  for (std::size_t f = 0; f < names.size(); ++f) {
    pcl::PCLPointField field;
    field.name = names[f];
    field.offset = static_cast<std::uint32_t>(8 * f);
    field.datatype = pcl::PCLPointField::FLOAT64;
    field.count = 1;
    cloud.fields.push_back(field);
  }
  cloud.height = 1;
  cloud.width = static_cast<std::uint32_t>(n);
  cloud.is_bigendian = false;
  cloud.point_step = static_cast<std::uint32_t>(8 * names.size());
  cloud.row_step = cloud.point_step * cloud.width;
  cloud.is_dense = true;
  cloud.data.resize(static_cast<std::size_t>(cloud.row_step));
  for (std::size_t i = 0; i < n; ++i) {
    double* row = reinterpret_cast<double*>(cloud.data.data() + i * cloud.point_step);
    std::size_t k = 0;
    for (int c = 0; c < 3; ++c) row[k++] = ps.xyz_mm[i][c];
    if (ps.has_normals())
      for (int c = 0; c < 3; ++c) row[k++] = ps.normal[i][c];
    for (const PointAttribute* a : attrs) row[k++] = a->values[i];
  }
  return cloud;
}

template <typename SaveFn>
Status SaveWithPcl(const std::string& path, const PointSet& ps, const PointWriteOptions& options,
                   PointFormat format, SaveFn save) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  Result<pcl::PCLPointCloud2> cloud = ToCloud(ps, format == PointFormat::kPly);
  if (!cloud.ok()) return cloud.status().WithLocation(path);
  return WriteFileAtomicVia(path, [&](const std::string& temp) -> Status {
    int rc = -1;
    try {
      QuietPcl quiet;
      rc = save(temp, *cloud);
    } catch (const std::exception& e) {
      return Status(StatusCode::kIoError,
                    fmt::format("PCL could not write the {} file: {}", PointFormatName(format), e.what()),
                    path);
    }
    if (rc < 0)
      return Status(StatusCode::kIoError,
                    fmt::format("PCL could not write the {} file", PointFormatName(format)), path);
    return Status::Ok();
  });
}

// ASCII PLY, written here: PCL 1.13's PLYWriter::writeASCII prints float64 fields with 6
// significant digits whatever precision it is given (0.6666666666 -> 0.666667), which would
// silently round coordinates to about 0.1 um. Same fields and names as the binary path.
Status WriteAsciiPly(const std::string& path, const pcl::PCLPointCloud2& cloud) {
  return WriteFileAtomic(path, [&](AtomicFileWriter& w) -> Status {
    std::string out = fmt::format("ply\nformat ascii 1.0\ncomment written by tpcal\nelement vertex {}\n",
                                  cloud.width);
    for (const auto& f : cloud.fields) out += fmt::format("property double {}\n", f.name);
    out += "end_header\n";
    const std::size_t nf = cloud.fields.size();
    char buf[64];
    for (std::size_t i = 0; i < cloud.width; ++i) {
      const std::uint8_t* row = cloud.data.data() + i * cloud.point_step;
      for (std::size_t f = 0; f < nf; ++f) {
        double v;
        std::memcpy(&v, row + 8 * f, 8);
        const auto r = std::to_chars(buf, buf + sizeof(buf), v);
        out.append(buf, r.ptr);
        out.push_back(f + 1 < nf ? ' ' : '\n');
      }
      if (out.size() > (1u << 20)) {
        TPCAL_RETURN_IF_ERROR(w.Write(out));
        out.clear();
      }
    }
    return w.Write(out);
  });
}

}  // namespace

Result<PointFile> ParsePointXyz(std::string_view text, const std::string& source_name,
                                const PointReadOptions& options) {
  // xyz text may carry `# units:`; without it options.assumed_units applies.
  return internal::ParsePointText(text, source_name, internal::TextDialect::kXyz, options);
}

Result<PointFile> ReadPointXyz(const std::string& path, const PointReadOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  Result<FileBytes> bytes = ReadFileBytes(path, internal::kMaxLineBytes);
  if (!bytes.ok()) return bytes.status();
  return ParsePointXyz(bytes->view(), path, options);
}

Result<PointFile> ReadPointPly(const std::string& path, const PointReadOptions& options) {
  return LoadWithPcl(path, PointFormat::kPly, options,
                     [](const std::string& p, pcl::PCLPointCloud2& c) { return pcl::io::loadPLYFile(p, c); });
}

Result<PointFile> ReadPointPcd(const std::string& path, const PointReadOptions& options) {
  return LoadWithPcl(path, PointFormat::kPcd, options,
                     [](const std::string& p, pcl::PCLPointCloud2& c) { return pcl::io::loadPCDFile(p, c); });
}

Status WritePointPly(const std::string& path, const PointSet& points, const PointWriteOptions& options) {
  if (!options.binary) {
    TPCAL_RETURN_IF_ERROR(options.Validate());
    Result<pcl::PCLPointCloud2> cloud = ToCloud(points, /*ply_normal_names=*/true);
    if (!cloud.ok()) return cloud.status().WithLocation(path);
    return WriteAsciiPly(path, *cloud);
  }
  return SaveWithPcl(path, points, options, PointFormat::kPly,
                     [](const std::string& p, const pcl::PCLPointCloud2& c) {
                       pcl::PLYWriter writer;
                       return writer.writeBinary(p, c, Eigen::Vector4f::Zero(),
                                                 Eigen::Quaternionf::Identity(), false);
                     });
}

Status WritePointPcd(const std::string& path, const PointSet& points, const PointWriteOptions& options) {
  const bool binary = options.binary;
  return SaveWithPcl(path, points, options, PointFormat::kPcd,
                     [binary](const std::string& p, const pcl::PCLPointCloud2& c) {
                       pcl::PCDWriter writer;
                       if (binary) return writer.writeBinary(p, c);
                       return writer.writeASCII(p, c, Eigen::Vector4f::Zero(),
                                                Eigen::Quaternionf::Identity(), 17);
                     });
}

}  // namespace tpcal::pipeline
