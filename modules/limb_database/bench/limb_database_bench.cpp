// Limb database timings: build of the shipped configuration (50,000 samples per leg), load from
// the cache, foothold candidate queries. Run with --report_memory to print the resident memory of
// a process that has just loaded the four legs from the cache (and nothing else).
//
// The cache of the benchmarks lives in <system temp>/rbcp_limb_database_bench.

#include <benchmark/benchmark.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include "rbcp/limb_database/limb_database.h"
#include "rbcp/robot/robot_model.h"

namespace rbcp {
namespace {

std::string ConfigDir() { return std::string(RBCP_SOURCE_DIR) + "/config"; }

const RobotModel& Model() {
  static const RobotModel model = RobotModel::LoadDefault(ConfigDir());
  return model;
}

LimbDatabaseConfig Config() {
  LimbDatabaseConfig c = LimbDatabaseConfig::LoadFile(ConfigDir() + "/limb_database.yaml");
  c.cache_dir = (std::filesystem::temp_directory_path() / "rbcp_limb_database_bench").string();
  return c;
}

/// The shipped database, from the benchmark cache (built and written on first use).
const LimbDatabase& CachedDatabase() {
  static const LimbDatabase db = LimbDatabase::LoadOrBuild(Model(), LimbDatabase::DefaultRobotFiles(ConfigDir()), Config());
  return db;
}

/// VmRSS or VmHWM of this process [MB], from /proc/self/status.
double ProcStatusMb(const char* field) {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(field, 0) == 0) return std::stod(line.substr(std::strlen(field) + 1)) / 1024.0;
  }
  return -1.0;
}

ConvexSurface Square(const Eigen::Vector3d& centre, double half, const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity()) {
  ConvexSurface s;
  for (const auto& c : {Eigen::Vector3d(-half, -half, 0), Eigen::Vector3d(half, -half, 0),
                        Eigen::Vector3d(half, half, 0), Eigen::Vector3d(-half, half, 0)}) {
    s.vertices.push_back(centre + R * c);
  }
  s.normal = R.col(2);
  return s;
}

Eigen::Isometry3d StandingBase() {
  return Eigen::Translation3d(2.0, 1.0, Model().NominalBaseHeight()) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ());
}

void BM_Build(benchmark::State& state) {
  const LimbDatabaseConfig config = Config();
  for (auto _ : state) {
    LimbDatabase db = LimbDatabase::Build(Model(), config);
    benchmark::DoNotOptimize(db);
  }
  state.counters["samples_per_leg"] = config.samples_per_leg;
}
BENCHMARK(BM_Build)->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(5)->ReportAggregatesOnly(true);

void BM_LoadCached(benchmark::State& state) {
  CachedDatabase();  // makes sure the cache file exists
  const LimbDatabaseConfig config = Config();
  const std::vector<std::string> files = LimbDatabase::DefaultRobotFiles(ConfigDir());
  std::size_t bytes = 0;
  for (auto _ : state) {
    LimbDatabaseCacheReport report;
    LimbDatabase db = LimbDatabase::LoadOrBuild(Model(), files, config, &report);
    if (!report.loaded) {
      state.SkipWithError(("cache not used: " + report.rebuild_reason).c_str());
      return;
    }
    bytes = db.MemoryBytes();
    benchmark::DoNotOptimize(db);
  }
  state.counters["db_MB"] = static_cast<double>(bytes) / (1024.0 * 1024.0);
}
BENCHMARK(BM_LoadCached)->Unit(benchmark::kMillisecond)->Iterations(3)->Repetitions(5)->ReportAggregatesOnly(true);

/// Flat ground much larger than the leg's reach, base at the nominal height.
void BM_QueryFlatGround(benchmark::State& state) {
  const LimbDatabase& db = CachedDatabase();
  const Eigen::Isometry3d base = StandingBase();
  const ConvexSurface ground = Square(Eigen::Vector3d(base.translation().x(), base.translation().y(), 0.0), 5.0);
  const double max_distance = 0.5 * db.Resolution();
  std::size_t n = 0;
  for (auto _ : state) {
    const auto candidates = db.Candidates(Leg::kLF, base, ground, max_distance);
    n = candidates.size();
    benchmark::DoNotOptimize(candidates.data());
  }
  state.counters["candidates"] = static_cast<double>(n);
}
BENCHMARK(BM_QueryFlatGround)->Unit(benchmark::kMicrosecond)->Repetitions(5)->ReportAggregatesOnly(true);

/// A 30 cm stepping stone tilted by 10 degrees under the hip.
void BM_QueryStone(benchmark::State& state) {
  const LimbDatabase& db = CachedDatabase();
  const Eigen::Isometry3d base = StandingBase();
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(10.0 * M_PI / 180.0, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  const ConvexSurface stone = Square(base * Model().ReferenceFootPosition(Leg::kRH), 0.15, tilt);
  const double max_distance = 0.5 * db.Resolution();
  std::size_t n = 0;
  for (auto _ : state) {
    const auto candidates = db.Candidates(Leg::kRH, base, stone, max_distance);
    n = candidates.size();
    benchmark::DoNotOptimize(candidates.data());
  }
  state.counters["candidates"] = static_cast<double>(n);
}
BENCHMARK(BM_QueryStone)->Unit(benchmark::kMicrosecond)->Repetitions(5)->ReportAggregatesOnly(true);

/// A surface out of reach: the cost of finding nothing.
void BM_QueryOutOfReach(benchmark::State& state) {
  const LimbDatabase& db = CachedDatabase();
  const Eigen::Isometry3d base = StandingBase();
  const ConvexSurface far = Square(base.translation() + Eigen::Vector3d(3.0, 0.0, -0.45), 0.5);
  for (auto _ : state) {
    const auto candidates = db.Candidates(Leg::kLF, base, far, 0.005);
    benchmark::DoNotOptimize(candidates.data());
  }
}
BENCHMARK(BM_QueryOutOfReach)->Unit(benchmark::kMicrosecond)->Repetitions(5)->ReportAggregatesOnly(true);

int ReportMemory() {
  const double before = ProcStatusMb("VmRSS:");
  LimbDatabaseCacheReport report;
  const LimbDatabase db =
      LimbDatabase::LoadOrBuild(Model(), LimbDatabase::DefaultRobotFiles(ConfigDir()), Config(), &report);
  const double after = ProcStatusMb("VmRSS:");
  std::cout << "cache: " << report.cache_path << (report.loaded ? " (loaded)" : " (built: " + report.rebuild_reason + ")")
            << "\nsamples per leg: " << db.NumSamples(Leg::kLF) << ", cells LF/RF/LH/RH: " << db.NumCells(Leg::kLF)
            << "/" << db.NumCells(Leg::kRF) << "/" << db.NumCells(Leg::kLH) << "/" << db.NumCells(Leg::kRH)
            << "\nheap held by the database: " << static_cast<double>(db.MemoryBytes()) / (1024.0 * 1024.0) << " MB"
            << "\nresident before load: " << before << " MB, after: " << after << " MB (delta " << after - before
            << " MB), peak: " << ProcStatusMb("VmHWM:") << " MB\n";
  return report.loaded ? 0 : 1;
}

}  // namespace
}  // namespace rbcp

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--report_memory") return rbcp::ReportMemory();
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
