// One LiDAR model as the revolution assembler (lidar_decoder.h) sees it:
// a UDP payload in; its returns and the times that place them out, or a
// calibration packet kept for replay, or nothing (counted). The driver
// picks the model by `lidar.model` (make_sensor_model); VLP-16 and
// RS-Helios are the two there are. Stateful where the sensor is (the
// RS-Helios's DIFOP calibration), clock-free.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "sensing/lidar_return.h"

namespace evade::sensing {

enum class LidarModel { kVlp16, kRsHelios };
const char* model_name(LidarModel m);  // "vlp16", "rs_helios" (as in config and messages)

// count(name, n): every packet and problem is counted by name for HEALTH.
using CountFn = std::function<void(const std::string& name, int64_t n)>;

struct PacketTimes {
  int64_t sensor_us = 0;    // sensor clock (VLP-16: us past the hour; RS-Helios: UTC us)
  int64_t receive_us = 0;   // receive time minus the packet's span: first-firing estimate
  int64_t absolute_us = 0;  // sensor clock as an absolute time
};

enum class PacketUse {
  kPoints,       // returns (possibly none) and times filled: a data packet
  kCalibration,  // no points, but the decoding depends on it: kept in LIDAR_SCAN
  kIgnored,      // malformed, or carries nothing the cloud needs (counted)
};

struct RangeBand {
  double min_range_m = 0.0;
  double max_range_m = 200.0;
  bool vertical_offset_correction = true;  // VLP-16 only (vlp16.h)
};

class SensorModel {
 public:
  virtual ~SensorModel() = default;
  virtual LidarModel model() const = 0;
  // Decodes one payload received at `receive_utime`; appends returns to `returns`.
  virtual PacketUse decode(const uint8_t* data, size_t size, int64_t receive_utime, std::vector<LidarReturn>* returns,
                           PacketTimes* times) = 0;
  // to - from on the sensor clock, us (the VLP-16's wraps at the hour).
  virtual int64_t sensor_delta_us(int64_t from, int64_t to) const = 0;
  // False while a model that needs calibration has none.
  virtual bool calibrated() const = 0;
  // True for a packet to keep over a stretch of point-less packets (DIFOP).
  virtual bool is_calibration(const uint8_t* data, size_t size) const = 0;
};

std::unique_ptr<SensorModel> make_sensor_model(LidarModel model, const RangeBand& band, CountFn count);

}  // namespace evade::sensing
