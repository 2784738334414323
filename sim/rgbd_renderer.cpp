#include "sim/rgbd_renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cairn::sim {
namespace {

constexpr double kNear = 0.02;  // metres: hits closer than this along the ray are ignored
constexpr double kInf = std::numeric_limits<double>::infinity();

enum class Surface { kNone, kWall, kFloor, kCeiling, kObject };

// Ray (o + t d) against an axis-aligned box of half extents `half` centred at the origin.
bool intersect_box(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& half, double* t,
                   Eigen::Vector3d* n) {
  double t_min = -kInf, t_max = kInf;
  int axis = -1;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(d[i]) < 1e-12) {
      if (std::abs(o[i]) > half[i]) return false;
      continue;
    }
    const double inv = 1.0 / d[i];
    double t1 = (-half[i] - o[i]) * inv, t2 = (half[i] - o[i]) * inv;
    if (t1 > t2) std::swap(t1, t2);
    if (t1 > t_min) {
      t_min = t1;
      axis = i;
    }
    t_max = std::min(t_max, t2);
    if (t_min > t_max) return false;
  }
  if (axis < 0 || t_min < kNear) return false;
  *t = t_min;
  *n = Eigen::Vector3d::Zero();
  (*n)[axis] = d[axis] > 0 ? -1.0 : 1.0;
  return true;
}

// Ray against a vertical cylinder of radius r, half height hz, centred at the origin.
bool intersect_cylinder(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double r, double hz, double* t,
                        Eigen::Vector3d* n) {
  double best = kInf;
  const double a = d.x() * d.x() + d.y() * d.y();
  if (a > 1e-12) {
    const double b = 2.0 * (o.x() * d.x() + o.y() * d.y());
    const double c = o.x() * o.x() + o.y() * o.y() - r * r;
    const double disc = b * b - 4.0 * a * c;
    if (disc >= 0.0) {
      const double t0 = (-b - std::sqrt(disc)) / (2.0 * a);
      if (t0 > kNear && std::abs(o.z() + t0 * d.z()) <= hz) {
        best = t0;
        *n = Eigen::Vector3d(o.x() + t0 * d.x(), o.y() + t0 * d.y(), 0.0) / r;
      }
    }
  }
  if (std::abs(d.z()) > 1e-12) {
    for (const double zc : {-hz, hz}) {
      const double tc = (zc - o.z()) / d.z();
      if (tc <= kNear || tc >= best) continue;
      const double px = o.x() + tc * d.x(), py = o.y() + tc * d.y();
      if (px * px + py * py <= r * r) {
        best = tc;
        *n = Eigen::Vector3d(0, 0, zc > 0 ? 1.0 : -1.0);
      }
    }
  }
  if (best == kInf) return false;
  *t = best;
  return true;
}

bool intersect_sphere(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double r, double* t, Eigen::Vector3d* n) {
  const double a = d.squaredNorm(), b = 2.0 * o.dot(d), c = o.squaredNorm() - r * r;
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return false;
  const double t0 = (-b - std::sqrt(disc)) / (2.0 * a);
  if (t0 <= kNear) return false;
  *t = t0;
  *n = (o + t0 * d) / r;
  return true;
}

uint8_t to_u8(double v) { return uint8_t(std::lround(std::clamp(v, 0.0, 255.0))); }

// Small deterministic texture offset in [-amplitude, amplitude] for a cell.
double texture(int a, int b, int c, double amplitude) {
  uint32_t h = uint32_t(a) * 73856093u ^ uint32_t(b) * 19349663u ^ uint32_t(c) * 83492791u;
  h ^= h >> 13;
  h *= 0x5bd1e995u;
  h ^= h >> 15;
  return amplitude * (double(h % 1001) / 500.0 - 1.0);
}

}  // namespace

struct RgbdRenderer::Hit {
  Surface surface = Surface::kNone;
  double t = kInf;  ///< ray parameter = z-depth (the camera ray has unit optical z component)
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  const WorldObject* object = nullptr;  ///< the object hit (kObject)
};

struct RgbdRenderer::ObjectView {
  const WorldObject* object = nullptr;
  int u_min = 0, u_max = -1, v_min = 0, v_max = -1;
  Eigen::Vector3d o_local;  ///< camera centre in the object frame
  double cos_yaw = 1, sin_yaw = 0;
};

Eigen::Isometry3d RgbdRenderer::camera_mount(const CameraOptions& options) {
  Eigen::Matrix3d R0;
  R0.col(0) = Eigen::Vector3d(0, -1, 0);  // optical x (right) = base -y
  R0.col(1) = Eigen::Vector3d(0, 0, -1);  // optical y (down) = base -z
  R0.col(2) = Eigen::Vector3d(1, 0, 0);   // optical z (forward) = base x
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(options.pitch_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()) * R0;
  T.translation() = Eigen::Vector3d(options.forward_offset_m, 0.0, options.height_m);
  return T;
}

CameraIntrinsics RgbdRenderer::intrinsics_of(const CameraOptions& options) {
  CameraIntrinsics k;
  k.width = options.width;
  k.height = options.height;
  k.fx = 0.5 * options.width / std::tan(0.5 * options.hfov_deg * M_PI / 180.0);
  k.fy = k.fx;
  k.cx = 0.5 * (options.width - 1);
  k.cy = 0.5 * (options.height - 1);
  k.depth_scale_m = 0.001;
  return k;
}

RgbdRenderer::RgbdRenderer(const CameraOptions& options, FloorPlan plan, double wall_height_m,
                           std::vector<WorldObject> objects)
    : options_(options),
      plan_(std::move(plan)),
      wall_height_m_(wall_height_m),
      objects_(std::move(objects)),
      intrinsics_(intrinsics_of(options)),
      T_base_camera_(camera_mount(options)) {}

std::vector<RgbdRenderer::ObjectView> RgbdRenderer::visible_objects(const std::vector<WorldObject>& scene,
                                                                    const Eigen::Isometry3d& T_world_camera) const {
  std::vector<ObjectView> views;
  const Eigen::Isometry3d T_camera_world = T_world_camera.inverse();
  const Eigen::Vector3d c = T_world_camera.translation();
  const CameraIntrinsics& k = intrinsics_;
  for (const WorldObject& obj : scene) {
    const Eigen::Matrix3d R = Eigen::AngleAxisd(obj.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Vector3d half = 0.5 * obj.size_m;
    double u0 = kInf, u1 = -kInf, v0 = kInf, v1 = -kInf, z_min = kInf;
    bool behind = false;
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3d s((corner & 1) ? 1 : -1, (corner & 2) ? 1 : -1, (corner & 4) ? 1 : -1);
      const Eigen::Vector3d p = T_camera_world * (obj.center_m + R * half.cwiseProduct(s));
      z_min = std::min(z_min, p.z());
      if (p.z() < kNear) {
        behind = true;
        continue;
      }
      u0 = std::min(u0, k.fx * p.x() / p.z() + k.cx);
      u1 = std::max(u1, k.fx * p.x() / p.z() + k.cx);
      v0 = std::min(v0, k.fy * p.y() / p.z() + k.cy);
      v1 = std::max(v1, k.fy * p.y() / p.z() + k.cy);
    }
    if (u0 == kInf && behind) continue;  // entirely behind the camera
    if (z_min > options_.render_range_m) continue;
    ObjectView view;
    view.object = &obj;
    view.u_min = behind ? 0 : std::max(0, int(std::floor(u0)) - 1);
    view.u_max = behind ? k.width - 1 : std::min(k.width - 1, int(std::ceil(u1)) + 1);
    view.v_min = behind ? 0 : std::max(0, int(std::floor(v0)) - 1);
    view.v_max = behind ? k.height - 1 : std::min(k.height - 1, int(std::ceil(v1)) + 1);
    if (view.u_min > view.u_max || view.v_min > view.v_max) continue;
    view.cos_yaw = std::cos(obj.yaw_rad);
    view.sin_yaw = std::sin(obj.yaw_rad);
    const Eigen::Vector3d o = c - obj.center_m;
    view.o_local = Eigen::Vector3d(view.cos_yaw * o.x() + view.sin_yaw * o.y(),
                                   -view.sin_yaw * o.x() + view.cos_yaw * o.y(), o.z());
    views.push_back(view);
  }
  return views;
}

RgbdRenderer::Hit RgbdRenderer::background(const Eigen::Vector3d& c, const Eigen::Vector3d& d, const RayHit& wall,
                                           double horizontal_norm) const {
  Hit h;
  if (wall.hit && horizontal_norm > 1e-12) {
    const double t_w = wall.range_m / horizontal_norm;
    const double z = c.z() + d.z() * t_w;
    if (z >= 0.0 && z <= wall_height_m_) {
      h.surface = Surface::kWall;
      h.t = t_w;
      h.normal = wall.x_face ? Eigen::Vector3d(d.x() > 0 ? -1 : 1, 0, 0) : Eigen::Vector3d(0, d.y() > 0 ? -1 : 1, 0);
      h.point = Eigen::Vector3d(wall.col, wall.row, z);  // cell indices + height, for texture
      return h;
    }
  }
  if (d.z() < -1e-12) {
    h.surface = Surface::kFloor;
    h.t = -c.z() / d.z();
    h.normal = Eigen::Vector3d::UnitZ();
  } else if (d.z() > 1e-12) {
    h.surface = Surface::kCeiling;
    h.t = (wall_height_m_ - c.z()) / d.z();
    h.normal = -Eigen::Vector3d::UnitZ();
  }
  if (h.surface != Surface::kNone) h.point = c + h.t * d;
  return h;
}

void RgbdRenderer::shade_pixel(const Hit& h, const Eigen::Vector3d& d, uint8_t* rgb) {
  const Eigen::Vector3d view = -d.normalized();
  const double facing = std::abs(h.normal.dot(view));
  double r = 0, g = 0, b = 0;
  switch (h.surface) {
    case Surface::kNone:
      break;
    case Surface::kWall: {
      const double v = 165.0 * (0.5 + 0.5 * facing) +
                       texture(int(h.point.x()), int(h.point.y()), int(std::floor(h.point.z() / 0.2)), 12.0);
      r = g = b = v;
      break;
    }
    case Surface::kFloor: {
      const int tile = int(std::floor(h.point.x() / 0.5)) + int(std::floor(h.point.y() / 0.5));
      const double v = (0.75 + 0.25 * facing) + ((tile & 1) ? 0.06 : -0.06);
      r = 128 * v;
      g = 115 * v;
      b = 102 * v;
      break;
    }
    case Surface::kCeiling:
      r = 72;
      g = 72;
      b = 78;
      break;
    case Surface::kObject: {
      const auto& col = h.object->color_rgb;
      const double shade = 0.35 + 0.5 * std::max(0.0, h.normal.dot(view)) + 0.15 * std::max(0.0, h.normal.z());
      r = col[0] * shade;
      g = col[1] * shade;
      b = col[2] * shade;
      break;
    }
  }
  rgb[0] = to_u8(r);
  rgb[1] = to_u8(g);
  rgb[2] = to_u8(b);
}

void RgbdRenderer::intersect(const ObjectView& view, const Eigen::Vector3d& d, Hit* hit) const {
  const WorldObject& obj = *view.object;
  const Eigen::Vector3d d_local(view.cos_yaw * d.x() + view.sin_yaw * d.y(),
                                -view.sin_yaw * d.x() + view.cos_yaw * d.y(), d.z());
  double t = kInf;
  Eigen::Vector3d n_local;
  bool found = false;
  switch (obj.shape) {
    case ObjectShape::kBox:
      found = intersect_box(view.o_local, d_local, 0.5 * obj.size_m, &t, &n_local);
      break;
    case ObjectShape::kCylinder:
      found = intersect_cylinder(view.o_local, d_local, 0.5 * obj.size_m.x(), 0.5 * obj.size_m.z(), &t, &n_local);
      break;
    case ObjectShape::kSphere:
      found = intersect_sphere(view.o_local, d_local, 0.5 * obj.size_m.x(), &t, &n_local);
      break;
  }
  if (!found || t >= hit->t) return;
  hit->surface = Surface::kObject;
  hit->t = t;
  hit->object = view.object;
  hit->normal = Eigen::Vector3d(view.cos_yaw * n_local.x() - view.sin_yaw * n_local.y(),
                                view.sin_yaw * n_local.x() + view.cos_yaw * n_local.y(), n_local.z());
}

RgbdFrame RgbdRenderer::render(const SE2& T_world_base, StampNs stamp_ns, std::mt19937_64& rng,
                               std::vector<int>* object_ids, const std::vector<WorldObject>& movers) const {
  const CameraIntrinsics& k = intrinsics_;
  RgbdFrame frame;
  frame.stamp_ns = stamp_ns;
  frame.intrinsics = k;
  frame.T_base_camera = T_base_camera_;
  const size_t n_pixels = size_t(k.width) * size_t(k.height);
  frame.rgb.assign(3 * n_pixels, 0);
  frame.depth.assign(n_pixels, 0);
  if (object_ids) object_ids->assign(n_pixels, -1);

  const Eigen::Isometry3d T_world_camera = T_world_base.to_isometry3() * T_base_camera_;
  const Eigen::Matrix3d R = T_world_camera.linear();
  const Eigen::Vector3d c = T_world_camera.translation();
  std::vector<WorldObject> with_movers;
  if (!movers.empty()) {
    with_movers = objects_;
    with_movers.insert(with_movers.end(), movers.begin(), movers.end());
  }
  const std::vector<ObjectView> views = visible_objects(movers.empty() ? objects_ : with_movers, T_world_camera);
  // Columns are vertical planes unless the optical y axis has a horizontal component (pitch).
  const bool cast_per_pixel = R.col(1).head<2>().norm() > 1e-9;
  std::vector<const ObjectView*> column_views;
  std::normal_distribution<double> unit(0.0, 1.0);
  const double max_depth_m = options_.max_depth_m;

  for (int u = 0; u < k.width; ++u) {
    const Eigen::Vector3d d_u = R.col(0) * ((u - k.cx) / k.fx) + R.col(2);
    column_views.clear();
    for (const ObjectView& v : views) {
      if (u >= v.u_min && u <= v.u_max) column_views.push_back(&v);
    }
    RayHit wall;
    for (int v = 0; v < k.height; ++v) {
      const Eigen::Vector3d d = d_u + R.col(1) * ((v - k.cy) / k.fy);
      const double s = d.head<2>().norm();
      if (v == 0 || cast_per_pixel) {
        wall = s > 1e-12 ? plan_.cast_ray_dir(c.head<2>(), d.head<2>() / s, options_.render_range_m) : RayHit{};
      }
      Hit hit = background(c, d, wall, s);
      for (const ObjectView* view : column_views) {
        if (v >= view->v_min && v <= view->v_max) intersect(*view, d, &hit);
      }
      const size_t idx = size_t(v) * size_t(k.width) + size_t(u);
      shade_pixel(hit, d, &frame.rgb[3 * idx]);
      if (object_ids && hit.surface == Surface::kObject) (*object_ids)[idx] = hit.object->id;
      if (hit.surface != Surface::kNone && hit.t <= max_depth_m) {
        const double z_m = hit.t + options_.depth_noise_sd_m * unit(rng);
        frame.depth[idx] = uint16_t(std::clamp(std::lround(z_m * 1000.0), 1L, 65535L));
      }
    }
  }
  if (options_.rgb_noise_sd > 0.0) {
    for (uint8_t& px : frame.rgb) px = to_u8(px + options_.rgb_noise_sd * unit(rng));
  }
  return frame;
}

}  // namespace cairn::sim
