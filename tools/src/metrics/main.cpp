// metrics LOG [--out metrics.json] [--plot trajectory.png] [--config robot.yaml]
// metrics --table MODE=LOG [MODE=LOG ...]   (the paper's Table I beside ours)
#include <CLI/CLI.hpp>

#include <cstdio>
#include <fstream>

#include "bus/log.h"
#include "metrics/run_metrics.h"
#include "metrics/trajectory_plot.h"

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

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Metrics of a run log (from SIM_TRUTH and PLAN)"};
  app.footer(evade::metrics::metrics_rules());
  std::string log, out, plot, config_path;
  std::vector<std::string> table;
  app.add_option("log", log, "run log (lcm-logger file)");
  app.add_option("--out", out, "also write the metrics JSON here");
  app.add_option("--plot", plot, "write the trajectory picture (PNG) here");
  app.add_option("--config", config_path, "robot configuration (section metrics:)");
  app.add_option("--table", table, "MODE=LOG pairs: print Table I for these runs beside the paper's");
  CLI11_PARSE(app, argc, argv);

  evade::metrics::MetricsParams params;
  try {
    auto root = evade::config::load_robot_config(config_path.empty() ? evade::config::default_config_path() : config_path);
    params = evade::metrics::MetricsParams::from_config(root.section("metrics"));
  } catch (const evade::config::ConfigError& e) {
    std::fprintf(stderr, "metrics: %s\n", e.what());
    return 2;
  }

  try {
    if (!table.empty()) {
      std::printf("%-18s | %-22s | %-14s | %-14s | %-16s\n", "algorithm", "min dist (m)", "time (s)", "reaction (s)",
                  "speed var");
      std::printf("%-18s | %-22s | %-14s | %-14s | %-16s\n", "", "here / paper", "here / paper", "here / paper",
                  "here / paper");
      std::printf("-------------------+------------------------+----------------+----------------+-----------------\n");
      for (const auto& pair : table) {
        auto eq = pair.find('=');
        if (eq == std::string::npos) throw std::runtime_error("--table takes MODE=LOG, got " + pair);
        std::string mode = pair.substr(0, eq);
        auto m = evade::metrics::compute_metrics(evade::bus::read_log(pair.substr(eq + 1)), params);
        const PaperRow* paper = nullptr;
        for (const auto& r : kPaper)
          if (mode == r.mode) paper = &r;
        std::string dist = m.collided ? "0 (collided)" : fmt(m.min_dist_m);
        std::string time = m.reached_goal ? fmt(m.time_to_goal_s, "%.2f") : "-";
        std::printf("%-18s | %-10s / %-9s | %-6s / %-5s | %-6s / %-5s | %-7s / %-6s\n",
                    paper ? paper->name : mode.c_str(), dist.c_str(), paper ? paper->min_dist : "",
                    time.c_str(), paper ? paper->time : "", fmt(m.reaction_time_s).c_str(),
                    paper ? paper->reaction : "", fmt(m.speed_var, "%.4f").c_str(), paper ? paper->speed_var : "");
      }
      return 0;
    }
    if (log.empty()) {
      std::fprintf(stderr, "metrics: a LOG is required (see --help)\n");
      return 2;
    }
    auto m = evade::metrics::compute_metrics(evade::bus::read_log(log), params);
    std::string json = evade::metrics::metrics_json(m);
    std::fputs(json.c_str(), stdout);
    if (!out.empty()) {
      std::ofstream f(out);
      f << json;
      if (!f) throw std::runtime_error("cannot write " + out);
    }
    if (!plot.empty()) evade::metrics::plot_trajectory(m, plot);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "metrics: %s\n", e.what());
    return 1;
  }
  return 0;
}
