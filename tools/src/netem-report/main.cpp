// netem-report --dir DIR [--warmup-s W]
// The verdict of a tools/netem-run run (lib/soak/live_report.h) from
// DIR/run/logs/exit_status.tsv, DIR/run/metrics.json, DIR/rss.tsv,
// DIR/pids.tsv, DIR/netem.json and DIR/health.jsonl: prints it and writes
// DIR/report.json. Memory growth is fitted after the first W seconds of
// each process (default 60). Exit 0 pass (no crash, no collision at
// fault), 1 fail, 2 missing or unreadable files.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "soak/live_report.h"

namespace fs = std::filesystem;

namespace {

std::string read_text(const fs::path& p) {
  std::ifstream f(p);
  if (!f) throw std::runtime_error("cannot read " + p.string());
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"verdict of a live run on a degraded bus (tools/netem-run)"};
  std::string dir;
  double warmup_s = 60.0;
  app.add_option("--dir", dir, "the run's directory")->required();
  app.add_option("--warmup-s", warmup_s, "memory samples before this are not fitted (default 60)")
      ->check(CLI::NonNegativeNumber);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    const fs::path d(dir);
    evade::soak::LiveFiles f{read_text(d / "run" / "logs" / "exit_status.tsv"),
                             read_text(d / "rss.tsv"),
                             read_text(d / "pids.tsv"),
                             read_text(d / "run" / "metrics.json"),
                             read_text(d / "netem.json"),
                             read_text(d / "health.jsonl")};
    const auto r = evade::soak::make_live_report(f, warmup_s);
    std::ofstream(d / "report.json") << evade::soak::live_report_json(r) << "\n";
    std::fputs(evade::soak::live_report_text(r).c_str(), stdout);
    return r.failures.empty() ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "netem-report: %s\n", e.what());
    return 2;
  }
}
