// benchmark-summary row --family F --seed K --mode M --metrics FILE [...]
//   one results.jsonl row for an episode (stdout, one line)
// benchmark-summary summarize RESULTS.jsonl [--json F] [--png F] [--markdown] [--fail-on-at-fault]
//   statistics per family and mode (docs/benchmark.md)
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "benchmark/benchmark_summary.h"
#include "benchmark/episode_row.h"
#include "benchmark/summary_plot.h"

namespace {

namespace bm = evade::benchmark;

std::optional<std::string> slurp(const std::string& path) {
  std::ifstream f(path);
  if (!f) return std::nullopt;
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

void write_file(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  f << text;
  if (!f) throw std::runtime_error("cannot write " + path);
}

// Prints the row; 0 for a row with metrics, 1 for an error row.
// With `perception_path`, an unreadable file is an error row too.
int run_row(const bm::EpisodeId& id, const std::string& metrics_path, const std::string& perception_path,
            const std::string& error) {
  std::string why = error;
  if (why.empty()) {
    if (auto text = slurp(metrics_path)) {
      try {
        std::string perception;
        if (!perception_path.empty()) {
          auto p = slurp(perception_path);
          if (!p) throw std::runtime_error("cannot read " + perception_path);
          perception = *p;
        }
        std::puts(bm::make_row(id, *text, perception).c_str());
        return 0;
      } catch (const std::exception& e) {
        why = e.what();
      }
    } else {
      why = "run_scenario exit " + std::to_string(id.exit_code) + " wrote no " + metrics_path;
    }
  }
  std::puts(bm::make_error_row(id, why).c_str());
  return 1;
}

int run_summarize(const std::string& results, const std::string& json, const std::string& png, bool markdown,
                  bool fail_on_at_fault) {
  auto rows = bm::read_results(results);
  if (rows.empty()) throw std::runtime_error(results + " has no rows");
  bm::check_rows(rows);
  auto groups = bm::summarize(rows);
  if (!json.empty()) write_file(json, bm::summary_json(groups));
  if (!png.empty()) bm::plot_summary(groups, png);
  if (markdown) {
    std::fputs(bm::markdown_table(groups).c_str(), stdout);
    const std::string perception = bm::perception_markdown_table(groups);
    if (!perception.empty()) std::printf("\nPerception (perception-metrics, pooled):\n\n%s", perception.c_str());
  }
  int errors = 0, at_fault = 0;
  for (const auto& e : rows) {
    errors += !e.error.empty();
    at_fault += e.error.empty() && (e.at_fault || e.collisions_at_fault > 0);
  }
  if (errors > 0)
    std::fprintf(stderr, "benchmark-summary: %d episodes produced no metrics (rows with \"error\")\n", errors);
  if (fail_on_at_fault && at_fault > 0)
    std::fprintf(stderr, "benchmark-summary: %d episodes had a collision at fault\n", at_fault);
  return errors > 0 || (fail_on_at_fault && at_fault > 0) ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Benchmark rows and their statistics (docs/benchmark.md)"};
  app.require_subcommand(1);
  bm::EpisodeId id;
  std::string metrics, perception, error;
  auto* row = app.add_subcommand("row", "print one results.jsonl row for an episode (exit 1: an error row)");
  row->add_option("--family", id.family, "scenario family")->required();
  row->add_option("--seed", id.seed, "seed")->required();
  row->add_option("--mode", id.mode, "planner mode")->required();
  row->add_option("--metrics", metrics, "the episode's metrics.json");
  row->add_option("--perception", perception, "the episode's perception-metrics JSON (adds \"perception\")");
  row->add_option("--error", error, "the episode failed before metrics: why");
  row->add_option("--host", id.host, "where it ran");
  row->add_option("--scenario-sha256", id.scenario_sha256, "hash of the scenario file");
  row->add_option("--exit-code", id.exit_code, "run_scenario's exit status");
  row->add_option("--wall-s", id.wall_s, "wall-clock seconds");
  row->add_option("--dir", id.dir, "where the episode's files are kept");

  std::string results, json, png;
  bool markdown = false, fail_on_at_fault = false;
  auto* sum = app.add_subcommand("summarize", "statistics per family and mode");
  sum->add_option("results", results, "results.jsonl")->required();
  sum->add_option("--json", json, "write summary.json here");
  sum->add_option("--png", png, "write summary.png here");
  sum->add_flag("--markdown", markdown, "print the summary table (Markdown)");
  sum->add_flag("--fail-on-at-fault", fail_on_at_fault, "exit 1 when any episode had a collision at fault");
  CLI11_PARSE(app, argc, argv);

  try {
    if (row->parsed()) {
      if (metrics.empty() && error.empty()) throw std::runtime_error("row needs --metrics or --error");
      return run_row(id, metrics, perception, error);
    }
    return run_summarize(results, json, png, markdown, fail_on_at_fault);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "benchmark-summary: %s\n", e.what());
    return 2;
  }
}
