// libFuzzer target: RS-Helios MSOP/DIFOP packets (see fuzz_lidar_common.h).
#include "fuzz_lidar_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return evade::sensing::fuzz::fuzz_lidar(evade::sensing::LidarModel::kRsHelios, data, size);
}
