// Binary cache of parsed point files (point_io.h, "binary cache").
//
// File layout (native little-endian):
//   header  : "TPCALPC\n" | u32 layout version | u32 0x01020304 (endianness check)
//   payload : key  = str abs_path | u64 size | i64 mtime_ns | u64 xxh64(all bytes)
//                    | u64 xxh64(first+last 64 KiB) | u64 options digest
//             info = u8 format | u8 kind | u8 source units | u64 source bytes
//             u64 n | u8 has_normals | u8 has_lines
//             n x 3 f64 xyz_mm | [n x 3 f64 normal] | n x i32 feature | [n x u64 line]
//             u64 n_names, str each | u64 n_attributes, each: str name | u8 numeric
//                 | numeric: n f64 ; text: n str
//   trailer : u64 XXH64 of the payload
//   (str = u32 length + bytes)
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>
#include <thread>

#include "pipeline/atomic_file.h"
#include "pipeline/file_bytes.h"
#include "pipeline/large_alloc.h"
#include "pipeline/point_io.h"
#include "pipeline/xxh64.h"

namespace tpcal::pipeline {
namespace {

constexpr char kMagic[8] = {'T', 'P', 'C', 'A', 'L', 'P', 'C', '\n'};
// Bump when the layout or the parser's results change, so old caches become stale.
constexpr std::uint32_t kLayoutVersion = 1;
constexpr std::uint32_t kEndianMark = 0x01020304;
constexpr std::size_t kHeaderBytes = 16;
constexpr std::size_t kEndBlockBytes = 64 * 1024;
constexpr std::size_t kHashBlockBytes = 1 << 20;

struct SourceKey {
  std::string abs_path;
  std::uint64_t size = 0;
  std::int64_t mtime_ns = 0;
  std::uint64_t hash_full = 0;
  std::uint64_t hash_ends = 0;
  std::uint64_t options_digest = 0;
};

std::string AbsolutePath(const std::string& path) {
  std::error_code ec;
  std::filesystem::path p = std::filesystem::weakly_canonical(std::filesystem::absolute(path, ec), ec);
  return ec ? path : p.string();
}

PointFormat ResolvedFormat(const std::string& path, const PointReadOptions& options) {
  return options.format == PointFormat::kAuto ? PointFormatFromExtension(path) : options.format;
}

// Digest of the options that change the parsed result (not threads or chunk sizes).
std::uint64_t OptionsDigest(const std::string& path, const PointReadOptions& options) {
  Xxh64State h(kLayoutVersion);
  const std::uint32_t fields[4] = {static_cast<std::uint32_t>(ResolvedFormat(path, options)),
                                   static_cast<std::uint32_t>(options.assumed_units),
                                   static_cast<std::uint32_t>(options.skip_nonfinite_points), 0};
  h.Update(fields, sizeof(fields));
  h.Update(&options.normal_tolerance, sizeof(double));
  return h.Digest();
}

std::uint64_t HashEnds(std::string_view bytes) {
  Xxh64State h;
  const std::size_t head = std::min(bytes.size(), kEndBlockBytes);
  h.Update(bytes.substr(0, head));
  const std::size_t tail = std::min(bytes.size() - head, kEndBlockBytes);
  h.Update(bytes.substr(bytes.size() - tail));
  return h.Digest();
}

// Hashes a file without holding it in memory: XXH64 of all bytes, or of the end blocks.
Result<std::uint64_t> HashFile(const std::string& path, CacheVerify verify, std::uint64_t size) {
  int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return Status(StatusCode::kIoError, "cannot open for hashing", path);
  auto pread_all = [&](char* dst, std::size_t n, std::uint64_t off) -> bool {
    while (n > 0) {
      ssize_t r = ::pread(fd, dst, n, static_cast<off_t>(off));
      if (r < 0 && errno == EINTR) continue;
      if (r <= 0) return false;
      dst += r;
      n -= static_cast<std::size_t>(r);
      off += static_cast<std::uint64_t>(r);
    }
    return true;
  };
  Xxh64State h;
  bool ok = true;
  if (verify == CacheVerify::kFull) {
    std::unique_ptr<char[]> buf = std::make_unique_for_overwrite<char[]>(kHashBlockBytes);
    for (std::uint64_t off = 0; off < size && ok; off += kHashBlockBytes) {
      const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(kHashBlockBytes, size - off));
      ok = pread_all(buf.get(), n, off);
      if (ok) h.Update(buf.get(), n);
    }
  } else {
    std::unique_ptr<char[]> buf = std::make_unique_for_overwrite<char[]>(kEndBlockBytes);
    const std::size_t head = static_cast<std::size_t>(std::min<std::uint64_t>(size, kEndBlockBytes));
    ok = pread_all(buf.get(), head, 0);
    if (ok) h.Update(buf.get(), head);
    const std::size_t tail = static_cast<std::size_t>(std::min<std::uint64_t>(size - head, kEndBlockBytes));
    if (ok) ok = pread_all(buf.get(), tail, size - tail);
    if (ok) h.Update(buf.get(), tail);
  }
  ::close(fd);
  if (!ok) return Status(StatusCode::kIoError, "read failed while hashing", path);
  return h.Digest();
}

// ---- serialisation ----------------------------------------------------------------------

class Writer {
 public:
  explicit Writer(AtomicFileWriter* w) : w_(w) {}
  Status Put(const void* data, std::size_t n) {
    hash_.Update(data, n);
    return w_->Write(std::string_view(static_cast<const char*>(data), n));
  }
  template <typename T>
  Status PutPod(T v) { return Put(&v, sizeof(T)); }
  Status PutStr(std::string_view s) {
    TPCAL_RETURN_IF_ERROR(PutPod(static_cast<std::uint32_t>(s.size())));
    return Put(s.data(), s.size());
  }
  template <typename T>
  Status PutArray(const std::vector<T>& v) { return Put(v.data(), v.size() * sizeof(T)); }
  std::uint64_t Digest() const { return hash_.Digest(); }

 private:
  AtomicFileWriter* w_;
  Xxh64State hash_;
};

// Reads the payload straight from the file into its destination (no intermediate copy of the
// whole file), hashing every byte on the way. Small reads go through a 64 KiB buffer.
class Reader {
 public:
  Reader(int fd, std::uint64_t payload_bytes) : fd_(fd), remaining_(payload_bytes) {}

  bool Get(void* dst, std::size_t n) {
    if (n > remaining_) return false;
    char* out = static_cast<char*>(dst);
    const std::size_t from_buf = std::min(n, buf_end_ - buf_pos_);
    std::memcpy(out, buf_.get() + buf_pos_, from_buf);
    buf_pos_ += from_buf;
    std::size_t left = n - from_buf;
    if (left >= kBufBytes) {
      if (!ReadFully(out + from_buf, left)) return false;
    } else if (left > 0) {
      if (!Refill() || buf_end_ - buf_pos_ < left) return false;
      std::memcpy(out + from_buf, buf_.get() + buf_pos_, left);
      buf_pos_ += left;
    }
    hash_.Update(out, n);
    remaining_ -= n;
    return true;
  }
  template <typename T>
  bool GetPod(T* v) { return Get(v, sizeof(T)); }
  bool GetStr(std::string* s) {
    std::uint32_t n;
    if (!GetPod(&n) || n > remaining_) return false;
    s->resize(n);
    return Get(s->data(), n);
  }
  template <typename T>
  bool GetArray(std::vector<T>* v, std::uint64_t n) {
    if (n > remaining_ / sizeof(T)) return false;
    ReserveLarge(v, static_cast<std::size_t>(n));
    v->resize(static_cast<std::size_t>(n));
    return Get(v->data(), static_cast<std::size_t>(n) * sizeof(T));
  }
  // After the payload: the stored digest must match and the file must end.
  bool CheckTrailer() {
    if (remaining_ != 0) return false;
    std::uint64_t stored = 0;
    remaining_ = 8;
    const Xxh64State payload_hash = hash_;
    if (!Get(&stored, 8)) return false;
    char extra;
    if (buf_pos_ != buf_end_ || ::read(fd_, &extra, 1) != 0) return false;
    return stored == payload_hash.Digest();
  }

 private:
  static constexpr std::size_t kBufBytes = 64 * 1024;

  bool ReadFully(char* dst, std::size_t n) {
    while (n > 0) {
      ssize_t r = ::read(fd_, dst, n);
      if (r < 0 && errno == EINTR) continue;
      if (r <= 0) return false;
      dst += r;
      n -= static_cast<std::size_t>(r);
    }
    return true;
  }
  bool Refill() {
    const std::size_t keep = buf_end_ - buf_pos_;
    std::memmove(buf_.get(), buf_.get() + buf_pos_, keep);
    buf_pos_ = 0;
    buf_end_ = keep;
    while (true) {
      ssize_t r = ::read(fd_, buf_.get() + buf_end_, kBufBytes - buf_end_);
      if (r < 0 && errno == EINTR) continue;
      if (r < 0) return false;
      buf_end_ += static_cast<std::size_t>(r);
      return true;
    }
  }

  int fd_;
  std::uint64_t remaining_;
  std::unique_ptr<char[]> buf_ = std::make_unique_for_overwrite<char[]>(kBufBytes);
  std::size_t buf_pos_ = 0, buf_end_ = 0;
  Xxh64State hash_;
};

Status WriteCache(const std::string& cache_path, const SourceKey& key, const PointFile& file) {
  const PointSet& ps = file.points;
  std::error_code ec;
  const auto dir = std::filesystem::path(cache_path).parent_path();
  if (!dir.empty()) std::filesystem::create_directories(dir, ec);
  return WriteFileAtomic(cache_path, [&](AtomicFileWriter& w) -> Status {
    TPCAL_RETURN_IF_ERROR(w.Write(std::string_view(kMagic, 8)));
    const std::uint32_t head[2] = {kLayoutVersion, kEndianMark};
    TPCAL_RETURN_IF_ERROR(w.Write(std::string_view(reinterpret_cast<const char*>(head), 8)));
    Writer out(&w);
    TPCAL_RETURN_IF_ERROR(out.PutStr(key.abs_path));
    TPCAL_RETURN_IF_ERROR(out.PutPod(key.size));
    TPCAL_RETURN_IF_ERROR(out.PutPod(key.mtime_ns));
    TPCAL_RETURN_IF_ERROR(out.PutPod(key.hash_full));
    TPCAL_RETURN_IF_ERROR(out.PutPod(key.hash_ends));
    TPCAL_RETURN_IF_ERROR(out.PutPod(key.options_digest));
    TPCAL_RETURN_IF_ERROR(out.PutPod(static_cast<std::uint8_t>(file.info.format)));
    TPCAL_RETURN_IF_ERROR(out.PutPod(static_cast<std::uint8_t>(file.info.kind)));
    TPCAL_RETURN_IF_ERROR(out.PutPod(static_cast<std::uint8_t>(file.info.source_units)));
    TPCAL_RETURN_IF_ERROR(out.PutPod(file.info.bytes));
    const std::uint64_t n = ps.size();
    TPCAL_RETURN_IF_ERROR(out.PutPod(n));
    TPCAL_RETURN_IF_ERROR(out.PutPod(static_cast<std::uint8_t>(ps.has_normals())));
    TPCAL_RETURN_IF_ERROR(out.PutPod(static_cast<std::uint8_t>(!ps.line.empty())));
    TPCAL_RETURN_IF_ERROR(out.PutArray(ps.xyz_mm));
    if (ps.has_normals()) TPCAL_RETURN_IF_ERROR(out.PutArray(ps.normal));
    static_assert(sizeof(int) == 4 && sizeof(std::size_t) == 8 && sizeof(Eigen::Vector3d) == 24);
    TPCAL_RETURN_IF_ERROR(out.PutArray(ps.feature));
    if (!ps.line.empty()) TPCAL_RETURN_IF_ERROR(out.PutArray(ps.line));
    TPCAL_RETURN_IF_ERROR(out.PutPod(static_cast<std::uint64_t>(ps.feature_names.size())));
    for (const std::string& name : ps.feature_names) TPCAL_RETURN_IF_ERROR(out.PutStr(name));
    TPCAL_RETURN_IF_ERROR(out.PutPod(static_cast<std::uint64_t>(ps.attributes.size())));
    for (const PointAttribute& a : ps.attributes) {
      TPCAL_RETURN_IF_ERROR(out.PutStr(a.name));
      TPCAL_RETURN_IF_ERROR(out.PutPod(static_cast<std::uint8_t>(a.is_numeric())));
      if (a.is_numeric()) {
        TPCAL_RETURN_IF_ERROR(out.PutArray(a.values));
      } else {
        for (const std::string& t : a.text) TPCAL_RETURN_IF_ERROR(out.PutStr(t));
      }
    }
    const std::uint64_t digest = out.Digest();
    return w.Write(std::string_view(reinterpret_cast<const char*>(&digest), 8));
  });
}

enum class LoadResult { kHit, kMissing, kStale, kCorrupt };

struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

// Loads the cache if it is intact and its key matches the source; fills `file` on a hit.
// With kFull the source is hashed on a second thread while the arrays load.
LoadResult LoadCache(const std::string& cache_path, const std::string& source_path,
                     const FileStamp& stamp, std::uint64_t options_digest, CacheVerify verify,
                     PointFile* file) {
  Fd f;
  f.fd = ::open(cache_path.c_str(), O_RDONLY | O_CLOEXEC);
  if (f.fd < 0) return errno == ENOENT ? LoadResult::kMissing : LoadResult::kCorrupt;
  struct stat st {};
  if (::fstat(f.fd, &st) != 0 || !S_ISREG(st.st_mode)) return LoadResult::kCorrupt;
  const std::uint64_t file_bytes = static_cast<std::uint64_t>(st.st_size);
  if (file_bytes < kHeaderBytes + 8) return LoadResult::kCorrupt;
  char header[kHeaderBytes];
  if (::read(f.fd, header, kHeaderBytes) != static_cast<ssize_t>(kHeaderBytes) ||
      std::memcmp(header, kMagic, 8) != 0)
    return LoadResult::kCorrupt;
  std::uint32_t head[2];
  std::memcpy(head, header + 8, 8);
  if (head[1] != kEndianMark) return LoadResult::kCorrupt;
  if (head[0] != kLayoutVersion) return LoadResult::kStale;

  Reader in(f.fd, file_bytes - kHeaderBytes - 8);
  SourceKey key;
  if (!in.GetStr(&key.abs_path) || !in.GetPod(&key.size) || !in.GetPod(&key.mtime_ns) ||
      !in.GetPod(&key.hash_full) || !in.GetPod(&key.hash_ends) || !in.GetPod(&key.options_digest))
    return LoadResult::kCorrupt;
  if (key.abs_path != AbsolutePath(source_path) || key.size != stamp.size ||
      key.mtime_ns != stamp.mtime_ns || key.options_digest != options_digest)
    return LoadResult::kStale;

  Result<std::uint64_t> content = Status(StatusCode::kInternal, "not hashed");
  std::thread hasher;
  if (verify == CacheVerify::kFull && std::thread::hardware_concurrency() > 1)
    hasher = std::thread([&] { content = HashFile(source_path, verify, stamp.size); });
  else
    content = HashFile(source_path, verify, stamp.size);
  struct Join {
    std::thread& t;
    ~Join() {
      if (t.joinable()) t.join();
    }
  } join{hasher};

  PointFile out;
  std::uint8_t format, kind, units, has_normals, has_lines;
  std::uint64_t n;
  if (!in.GetPod(&format) || !in.GetPod(&kind) || !in.GetPod(&units) || !in.GetPod(&out.info.bytes) ||
      !in.GetPod(&n) || !in.GetPod(&has_normals) || !in.GetPod(&has_lines))
    return LoadResult::kCorrupt;
  if (format > static_cast<std::uint8_t>(PointFormat::kXyz) ||
      kind > static_cast<std::uint8_t>(PointFileKind::kPlan) ||
      units > static_cast<std::uint8_t>(LengthUnit::kInch))
    return LoadResult::kCorrupt;
  out.info.format = static_cast<PointFormat>(format);
  out.info.kind = static_cast<PointFileKind>(kind);
  out.info.source_units = static_cast<LengthUnit>(units);
  out.info.chunks = 0;  // nothing parsed
  PointSet& ps = out.points;
  if (!in.GetArray(&ps.xyz_mm, n)) return LoadResult::kCorrupt;
  if (has_normals && !in.GetArray(&ps.normal, n)) return LoadResult::kCorrupt;
  if (!in.GetArray(&ps.feature, n)) return LoadResult::kCorrupt;
  if (has_lines && !in.GetArray(&ps.line, n)) return LoadResult::kCorrupt;
  std::uint64_t n_names, n_attr;
  if (!in.GetPod(&n_names) || n_names > file_bytes) return LoadResult::kCorrupt;
  ps.feature_names.resize(static_cast<std::size_t>(n_names));
  for (auto& name : ps.feature_names)
    if (!in.GetStr(&name)) return LoadResult::kCorrupt;
  if (!in.GetPod(&n_attr) || n_attr > file_bytes) return LoadResult::kCorrupt;
  ps.attributes.resize(static_cast<std::size_t>(n_attr));
  for (PointAttribute& a : ps.attributes) {
    std::uint8_t numeric;
    if (!in.GetStr(&a.name) || !in.GetPod(&numeric)) return LoadResult::kCorrupt;
    if (numeric) {
      if (!in.GetArray(&a.values, n)) return LoadResult::kCorrupt;
    } else {
      if (n > file_bytes / 4) return LoadResult::kCorrupt;
      a.text.resize(static_cast<std::size_t>(n));
      for (auto& t : a.text)
        if (!in.GetStr(&t)) return LoadResult::kCorrupt;
    }
  }
  if (!in.CheckTrailer()) return LoadResult::kCorrupt;
  for (int fi : ps.feature)
    if (fi != PointSet::kUnlabelled && (fi < 0 || static_cast<std::uint64_t>(fi) >= n_names))
      return LoadResult::kCorrupt;
  if (hasher.joinable()) hasher.join();
  if (!content.ok() || *content != (verify == CacheVerify::kFull ? key.hash_full : key.hash_ends))
    return LoadResult::kStale;
  ps.source = source_path;
  *file = std::move(out);
  return LoadResult::kHit;
}

}  // namespace

std::string PointCachePath(const std::string& source_path, const PointCacheOptions& cache) {
  if (cache.cache_dir.empty()) return source_path + ".tpcache";
  const std::string abs = AbsolutePath(source_path);
  return (std::filesystem::path(cache.cache_dir) /
          fmt::format("{}.{:016x}.tpcache", std::filesystem::path(source_path).filename().string(),
                      Xxh64(abs)))
      .string();
}

Result<PointFile> ReadPointFileCached(const std::string& path, const PointReadOptions& options,
                                      const PointCacheOptions& cache) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  Result<FileStamp> stamp = StatFile(path);
  if (!stamp.ok()) return stamp.status();
  const std::string cache_path = PointCachePath(path, cache);
  const std::uint64_t digest = OptionsDigest(path, options);

  PointFile hit;
  const LoadResult loaded = LoadCache(cache_path, path, *stamp, digest, cache.verify, &hit);
  if (loaded == LoadResult::kHit) {
    hit.info.cache = CacheOutcome::kHit;
    return hit;
  }

  // Miss: parse. Text formats are hashed from the very bytes that are parsed; PLY/PCD are read
  // by PCL, so they are hashed separately and the cache is written only if the file did not
  // change in between.
  SourceKey key;
  key.abs_path = AbsolutePath(path);
  key.options_digest = digest;
  Result<PointFile> parsed = Status(StatusCode::kInternal, "not parsed");
  const PointFormat format = ResolvedFormat(path, options);
  bool key_valid = true;
  if (format == PointFormat::kCsv || format == PointFormat::kXyz) {
    Result<FileBytes> bytes = ReadFileBytes(path);
    if (!bytes.ok()) return bytes.status();
    key.hash_full = Xxh64(bytes->view());
    key.hash_ends = HashEnds(bytes->view());
    key.size = bytes->size;
    parsed = format == PointFormat::kCsv ? ParsePointCsv(bytes->view(), path, options)
                                         : ParsePointXyz(bytes->view(), path, options);
    key_valid = key.size == stamp->size;
  } else {
    Result<std::uint64_t> full = HashFile(path, CacheVerify::kFull, stamp->size);
    Result<std::uint64_t> ends = HashFile(path, CacheVerify::kEnds, stamp->size);
    parsed = ReadPointFile(path, options);
    key_valid = full.ok() && ends.ok();
    if (key_valid) {
      key.hash_full = *full;
      key.hash_ends = *ends;
      key.size = stamp->size;
    }
  }
  if (!parsed.ok()) return parsed.status();
  Result<FileStamp> after = StatFile(path);
  key_valid = key_valid && after.ok() && after->size == stamp->size &&
              after->mtime_ns == stamp->mtime_ns;
  key.mtime_ns = stamp->mtime_ns;

  PointFile file = std::move(*parsed);
  file.info.cache = loaded == LoadResult::kMissing ? CacheOutcome::kMissing
                    : loaded == LoadResult::kStale ? CacheOutcome::kStale
                                                   : CacheOutcome::kCorrupt;
  if (cache.write) {
    if (key_valid) {
      file.info.cache_write = WriteCache(cache_path, key, file);
    } else {
      file.info.cache_write = Status(StatusCode::kIoError,
                                     "source changed while it was read; cache not written", path);
    }
  }
  return file;
}

}  // namespace tpcal::pipeline
