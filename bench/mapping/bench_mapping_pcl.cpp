// What PCL would cost for the crop step alone, on the bench_mapping
// revolution: copying the message's arrays into a pcl::PointCloud, then a
// CropBox (sensor frame, the grid's extent), and a PassThrough on z. Compare
// with BM_BuildElevationMap in bench_mapping, which crops, transforms with
// per-slice poses, bins, fills holes and computes the obstacle layer.
#include <benchmark/benchmark.h>
#include <pcl/filters/crop_box.h>
#include <pcl/filters/passthrough.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "mapping/synthetic_scan.h"

namespace evade::mapping {
namespace {

SynthCloud revolution() {
  SynthWorld w;
  for (int k = 0; k < 24; ++k) {
    const double a = 2.0 * M_PI * k / 24.0, r = 2.0 + (k % 4);
    w.cylinders.push_back({r * std::cos(a), r * std::sin(a), 0.25 + 0.05 * (k % 2), 0.5 + 1.2 * (k % 2)});
  }
  w.boxes.push_back({3.0, -3.0, 0.3, 1.0, 2.0, 1.0});
  w.boxes.push_back({6.0, 0.0, 0.0, 0.2, 12.2, 4.0});
  w.boxes.push_back({-6.0, 0.0, 0.0, 0.2, 12.2, 4.0});
  w.boxes.push_back({0.0, 6.0, 0.0, 12.2, 0.2, 4.0});
  w.boxes.push_back({0.0, -6.0, 0.0, 12.2, 0.2, 4.0});
  SynthScanOptions o;
  o.range_noise_std_m = 0.01;
  return synth_vlp16(w, o);
}

pcl::PointCloud<pcl::PointXYZ>::Ptr to_pcl(const SynthCloud& c) {
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->resize(c.x.size());
  for (size_t i = 0; i < c.x.size(); ++i) (*cloud)[i] = pcl::PointXYZ(c.x[i], c.y[i], c.z[i]);
  return cloud;
}

void BM_PclCopyCropBoxPassThrough(benchmark::State& state) {
  const SynthCloud c = revolution();
  pcl::PointCloud<pcl::PointXYZ> out, out2;
  size_t kept = 0;
  for (auto _ : state) {
    auto cloud = to_pcl(c);
    pcl::CropBox<pcl::PointXYZ> crop;
    crop.setInputCloud(cloud);
    crop.setMin(Eigen::Vector4f(-5.0f, -5.0f, -1.5f, 1.0f));
    crop.setMax(Eigen::Vector4f(5.0f, 5.0f, 1.5f, 1.0f));
    crop.filter(out);
    pcl::PassThrough<pcl::PointXYZ> pass;
    pass.setInputCloud(pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>(out));
    pass.setFilterFieldName("z");
    pass.setFilterLimits(-1.5f, 1.5f);
    pass.filter(out2);
    kept = out2.size();
    benchmark::DoNotOptimize(out2.data());
  }
  state.counters["points"] = double(c.x.size());
  state.counters["kept"] = double(kept);
}
BENCHMARK(BM_PclCopyCropBoxPassThrough)->Unit(benchmark::kMillisecond);

void BM_PclVoxelGrid10cm(benchmark::State& state) {
  const SynthCloud c = revolution();
  auto cloud = to_pcl(c);
  pcl::PointCloud<pcl::PointXYZ> out;
  for (auto _ : state) {
    pcl::VoxelGrid<pcl::PointXYZ> vg;
    vg.setInputCloud(cloud);
    vg.setLeafSize(0.1f, 0.1f, 0.1f);
    vg.filter(out);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["kept"] = double(out.size());
}
BENCHMARK(BM_PclVoxelGrid10cm)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace evade::mapping

BENCHMARK_MAIN();
