// summary.png: one panel per family, success rate per mode with its 95 %
// Wilson interval as an error bar, and the at-fault collision rate beside it.
#pragma once

#include <string>
#include <vector>

#include "benchmark/benchmark_summary.h"

namespace evade::benchmark {

// Throws std::runtime_error when the PNG cannot be written or there is no group.
void plot_summary(const std::vector<GroupSummary>& groups, const std::string& png_path);

}  // namespace evade::benchmark
