// Point-file parsing benchmark (a small driver, not Google Benchmark: it needs one generated
// file and prints ratios against a baseline measured in the same run).
//
// Generates a canonical `tpcal points v1` CSV (feature,x,y,z,i,j,k, ~10 significant digits)
// in a temp directory and reports, best of --repeat runs:
//   read      : one plain read of the file into memory (the baseline)
//   parse x1  : ParsePointCsv on the in-memory text, 1 thread
//   parse xN  : the same with all hardware threads
//   file x1/xN: ReadPointCsv (read + parse)
// Usage: parse_bench [--points N] [--repeat R] [--threads T] [--keep]
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <thread>

#include "pipeline/io/atomic_file.h"
#include "pipeline/io/file_bytes.h"
#include "pipeline/io/point_io.h"

namespace {

using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;
using namespace tpcal;
using namespace tpcal::pipeline;

std::string GenerateCanonicalCsv(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> coord(-200.0, 200.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const char* features[] = {"S_R", "B_R", "H1", "H2", "H3", "H4", "H5", "H6", "H7", "H8",
                            "S1", "S2", "S3", "S4", "S5", "S6", "B1", "B2", "B3", "B4"};
  std::string out = "# tpcal points v1\n# units: mm\nfeature,x,y,z,i,j,k\n";
  out.reserve(n * 80);
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Vector3d nv{gauss(rng), gauss(rng), gauss(rng)};
    nv.normalize();
    // Features come in runs of 500 points, as a CMM probes them.
    const double x = coord(rng), y = coord(rng), z = coord(rng);  // drawn in this order under every compiler
    fmt::format_to(std::back_inserter(out), "{},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g}\n",
                   features[(i / 500) % 20], x, y, z, nv.x(), nv.y(), nv.z());
  }
  return out;
}

double CpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

struct Timing {
  double wall_s = 1e300;  // best wall-clock time
  double cpu_s = 1e300;   // process CPU time of that best run (all threads)
};

template <typename Fn>
Timing Best(int repeat, Fn fn) {
  Timing best;
  for (int r = 0; r < repeat; ++r) {
    const double c0 = CpuSeconds();
    const auto t0 = Clock::now();
    fn();
    const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
    if (wall < best.wall_s) best = {wall, CpuSeconds() - c0};
  }
  return best;
}

[[noreturn]] void Die(const Status& s) {
  fmt::print(stderr, "parse_bench: {}\n", s.ToString());
  std::exit(1);
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t n_points = 2000000;
  int repeat = 5;
  int threads = 0;
  bool keep = false;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--points" && a + 1 < argc) n_points = std::strtoull(argv[++a], nullptr, 10);
    else if (arg == "--repeat" && a + 1 < argc) repeat = std::atoi(argv[++a]);
    else if (arg == "--threads" && a + 1 < argc) threads = std::atoi(argv[++a]);
    else if (arg == "--keep") keep = true;
    else {
      fmt::print(stderr, "usage: parse_bench [--points N] [--repeat R] [--threads T] [--keep]\n");
      return 2;
    }
  }
  const int hw = threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));

  const fs::path dir = fs::temp_directory_path() / fmt::format("tpcal_parse_bench_{}", ::getpid());
  fs::create_directories(dir);
  const std::string path = (dir / "canonical.csv").string();
  {
    const std::string text = GenerateCanonicalCsv(n_points, 1);
    if (Status s = WriteFileAtomic(path, text); !s.ok()) Die(s);
  }
  Result<FileBytes> bytes = ReadFileBytes(path);  // also warms the page cache
  if (!bytes.ok()) Die(bytes.status());
  const double mb = static_cast<double>(bytes->size) / 1e6;
  fmt::print("file: {} points, {:.1f} MB ({:.1f} bytes/row), {} hardware threads used for xN, best of {}\n",
             n_points, mb, static_cast<double>(bytes->size) / static_cast<double>(n_points), hw, repeat);

  const Timing t_read = Best(repeat, [&] {
    Result<FileBytes> b = ReadFileBytes(path);
    if (!b.ok()) Die(b.status());
  });

  PointReadOptions one;
  one.threads = 1;
  PointReadOptions all;
  all.threads = hw;
  std::size_t check = 0;
  auto parse = [&](const PointReadOptions& o) {
    Result<PointFile> r = ParsePointCsv(bytes->view(), path, o);
    if (!r.ok()) Die(r.status());
    check += r->points.size();
  };
  auto read_parse = [&](const PointReadOptions& o) {
    Result<PointFile> r = ReadPointCsv(path, o);
    if (!r.ok()) Die(r.status());
    check += r->points.size();
  };
  const Timing t_parse1 = Best(repeat, [&] { parse(one); });
  const Timing t_parseN = Best(repeat, [&] { parse(all); });
  const Timing t_file1 = Best(repeat, [&] { read_parse(one); });
  const Timing t_fileN = Best(repeat, [&] { read_parse(all); });

  auto row = [&](const std::string& name, const Timing& t) {
    fmt::print("  {:<34} {:8.1f} ms {:7.0f} MB/s {:6.2f} x read | cpu {:8.1f} ms {:7.0f} MB/cpu-s\n", name,
               t.wall_s * 1e3, mb / t.wall_s, t.wall_s / t_read.wall_s, t.cpu_s * 1e3, mb / t.cpu_s);
  };
  fmt::print("results (MB of CSV text per second; 'x read' = wall time / plain-read wall time; cpu = process "
             "CPU time, all threads, robust when the machine is shared):\n");
  row("read file into memory (baseline)", t_read);
  row("parse in memory, 1 thread", t_parse1);
  row(fmt::format("parse in memory, {} threads", hw), t_parseN);
  row("read + parse, 1 thread", t_file1);
  row(fmt::format("read + parse, {} threads", hw), t_fileN);
  fmt::print("ratios: parse speed-up x{} / x1 {:.2f} (wall)\n", hw, t_parse1.wall_s / t_parseN.wall_s);
  fmt::print("load average at the end: {}", [] {
    std::string la;
    if (FILE* f = std::fopen("/proc/loadavg", "r")) {
      char buf[128] = {};
      if (std::fgets(buf, sizeof(buf), f)) la = buf;
      std::fclose(f);
    }
    return la.empty() ? std::string("unknown\n") : la;
  }());
  fmt::print("(checksum {} points)\n", check);
  if (!keep) fs::remove_all(dir);
  return 0;
}
