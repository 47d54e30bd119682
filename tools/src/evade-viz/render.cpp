#include "render.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/visualization/pcl_visualizer.h>
#include <vtkActor.h>
#include <vtkCellArray.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkProperty.h>
#include <vtkSmartPointer.h>

#include <cmath>

namespace evade::viz {

namespace {

using pcl::visualization::PCLVisualizer;

void add_points(PCLVisualizer& v, const PointsPrim& prim) {
  pcl::PointCloud<pcl::PointXYZRGB>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZRGB>);
  cloud->reserve(prim.xyz.size());
  for (size_t i = 0; i < prim.xyz.size(); ++i) {
    pcl::PointXYZRGB q;
    q.x = prim.xyz[i].x;
    q.y = prim.xyz[i].y;
    q.z = prim.xyz[i].z;
    const Rgb c = i < prim.rgb.size() ? prim.rgb[i] : Rgb{1, 1, 1};
    q.r = uint8_t(c.r * 255);
    q.g = uint8_t(c.g * 255);
    q.b = uint8_t(c.b * 255);
    cloud->push_back(q);
  }
  pcl::visualization::PointCloudColorHandlerRGBField<pcl::PointXYZRGB> rgb(cloud);
  v.addPointCloud<pcl::PointXYZRGB>(cloud, rgb, prim.id);
  v.setPointCloudRenderingProperties(pcl::visualization::PCL_VISUALIZER_POINT_SIZE, prim.size_px, prim.id);
}

// All polylines of a primitive as one VTK actor.
void add_lines(PCLVisualizer& v, const LinesPrim& prim) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  for (const auto& strip : prim.strips) {
    if (strip.size() < 2) continue;
    cells->InsertNextCell(vtkIdType(strip.size()));
    for (const auto& q : strip) cells->InsertCellPoint(points->InsertNextPoint(q.x, q.y, q.z));
  }
  if (cells->GetNumberOfCells() == 0) return;
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetLines(cells);
  v.addModelFromPolyData(poly, prim.id);
  v.setShapeRenderingProperties(pcl::visualization::PCL_VISUALIZER_COLOR, prim.rgb.r, prim.rgb.g, prim.rgb.b, prim.id);
  v.setShapeRenderingProperties(pcl::visualization::PCL_VISUALIZER_OPACITY, prim.opacity, prim.id);
  v.setShapeRenderingProperties(pcl::visualization::PCL_VISUALIZER_LINE_WIDTH, prim.width_px, prim.id);
  // Unlit: a line's colour is the scene's colour whatever its direction
  // (lit, orange came out yellow).
  const auto it = v.getShapeActorMap()->find(prim.id);
  if (it != v.getShapeActorMap()->end())
    if (auto* actor = vtkActor::SafeDownCast(it->second)) {
      actor->GetProperty()->SetLighting(false);
      actor->GetProperty()->SetAmbient(1.0);
      actor->GetProperty()->SetDiffuse(0.0);
      actor->GetProperty()->SetSpecular(0.0);
    }
}

}  // namespace

Renderer::Renderer(const VizParams& p) : p_(p), v_(std::make_unique<PCLVisualizer>("evade-viz")) {
  v_->setSize(p.window_width_px, p.window_height_px);
  v_->setBackgroundColor(0.08, 0.08, 0.1);
  v_->setShowFPS(false);
  v_->setCameraPosition(-p.camera_distance_m, 0, p.camera_height_m, 2, 0, 0, 0, 0, 1);
}

Renderer::~Renderer() = default;

void Renderer::on_key(std::function<void(const std::string&)> fn) {
  v_->registerKeyboardCallback([fn](const pcl::visualization::KeyboardEvent& e) {
    if (e.keyDown()) fn(e.getKeySym());
  });
}

void Renderer::draw(const Scene& s, const std::string& status) {
  v_->removeAllPointClouds();
  v_->removeAllShapes();
  for (const auto& p : s.points)
    if (!p.xyz.empty()) add_points(*v_, p);
  for (const auto& l : s.lines) add_lines(*v_, l);
  for (const auto& l : s.labels)
    v_->addText3D(l.text, pcl::PointXYZ(l.at.x, l.at.y, l.at.z), l.height_m, l.rgb.r, l.rgb.g, l.rgb.b, l.id);
  const int font = 14, line_px = 18;
  int y = p_.window_height_px - line_px - 4;
  int n = 0;
  for (const auto& line : s.hud) {
    v_->addText(line, 8, y, font, 0.9, 0.9, 0.9, "hud_" + std::to_string(n++));
    y -= line_px;
  }
  v_->addText(status, 8, 6, font, 0.7, 0.7, 0.7, "status");
  hud_lines_ = n;
}

void Renderer::follow(const Scene& s) {
  if (!s.have_robot) return;
  const double c = std::cos(s.robot_yaw), sn = std::sin(s.robot_yaw);
  v_->setCameraPosition(s.robot_x - c * p_.camera_distance_m, s.robot_y - sn * p_.camera_distance_m, p_.camera_height_m,
                        s.robot_x + 2 * c, s.robot_y + 2 * sn, 0.0, 0, 0, 1);
}

bool Renderer::spin(int ms) {
  v_->spinOnce(ms, true);
  return !v_->wasStopped();
}

bool Renderer::snapshot(const std::string& path) {
  v_->spinOnce(1, true);
  v_->saveScreenshot(path);
  return true;
}

}  // namespace evade::viz
