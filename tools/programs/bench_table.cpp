// bench_table: the paper's Table 1 from runs of the replanning loop (tools/bench table). Each run
// is a folder with meta.json ({"scenario", "seed", "exit", "wall_s", "stopped_after_s"}: written by
// tools/bench; the last is null unless the bench stopped a run that went on too long) and,
// when the run left a log, run.json (run_log's JSON of it). Per scenario: the mean affordance
// extraction, root planning and contact planning times, the steps walked, the success over the
// runs, the mean simulated time to the goal and the replanning latency (median and 95th
// percentile over every replan of every run), as markdown beside the paper's figures, and as JSON.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rbcp/core/error.h"
#include "rbcp/core/format.h"
#include "rbcp/core/run_metrics.h"
#include "rbcp/cli/cli.h"
#include "rbcp/nodes/run_record.h"

namespace {

using namespace rbcp;
namespace fs = std::filesystem;

/// Table 1 of Geisert et al. (TAROS 2019), ANYmal: mean computation times over 20 runs per
/// environment, and success in dynamic simulation (Gazebo, Free Gait controller).
struct PaperRow {
  const char* scenario;
  const char* environment;
  double affordance_ms;
  double root_s;
  double contact_s;
  double steps;
  int successes;
  int runs;
};
constexpr PaperRow kPaper[] = {
    {"flat_ground", "Flat ground (5 m)", 1.36, 0.54, 3.30, 62.2, 20, 20},
    {"slalom_debris", "Slalom debris", 8.85, 0.82, 5.48, 79.1, 18, 20},
    {"plinth", "Plinth", 2.27, 1.26, 4.26, 59.8, 12, 20},
    {"darpa_rubble", "DARPA", 25.4, 2.18, 8.94, 29.9, 7, 20},
};

/// The paper's row of a scenario: of its box re-creation (darpa_rubble) or of its own mesh
/// (paper_darpa, the paper's environments under our names).
const PaperRow* PaperFor(const std::string& scenario) {
  static const std::pair<const char*, const char*> kMeshes[] = {{"paper_flat_ground", "flat_ground"},
                                                                {"paper_slalom_debris", "slalom_debris"},
                                                                {"paper_plinth", "plinth"},
                                                                {"paper_darpa", "darpa_rubble"}};
  std::string name = scenario;
  for (const auto& [mesh, box] : kMeshes) {
    if (name == mesh) name = box;
  }
  for (const PaperRow& row : kPaper) {
    if (name == row.scenario) return &row;
  }
  return nullptr;
}

nlohmann::json ReadJson(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot read " + path.string());
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path.string() + ": not JSON: " + e.what());
  }
}

/// The mean, or null when there is nothing to average.
nlohmann::json Mean(const std::vector<double>& v) {
  if (v.empty()) return nullptr;
  double sum = 0.0;
  for (double x : v) sum += x;
  return sum / static_cast<double>(v.size());
}

/// A number of a run_log document at a JSON pointer, or `fallback` when it is not there.
double Number(const nlohmann::json& j, const std::string& pointer, double fallback = 0.0) {
  const nlohmann::json::json_pointer p(pointer);
  return j.contains(p) && j.at(p).is_number() ? j.at(p).get<double>() : fallback;
}

struct Run {
  int seed = 0;
  int exit = 0;
  double wall_s = 0.0;
  std::optional<double> stopped_after_s;  ///< the bench stopped the run after this much wall time
  bool logged = false;  ///< run.json was there
  nlohmann::json log;
};

struct Row {
  std::string scenario;
  std::vector<Run> runs;
};

/// One scenario's figures, as the JSON document and the markdown read them.
nlohmann::json Summarise(const Row& row) {
  std::vector<double> affordance_ms, root_s, contact_total_s, contact_plan_ms, steps, goal_s, wall_s, latencies;
  std::vector<double> step_period_s, speed_mps;
  std::vector<double> map_rms_m, map_p95_m, coverage, map_latency_ms;  // runs planning on a mapped terrain
  int successes = 0;
  nlohmann::json per_run = nlohmann::json::array();
  for (const Run& r : row.runs) {
    wall_s.push_back(r.wall_s);
    // tools/launch exits 0 when the operator (scenario_publisher) received the simulator's verdict
    // "goal reached". The log holds the same verdict, unless the logger missed that one message
    // (UDP, under load): then verdict_in_log is false and the run still counts.
    const bool ok = r.exit == 0 && !r.stopped_after_s;
    nlohmann::json one = {{"seed", r.seed}, {"exit", r.exit}, {"wall_s", r.wall_s}, {"reached_goal", ok}};
    if (r.logged) {
      const nlohmann::json& j = r.log;
      one["verdict_in_log"] = j.value("outcome", "") != "no verdict in the log";
      one["outcome"] = r.stopped_after_s ? "stopped after " + FixedNumber(*r.stopped_after_s, 0) + " s of wall time"
                                         : j.value("outcome", "");
      one["sim_time_s"] = Number(j, "/sim_time_s");
      one["steps"] = Number(j, "/steps");
      one["plans"] = Number(j, "/plans");
      one["unanswered_waits"] = Number(j, "/unanswered_waits");
      one["replan_latency_ms"] = j.value("replan_latency_ms", nlohmann::json::object());
      one["compute_ms"] = j.value("compute_ms", nlohmann::json::object());
      if (Number(j, "/compute_ms/affordance_extractor/count") > 0) {
        affordance_ms.push_back(Number(j, "/compute_ms/affordance_extractor/mean"));
      }
      if (Number(j, "/compute_ms/root_planner/count") > 0) root_s.push_back(1e-3 * Number(j, "/compute_ms/root_planner/first"));
      if (Number(j, "/compute_ms/contact_planner/count") > 0) {
        contact_plan_ms.push_back(Number(j, "/compute_ms/contact_planner/mean"));
        if (ok) contact_total_s.push_back(1e-3 * Number(j, "/compute_ms/contact_planner/total"));
      }
      if (ok) {
        successes += 1;
        steps.push_back(Number(j, "/steps"));
        goal_s.push_back(Number(j, "/sim_time_s"));
        if (goal_s.back() > 0.0 && steps.back() > 0.0) step_period_s.push_back(StepPeriodS(goal_s.back(), static_cast<int>(steps.back())));
        const nlohmann::json trace = j.value("sim_trace", nlohmann::json::array());
        if (goal_s.back() > 0.0 && !trace.empty()) {
          const auto base_xy = [](const nlohmann::json& sample) {
            return Eigen::Vector2d(Number(sample, "/base/position/0"), Number(sample, "/base/position/1"));
          };
          speed_mps.push_back(RunSpeedMps(base_xy(trace.front()), base_xy(trace.back()), goal_s.back()));
        }
      }
      if (j.contains("perception") && j["perception"].is_object()) {
        const nlohmann::json& m = j["perception"];
        one["perception"] = {{"height_error_m", m.value("height_error_m", nlohmann::json())},
                             {"path_coverage", m.value("path_coverage", nlohmann::json())},
                             {"cloud_to_terrain_ms", m.value("cloud_to_terrain_ms", nlohmann::json())},
                             {"known_cells", m.value("known_cells", nlohmann::json())}};
        if (Number(m, "/height_error_m/cells") > 0) {
          map_rms_m.push_back(Number(m, "/height_error_m/rms"));
          map_p95_m.push_back(Number(m, "/height_error_m/p95"));
        }
        if (m.contains("path_coverage") && m["path_coverage"].is_number()) coverage.push_back(m["path_coverage"]);
        if (Number(m, "/cloud_to_terrain_ms/count") > 0) map_latency_ms.push_back(Number(m, "/cloud_to_terrain_ms/median"));
      }
      for (const auto& replan : j.value("replans", nlohmann::json::array())) {
        if (replan.contains("latency_ms") && replan["latency_ms"].is_number()) latencies.push_back(replan["latency_ms"]);
      }
    } else {
      one["outcome"] = "no log of the run";
    }
    per_run.push_back(one);
  }
  nlohmann::json s = {
      {"scenario", row.scenario},
      {"runs", row.runs.size()},
      {"successes", successes},
      {"affordance_ms", Mean(affordance_ms)},
      {"root_s", Mean(root_s)},
      {"contact_s", Mean(contact_total_s)},
      {"contact_plan_ms", Mean(contact_plan_ms)},
      {"steps", Mean(steps)},
      {"time_to_goal_s", Mean(goal_s)},
      // Per run that reached the goal (rbcp/core/run_metrics.h, as sim_bench reports them).
      {"step_period_s", Mean(step_period_s)},
      {"speed_mps", Mean(speed_mps)},
      {"wall_s", Mean(wall_s)},
      {"replan_latency_ms",
       {{"count", latencies.size()},
        {"median", latencies.empty() ? nlohmann::json() : nlohmann::json(nodes::Percentile(latencies, 0.5))},
        {"p95", latencies.empty() ? nlohmann::json() : nlohmann::json(nodes::Percentile(latencies, 0.95))}}},
      {"per_run", per_run},
  };
  if (!map_rms_m.empty() || !coverage.empty() || !map_latency_ms.empty()) {
    // The map's quality over the runs: the worst run's height error (the bar is on every run),
    // the mean coverage of the walked path, the median of the runs' median latencies.
    const auto largest = [](const std::vector<double>& v) {
      return v.empty() ? nlohmann::json() : nlohmann::json(*std::max_element(v.begin(), v.end()));
    };
    s["perception"] = {
        {"runs", std::max({map_rms_m.size(), coverage.size(), map_latency_ms.size()})},
        {"height_error_rms_m", {{"mean", Mean(map_rms_m)}, {"max", largest(map_rms_m)}}},
        {"height_error_p95_m", {{"mean", Mean(map_p95_m)}, {"max", largest(map_p95_m)}}},
        {"path_coverage", Mean(coverage)},
        {"cloud_to_terrain_ms_median",
         map_latency_ms.empty() ? nlohmann::json() : nlohmann::json(nodes::Percentile(map_latency_ms, 0.5))},
    };
  }
  if (const PaperRow* p = PaperFor(row.scenario)) {
    s["paper"] = {{"environment", p->environment}, {"affordance_ms", p->affordance_ms}, {"root_s", p->root_s},
                  {"contact_s", p->contact_s},     {"steps", p->steps},                 {"successes", p->successes},
                  {"runs", p->runs}};
  }
  return s;
}

std::string Markdown(const nlohmann::json& table) {
  std::ostringstream md;
  // A figure with its unit, or a dash where no run gave one.
  const auto f = [](const nlohmann::json& x, int digits, const std::string& unit = "") {
    return x.is_number() ? FixedNumber(x.get<double>(), digits) + unit : std::string("–");
  };
  md << "| environment | affordance | root | contact, steps | success | time to goal (simulated) | mean speed "
        "| step period | replanning latency median / p95 | wall time per run |\n"
     << "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& s : table["scenarios"]) {
    const bool paper = s.contains("paper");
    const nlohmann::json& p = paper ? s["paper"] : nlohmann::json::object();
    // Ours, then the paper's figure in parentheses.
    const auto theirs = [&](const std::string& text) { return paper ? " (paper " + text + ")" : std::string(); };
    const int successes = s["successes"];
    md << "| " << s["scenario"].get<std::string>() << " | " << f(s["affordance_ms"], 3, " ms")
       << theirs(paper ? f(p["affordance_ms"], 2, " ms") : "") << " | " << f(s["root_s"], 3, " s")
       << theirs(paper ? f(p["root_s"], 2, " s") : "") << " | "
       << (successes > 0 ? f(s["contact_s"], 2, " s, ") + f(s["steps"], 1, " steps") : std::string("–"))
       << theirs(paper ? f(p["contact_s"], 2, " s, ") + f(p["steps"], 1, " steps") : "") << " | " << successes << "/"
       << s["runs"].get<int>()
       << theirs(paper ? std::to_string(p["successes"].get<int>()) + "/" + std::to_string(p["runs"].get<int>()) : "")
       << " | " << f(s["time_to_goal_s"], 1, " s") << " | " << f(s["speed_mps"], 3, " m/s") << " | "
       << f(s["step_period_s"], 2, " s") << " | " << f(s["replan_latency_ms"]["median"], 1) << " / "
       << f(s["replan_latency_ms"]["p95"], 1, " ms") << " (" << s["replan_latency_ms"]["count"].get<int>()
       << " replans) | " << f(s["wall_s"], 0, " s") << " |\n";
  }
  bool perceived = false;
  for (const auto& s : table["scenarios"]) perceived = perceived || s.contains("perception");
  if (perceived) {
    md << "\n| environment | map height error RMS, mean / worst run | 95th percentile, mean / worst run "
          "| walked path covered by the map | cloud-to-TERRAIN latency (median of the runs' medians) |\n"
       << "|---|---|---|---|---|\n";
    for (const auto& s : table["scenarios"]) {
      if (!s.contains("perception")) continue;
      const nlohmann::json& m = s["perception"];
      const auto cm = [&](const nlohmann::json& x) { return x.is_number() ? f(100.0 * x.get<double>(), 1) : f(x, 1); };
      md << "| " << s["scenario"].get<std::string>() << " | " << cm(m["height_error_rms_m"]["mean"]) << " / "
         << cm(m["height_error_rms_m"]["max"]) << " cm | " << cm(m["height_error_p95_m"]["mean"]) << " / "
         << cm(m["height_error_p95_m"]["max"]) << " cm | " << cm(m["path_coverage"]) << " % | "
         << f(m["cloud_to_terrain_ms_median"], 1, " ms") << " |\n";
    }
  }
  return md.str();
}

/// The command line.
struct Options {
  std::string runs_dir, out_dir;
  std::vector<std::string> order;  ///< scenarios first in the table
  std::string title;
};

void AddOptions(CLI::App& app, Options& o) {
  app.add_option("--runs", o.runs_dir, "folder of run folders")->required()->check(CLI::ExistingDirectory);
  app.add_option("--out", o.out_dir, "where table.md and table.json go")->required();
  app.add_option("--scenarios", o.order, "scenario order in the table (default: by name)")->delimiter(',');
  app.add_option("--title", o.title, "a line under the table's heading (date, runs, seeds, machine)");
  app.description(
      "The paper's Table 1 from runs of the replanning loop (tools/bench table writes the runs): every\n"
      "folder under --runs with a meta.json ({scenario, seed, exit, wall_s, stopped_after_s}) and, when\n"
      "the run left a log, run.json (run_log's output). Per scenario: mean affordance extraction time (each TERRAIN), root\n"
      "planning time (the first path), contact planning time (the sum of the planning times of the plans\n"
      "the robot got, runs that reached the goal) with the steps walked, success over the runs (tools/launch\n"
      "exited 0: the simulator's verdict was goal reached), mean\n"
      "simulated time to the goal, replanning latency median and 95th percentile over every replan of\n"
      "every run (run_log's, from the log's receive times). Writes table.md (beside the paper's figures)\n"
      "and table.json into --out. Reads files; talks no LCM. Exit status: 0 written, 2 bad input.");
}

/// One run folder: its meta.json and, when the run left a log, its run.json.
Run ReadRun(const fs::path& folder, std::string* scenario) {
  const nlohmann::json meta = ReadJson(folder / "meta.json");
  Run run;
  *scenario = meta.at("scenario").get<std::string>();
  run.seed = meta.at("seed");
  run.exit = meta.at("exit");
  run.wall_s = meta.at("wall_s");
  if (meta.contains("stopped_after_s") && meta["stopped_after_s"].is_number()) run.stopped_after_s = meta["stopped_after_s"];
  const fs::path log_path = folder / "run.json";
  if (fs::exists(log_path)) {
    run.log = ReadJson(log_path);
    run.logged = true;
  }
  return run;
}

/// The runs under runs_dir, by scenario (a folder without meta.json is not a run).
std::map<std::string, Row> ReadRows(const std::string& runs_dir) {
  std::map<std::string, Row> rows;
  for (const auto& entry : fs::directory_iterator(runs_dir)) {
    if (!entry.is_directory() || !fs::exists(entry.path() / "meta.json")) continue;
    std::string scenario;
    Run run = ReadRun(entry.path(), &scenario);
    Row& row = rows[scenario];
    row.scenario = scenario;
    row.runs.push_back(std::move(run));
  }
  if (rows.empty()) throw InputError("no run (a folder with meta.json) in " + runs_dir);
  return rows;
}

/// table.json: a summary per scenario, those of --scenarios first, then the others by name.
nlohmann::json TableJson(std::map<std::string, Row>& rows, const Options& o) {
  std::vector<std::string> order = o.order;
  for (const auto& [name, row] : rows) {
    if (std::find(order.begin(), order.end(), name) == order.end()) order.push_back(name);
  }
  nlohmann::json table = {{"schema_version", 1}, {"title", o.title}, {"scenarios", nlohmann::json::array()}};
  for (const std::string& name : order) {
    auto it = rows.find(name);
    if (it == rows.end()) continue;
    std::sort(it->second.runs.begin(), it->second.runs.end(), [](const Run& a, const Run& b) { return a.seed < b.seed; });
    table["scenarios"].push_back(Summarise(it->second));
  }
  return table;
}

/// table.md: the table with its heading and what its columns mean.
std::string TableMarkdown(const nlohmann::json& table, const std::string& title) {
  std::ostringstream md;
  md << "# Table 1 through the replanning loop\n\n";
  if (!title.empty()) md << title << "\n\n";
  md << Markdown(table) << "\n"
     << "Ours, and in parentheses the paper's Table 1 (ANYmal, 20 runs per environment).\n"
     << "Ours: the four processes over LCM with the simulator as the world (tools/launch), the robot replanning\n"
     << "at every step boundary (8 steps planned, 8 more searched). Affordance: mean extraction time per TERRAIN\n"
     << "message. Root: the first root path's planning time. Contact: the sum of the planning times of the\n"
     << "plans the robot got, and the steps walked to the goal (runs that reached it). Success: runs whose\n"
     << "simulated robot reached the goal (Bullet, the onboard controller; the paper: Gazebo, Free Gait);\n"
     << "a run still going after the bench's --run-timeout is stopped and counts as failed.\n"
     << "Latency: from the first receipt of the ROBOT_STATE a plan started from to the receipt of that\n"
     << "CONTACT_PLAN, in the log's receive times, over every replan of every run. The paper's contact time\n"
     << "plans the whole path once.\n";
  return md.str();
}

int WriteTable(const Options& o) {
  std::map<std::string, Row> rows = ReadRows(o.runs_dir);
  const nlohmann::json table = TableJson(rows, o);
  fs::create_directories(o.out_dir);
  std::ofstream(fs::path(o.out_dir) / "table.json") << table.dump(1) << "\n";
  const std::string md = TableMarkdown(table, o.title);
  std::ofstream(fs::path(o.out_dir) / "table.md") << md;
  std::cout << md;
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return rbcp::cli::Main("bench_table", argc, argv, AddOptions, WriteTable); }
