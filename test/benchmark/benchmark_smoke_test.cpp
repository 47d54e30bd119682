// CI smoke for the closed loop (issue 17 item 9): a few lockstep episodes of
// two scenario families through tools/benchmark, the real stack end to end.
// Fails on any collision at fault and on any episode without metrics.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>

#include "benchmark/episode_row.h"

namespace evade::benchmark {
namespace {

namespace fs = std::filesystem;

TEST(BenchmarkSmoke, TwoFamiliesThreeSeedsNoCollisionAtFault) {
  fs::path out = fs::path(::testing::TempDir()) / "benchmark_smoke";
  fs::remove_all(out);
  std::string cmd = std::string(EVADE_SOURCE_DIR) + "/tools/benchmark --families crossing,headon --episodes 3 --out " +
                    out.string() + " --jobs 2 --fail-on-at-fault";
  int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  auto rows = read_results((out / "results.jsonl").string());
  ASSERT_EQ(rows.size(), 6u);
  for (const Episode& e : rows) {
    SCOPED_TRACE(e.id.family + " seed " + std::to_string(e.id.seed) + ": " + e.id.dir);
    EXPECT_EQ(e.error, "");
    EXPECT_FALSE(e.at_fault);
    EXPECT_EQ(e.collisions_at_fault, 0);
  }
  EXPECT_EQ(WEXITSTATUS(status), 0) << "see " << out / "summary.md"
                                    << " and " << out / "failed";
}

}  // namespace
}  // namespace evade::benchmark
