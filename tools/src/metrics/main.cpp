// metrics LOG [--out metrics.json] [--plot trajectory.png] [--config robot.yaml] [--no-reaction]
// metrics --table MODE=LOG [MODE=LOG ...]   (the paper's Table I beside ours)
// metrics --stats RESULTS.jsonl              (the same over many runs: mean ± sd)
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "benchmark/benchmark_summary.h"
#include "bus/log.h"
#include "bus/process_main.h"
#include "config/robot_profile.h"
#include "metrics/run_metrics.h"
#include "metrics/trajectory_plot.h"
#include "planning/params.h"

namespace {

struct PaperRow {
  const char* mode;
  const char* name;
  const char* min_dist;
  const char* time;
  const char* reaction;
  const char* speed_var;
};
// Table I of the paper (simulation, Gazebo with a Jackal).
const PaperRow kPaper[] = {{"mpc", "MPC", "0 (collided)", "-", "1.331", "-"},
                           {"cbf", "MPC-CBF", "0.273", "22.07", "0.357", "0.1598"},
                           {"kf", "MPC-KF", "0.201", "20.05", "1.197", "0.0061"},
                           {"cbf_curvefit", "MPC-CBF-curvefit", "0.074", "23.27", "0.421", "0.1306"},
                           {"dcbf", "MPC-D-CBF (paper)", "0.828", "21.52", "0.353", "0.0172"},
                           // not in the paper: evade's own planner (mode evade), no paper figures
                           {"evade", "evade (not paper)", "", "", "", ""}};

std::string fmt(const std::optional<double>& v, const char* f = "%.3f") {
  if (!v) return "-";
  char b[32];
  std::snprintf(b, sizeof b, f, *v);
  return b;
}

struct Params {
  evade::metrics::MetricsParams metrics;
  evade::planning::PlannerParams planner;
};

// Throws evade::config::ConfigError.
Params load_params(const std::string& path, const std::string& robot) {
  auto root = evade::config::load_robot_config(path, {robot, ""});
  Params p;
  p.metrics = evade::metrics::MetricsParams::from_config(root.section("metrics"));
  p.planner = evade::planning::PlannerParams::from_config(root);
  return p;
}

// The configuration a run's reaction replay uses: --config, else the
// robot.yaml run_scenario writes beside run.lcmlog, else the default.
std::string config_for(const std::string& log, const std::string& config_path) {
  if (!config_path.empty()) return config_path;
  const auto beside = std::filesystem::path(log).parent_path() / "robot.yaml";
  return std::filesystem::exists(beside) ? beside.string() : evade::config::default_config_path();
}

void print_table(const std::vector<std::string>& pairs, const std::string& config_path, const std::string& robot) {
  std::printf("%-18s | %-22s | %-14s | %-14s | %-16s | %s\n", "algorithm", "min dist (m)", "time (s)", "reaction (s)",
              "speed var", "contacts");
  std::printf("%-18s | %-22s | %-14s | %-14s | %-16s | %s\n", "", "here / paper", "here / paper", "here / paper",
              "here / paper", "(at fault)");
  std::printf("-------------------+------------------------+----------------+----------------+------------------+");
  std::printf("-----------\n");
  for (const auto& pair : pairs) {
    auto eq = pair.find('=');
    if (eq == std::string::npos) throw std::runtime_error("--table takes MODE=LOG, got " + pair);
    const std::string mode = pair.substr(0, eq), log = pair.substr(eq + 1);
    const Params params = load_params(config_for(log, config_path), robot);
    auto m = evade::metrics::compute_metrics(evade::bus::read_log(log), params.metrics, &params.planner);
    const PaperRow* paper = nullptr;
    for (const auto& r : kPaper)
      if (mode == r.mode) paper = &r;
    std::string dist = m.collided ? "0 (collided)" : fmt(m.min_dist_m);
    std::string time = m.reached_goal ? fmt(m.time_to_goal_s, "%.2f") : "-";
    std::string contacts = std::to_string(m.contacts.size()) + " (" + std::to_string(m.collisions_at_fault) + ")";
    std::printf("%-18s | %-10s / %-9s | %-6s / %-5s | %-6s / %-5s | %-7s / %-6s | %s\n",
                paper ? paper->name : mode.c_str(), dist.c_str(), paper ? paper->min_dist : "", time.c_str(),
                paper ? paper->time : "", fmt(m.reaction_time_s).c_str(), paper ? paper->reaction : "",
                fmt(m.speed_var, "%.4f").c_str(), paper ? paper->speed_var : "", contacts.c_str());
  }
}

std::string mean_sd(const std::optional<evade::benchmark::MeanSd>& s, const char* f) {
  if (!s) return "-";
  return s->n > 1 ? fmt(s->mean, f) + " ± " + fmt(s->sd, f) : fmt(s->mean, f);
}

// Pads to a width in characters (UTF-8: "±" is two bytes, one character).
std::string pad(std::string s, size_t width) {
  size_t chars = 0;
  for (unsigned char c : s) chars += (c & 0xC0) != 0x80;
  if (chars < width) s.append(width - chars, ' ');
  return s;
}

// Table I over the runs of a benchmark's results.jsonl (tools/table1 --runs N):
// mean ± sample sd per metric, the paper's value, and the collision counts.
void print_stats(const std::string& results) {
  const size_t w[] = {18, 4, 30, 22, 22, 26, 9};
  auto row = [&](const std::vector<std::string>& cells, const std::string& last) {
    std::string line;
    for (size_t i = 0; i < cells.size(); ++i) line += pad(cells[i], w[i]) + " | ";
    std::printf("%s%s\n", line.c_str(), last.c_str());
  };
  row({"algorithm", "runs", "min dist (m)", "time (s)", "reaction (s)", "speed var", "goal"}, "runs with contacts");
  row({"", "", "mean ± sd / paper", "mean ± sd / paper", "mean ± sd / paper", "mean ± sd / paper", "reached"},
      "at fault / not");
  for (const auto& s : evade::benchmark::mode_stats(evade::benchmark::read_results(results))) {
    const PaperRow* paper = nullptr;
    for (const auto& r : kPaper)
      if (s.mode == r.mode) paper = &r;
    auto cell = [&](const std::optional<evade::benchmark::MeanSd>& v, const char* f, const char* p) {
      return mean_sd(v, f) + " / " + (paper ? p : "");
    };
    std::string goal = std::to_string(s.reached_goal) + "/" + std::to_string(s.runs);
    if (s.errors > 0) goal += " +" + std::to_string(s.errors) + " err";
    row({paper ? paper->name : s.mode, std::to_string(s.runs), cell(s.min_dist_m, "%.3f", paper ? paper->min_dist : ""),
         cell(s.time_to_goal_s, "%.2f", paper ? paper->time : ""),
         cell(s.reaction_time_s, "%.3f", paper ? paper->reaction : ""),
         cell(s.speed_var, "%.4f", paper ? paper->speed_var : ""), goal},
        std::to_string(s.runs_at_fault) + " / " + std::to_string(s.runs_not_at_fault));
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Metrics of a run log (from SIM_TRUTH and PLAN)"};
  app.footer(evade::metrics::metrics_rules());
  std::string log, out, plot;
  evade::bus::CommonOptions opts;
  std::vector<std::string> table;
  app.add_option("log", log, "run log (lcm-logger file)");
  app.add_option("--out", out, "also write the metrics JSON here");
  app.add_option("--plot", plot, "write the trajectory picture (PNG) here");
  // --config: the run's robot configuration (sections metrics: and planner:;
  // default config/robot.yaml, and with --table the robot.yaml beside each
  // log when there is one); --robot: a profile merged onto it.
  evade::bus::add_robot_options(app, opts, false);
  app.add_option("--table", table, "MODE=LOG pairs: print Table I for these runs beside the paper's");
  bool no_reaction = false;
  app.add_flag("--no-reaction", no_reaction,
               "skip the counterfactual planner replay: no reaction times (the costly part; see below)");
  std::string stats;
  app.add_option("--stats", stats,
                 "RESULTS.jsonl of tools/benchmark: Table I as mean ± sd over the runs of each mode "
                 "(time over the runs that reached the goal), beside the paper's");
  CLI11_PARSE(app, argc, argv);

  try {
    if (!stats.empty()) {
      print_stats(stats);
      return 0;
    }
    if (!table.empty()) {
      print_table(table, opts.config_path, opts.robot);
      return 0;
    }
    if (log.empty()) {
      std::fprintf(stderr, "metrics: a LOG is required (see --help)\n");
      return 2;
    }
    const Params params =
        load_params(opts.config_path.empty() ? evade::config::default_config_path() : opts.config_path, opts.robot);
    auto m = evade::metrics::compute_metrics(evade::bus::read_log(log), params.metrics,
                                             no_reaction ? nullptr : &params.planner);
    std::string json = evade::metrics::metrics_json(m);
    std::fputs(json.c_str(), stdout);
    if (!out.empty()) {
      std::ofstream f(out);
      f << json;
      if (!f) throw std::runtime_error("cannot write " + out);
    }
    if (!plot.empty()) evade::metrics::plot_trajectory(m, plot);
  } catch (const evade::config::ConfigError& e) {
    std::fprintf(stderr, "metrics: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "metrics: %s\n", e.what());
    return 1;
  }
  return 0;
}
