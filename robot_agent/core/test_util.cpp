#include "robot_agent/core/test_util.h"

#include "common/carmen_log.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

namespace cairn::agent::testing {
namespace {

void add_box(std::vector<Segment>* w, double x0, double y0, double x1, double y1) {
  w->push_back({{x0, y0}, {x1, y0}});
  w->push_back({{x1, y0}, {x1, y1}});
  w->push_back({{x1, y1}, {x0, y1}});
  w->push_back({{x0, y1}, {x0, y0}});
}

double cast_one(const std::vector<Segment>& world, const Eigen::Vector2d& o, const Eigen::Vector2d& d) {
  double best = std::numeric_limits<double>::infinity();
  for (const Segment& s : world) {
    const Eigen::Vector2d e = s.b - s.a;
    const double den = d.x() * e.y() - d.y() * e.x();
    if (std::abs(den) < 1e-12) continue;
    const Eigen::Vector2d w = s.a - o;
    const double t = (w.x() * e.y() - w.y() * e.x()) / den;
    const double u = (w.x() * d.y() - w.y() * d.x()) / den;
    if (t > 0.0 && u >= 0.0 && u <= 1.0) best = std::min(best, t);
  }
  return best;
}

}  // namespace

std::vector<Segment> make_room(double yaw_rad) {
  std::vector<Segment> w;
  // Outer wall with a notch in the top-right corner.
  const std::vector<Eigen::Vector2d> outer = {{-6, -5}, {6, -5}, {6, 2}, {4, 2}, {4, 5}, {-6, 5}};
  for (size_t i = 0; i < outer.size(); ++i) w.push_back({outer[i], outer[(i + 1) % outer.size()]});
  w.push_back({{-6, 1}, {-3.5, 1}});  // inner wall
  add_box(&w, 3.0, -3.6, 3.6, -3.0);  // pillars
  add_box(&w, -0.4, 3.2, 0.4, 3.7);
  add_box(&w, -4.0, -3.5, -3.4, -2.6);
  const SE2 R(0.0, 0.0, yaw_rad);
  for (Segment& s : w) {
    s.a = R * s.a;
    s.b = R * s.b;
  }
  return w;
}

LaserScan ray_cast(const std::vector<Segment>& world, const SE2& T, StampNs stamp_ns, int num_beams,
                   double noise_sigma_m, unsigned seed) {
  LaserScan scan;
  scan.stamp_ns = stamp_ns;
  scan.angle_min_rad = float(-M_PI);
  scan.angle_increment_rad = float(2.0 * M_PI / num_beams);
  scan.range_min_m = 0.05f;
  scan.range_max_m = 30.f;
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (int i = 0; i < num_beams; ++i) {
    const double a = T.yaw() + double(beam_angle_rad(scan, size_t(i)));
    double r = cast_one(world, T.translation(), {std::cos(a), std::sin(a)});
    if (noise_sigma_m > 0.0) r += noise_sigma_m * noise(rng);
    scan.ranges_m.push_back(std::isfinite(r) ? float(r) : scan.range_max_m);
  }
  return scan;
}

Eigen::Isometry3d test_T_base_camera() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  // Columns: camera x (right) = -base y, camera y (down) = -base z, camera z (forward) = base x.
  T.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  T.translation() = Eigen::Vector3d(0.1, 0.0, 0.4);
  return T;
}

RgbdFrame grey_wall_frame() {
  RgbdFrame f;
  f.stamp_ns = 1000;
  f.intrinsics = CameraIntrinsics{320, 240, 260.0, 260.0, 159.5, 119.5, 0.001};
  f.T_base_camera = test_T_base_camera();
  f.rgb.assign(320 * 240 * 3, 128);
  f.depth.assign(320 * 240, 4000);
  return f;
}

void paint_square(RgbdFrame* f, int u0, int v0, int size, uint8_t r, uint8_t g, uint8_t b, uint16_t depth_mm) {
  const int w = f->intrinsics.width;
  for (int v = v0; v < v0 + size; ++v)
    for (int u = u0; u < u0 + size; ++u) {
      const size_t i = size_t(v) * size_t(w) + size_t(u);
      f->rgb[3 * i] = r, f->rgb[3 * i + 1] = g, f->rgb[3 * i + 2] = b;
      f->depth[i] = depth_mm;
    }
}

RgbdFrame render_rgbd(const SE2& T_world_base, const Eigen::Vector3d& object_world, double size_m, StampNs stamp_ns,
                      const std::array<uint8_t, 3>& rgb) {
  RgbdFrame f;
  f.stamp_ns = stamp_ns;
  f.intrinsics = CameraIntrinsics{160, 120, 130.0, 130.0, 79.5, 59.5, 0.001};
  f.T_base_camera = test_T_base_camera();
  const size_t n = 160 * 120;
  f.rgb.assign(3 * n, 128);  // grey background
  f.depth.assign(n, 4000);   // at 4 m
  const Eigen::Vector3d p_cam = (T_world_base.to_isometry3() * f.T_base_camera).inverse() * object_world;
  if (p_cam.z() < 0.3) return f;
  const double u = f.intrinsics.fx * p_cam.x() / p_cam.z() + f.intrinsics.cx;
  const double v = f.intrinsics.fy * p_cam.y() / p_cam.z() + f.intrinsics.cy;
  const double half_px = 0.5 * size_m * f.intrinsics.fx / p_cam.z();
  for (int row = 0; row < 120; ++row) {
    for (int col = 0; col < 160; ++col) {
      if (std::abs(col - u) > half_px || std::abs(row - v) > half_px) continue;
      const size_t i = size_t(row) * 160 + col;
      f.rgb[3 * i] = rgb[0];
      f.rgb[3 * i + 1] = rgb[1];
      f.rgb[3 * i + 2] = rgb[2];
      f.depth[i] = uint16_t(std::lround(p_cam.z() * 1000.0));
    }
  }
  return f;
}

std::optional<std::vector<CarmenScan>> read_carmen_flaser(const std::string& path, int max_scans) {
  if (!std::ifstream(path)) return std::nullopt;
  const CarmenLog log = read_carmen_log(path);  // the project's one CARMEN reader (common/)
  std::vector<CarmenScan> out;
  for (const auto& record : log.scans) {
    if (int(out.size()) >= max_scans) break;
    CarmenScan c{record.scan, record.T_world_laser};
    c.scan.range_min_m = 0.05f;  // the matcher tests' sensor limits
    c.scan.range_max_m = 50.f;
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace cairn::agent::testing
