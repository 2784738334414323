// The map image: occupancy grid (ROS map_server shades) scaled up, each robot's trajectory as a
// coloured polyline with keyframe dots, objects as class-coloured markers with labels, and each
// robot's next exploration goal as a dashed line from it to a target ring, over the saliency layer
// (orange, the plan's) when there is one.
#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <utility>

#include "base_station/core/saliency_layer.h"
#include "base_station/export/exporter.h"

namespace cairn::base {
namespace {

cv::Scalar robot_colour(RobotId robot) {
  static const cv::Scalar kPalette[] = {
      // BGR, distinct on light grey
      {200, 90, 20}, {30, 140, 30}, {150, 40, 160}, {20, 120, 200}, {120, 120, 0}, {90, 60, 140}};
  return kPalette[size_t(std::max(0, robot.value)) % (sizeof(kPalette) / sizeof(kPalette[0]))];
}

cv::Scalar class_colour(const std::string& class_name) {
  if (class_name == "victim") return {30, 30, 220};
  if (class_name == "hazard") return {0, 140, 255};
  if (class_name == "exit") return {40, 160, 40};
  return {180, 60, 60};
}

/// Maps global metres to image pixels of the scaled grid (row 0 = top = largest y).
struct PixelMapper {
  Eigen::Vector2d origin_m;
  double resolution_m;
  int height_cells;
  int scale;
  cv::Point operator()(const Eigen::Vector2d& p_m) const {
    const Eigen::Vector2d c = (p_m - origin_m) / resolution_m;
    return {int(std::lround(c.x() * scale)), int(std::lround((height_cells - c.y()) * scale))};
  }
};

/// Cells [col0, col1] x [row0, row1] (inclusive) worth drawing: the known cells plus a margin.
struct CellBox {
  int col0, row0, col1, row1;
};

CellBox known_box(const OccupancyGrid& grid, int margin_cells) {
  CellBox b{grid.width(), grid.height(), -1, -1};
  for (int r = 0; r < grid.height(); ++r) {
    for (int c = 0; c < grid.width(); ++c) {
      if (!grid.known(c, r)) continue;
      b.col0 = std::min(b.col0, c);
      b.col1 = std::max(b.col1, c);
      b.row0 = std::min(b.row0, r);
      b.row1 = std::max(b.row1, r);
    }
  }
  if (b.col1 < 0) return {0, 0, grid.width() - 1, grid.height() - 1};
  return {std::max(0, b.col0 - margin_cells), std::max(0, b.row0 - margin_cells),
          std::min(grid.width() - 1, b.col1 + margin_cells), std::min(grid.height() - 1, b.row1 + margin_cells)};
}

cv::Mat grid_image(const OccupancyGrid& grid, const CellBox& box, int scale) {
  const std::vector<uint8_t> cells = grid.to_image();  // top row first
  const cv::Mat gray(grid.height(), grid.width(), CV_8UC1, const_cast<uint8_t*>(cells.data()));
  const cv::Rect roi(box.col0, grid.height() - 1 - box.row1, box.col1 - box.col0 + 1, box.row1 - box.row0 + 1);
  cv::Mat bgr;
  cv::cvtColor(gray(roi), bgr, cv::COLOR_GRAY2BGR);
  cv::Mat scaled;
  cv::resize(bgr, scaled, cv::Size(), scale, scale, cv::INTER_NEAREST);
  return scaled;
}

void draw_trajectories(const MergedMap& merged, const PixelMapper& px, cv::Mat* img) {
  for (const auto& [robot, trajectory] : merged.trajectories) {
    std::vector<cv::Point> points;
    for (const StampedPose& p : trajectory) points.push_back(px(p.pose.translation()));
    const cv::Scalar colour = robot_colour(robot);
    if (points.size() >= 2) cv::polylines(*img, points, false, colour, 2, cv::LINE_AA);
    for (const cv::Point& p : points) cv::circle(*img, p, 3, colour, cv::FILLED, cv::LINE_AA);
    if (!points.empty()) {
      cv::putText(*img, "R" + std::to_string(robot.value), points.back() + cv::Point(6, -6), cv::FONT_HERSHEY_SIMPLEX,
                  0.6, colour, 2, cv::LINE_AA);
    }
  }
}

void draw_objects(const std::vector<GlobalObject>& objects, const PixelMapper& px, cv::Mat* img) {
  for (const GlobalObject& o : objects) {
    const cv::Point c = px(o.position_m.head<2>());
    const cv::Scalar colour = class_colour(o.class_name);
    cv::drawMarker(*img, c, colour, cv::MARKER_DIAMOND, 18, 3, cv::LINE_AA);
    char conf[16];
    std::snprintf(conf, sizeof(conf), " %.0f%%", 100.0 * o.confidence);
    const std::string label = o.class_name + conf;
    const cv::Point at = c + cv::Point(12, 5);
    cv::putText(*img, label, at, cv::FONT_HERSHEY_SIMPLEX, 0.55, {255, 255, 255}, 4, cv::LINE_AA);
    cv::putText(*img, label, at, cv::FONT_HERSHEY_SIMPLEX, 0.55, colour, 2, cv::LINE_AA);
  }
}

/// The saliency layer as an orange wash, stronger where more salient (cells of at least 0.1).
void draw_saliency(const SaliencyLayer& layer, const PixelMapper& px, cv::Mat* img) {
  for (int r = 0; r < layer.height(); ++r) {
    for (int c = 0; c < layer.width(); ++c) {
      const double v = layer.value(c, r);
      if (v < 0.1) continue;
      const Eigen::Vector2d half(0.5 * layer.cell_m(), 0.5 * layer.cell_m());
      const cv::Point a = px(layer.centre_m(c, r) - half), b = px(layer.centre_m(c, r) + half);
      const cv::Rect area = cv::Rect(a, b) & cv::Rect(0, 0, img->cols, img->rows);
      if (area.empty()) continue;
      cv::Mat cell = (*img)(area);  // blended in place (same size and type: no reallocation)
      cv::addWeighted(cell, 1.0 - 0.7 * v, cv::Mat(cell.size(), cell.type(), cv::Scalar(0, 150, 255)), 0.7 * v, 0.0,
                      cell);
    }
  }
}

void draw_goals(const MergedMap& merged, const ExplorationPlan& plan, const PixelMapper& px, cv::Mat* img) {
  for (const ExplorationGoal& g : plan.goals) {
    const Trajectory& t = merged.trajectory(g.robot);
    if (t.empty()) continue;
    const cv::Scalar colour = robot_colour(g.robot);
    const cv::Point from = px(t.back().pose.translation()), to = px(g.goal_m);
    const double length = std::hypot(to.x - from.x, to.y - from.y);
    for (double s = 0; s < length; s += 12) {  // dashes of 6 px
      const double e = std::min(length, s + 6);
      cv::line(*img, from + (to - from) * (s / length), from + (to - from) * (e / length), colour, 2, cv::LINE_AA);
    }
    cv::circle(*img, to, 9, colour, 2, cv::LINE_AA);
    cv::circle(*img, to, 3, colour, cv::FILLED, cv::LINE_AA);
    cv::putText(*img, "R" + std::to_string(g.robot.value) + " next", to + cv::Point(11, 4), cv::FONT_HERSHEY_SIMPLEX,
                0.45, colour, 1, cv::LINE_AA);
  }
}

/// Where the known part of `grid` lands in the image (scaled up to about png_min_size_px); nullopt for
/// an empty grid.
std::optional<std::pair<CellBox, PixelMapper>> image_frame(const OccupancyGrid& grid, const ExportOptions& options) {
  if (grid.width() == 0 || grid.height() == 0) return std::nullopt;
  const CellBox box = known_box(grid, int(std::ceil(0.5 / grid.resolution_m())));
  const int longest = std::max(box.col1 - box.col0 + 1, box.row1 - box.row0 + 1);
  const int scale =
      std::clamp((options.png_min_size_px + longest - 1) / longest, 1, std::max(1, options.png_max_scale));
  const Eigen::Vector2d origin_m = grid.origin_m() + grid.resolution_m() * Eigen::Vector2d(box.col0, box.row0);
  return std::make_pair(box, PixelMapper{origin_m, grid.resolution_m(), box.row1 - box.row0 + 1, scale});
}

}  // namespace

MapImageGeometry map_image_geometry(const OccupancyGrid& grid, const ExportOptions& options) {
  MapImageGeometry g;
  const auto frame = image_frame(grid, options);
  if (!frame) return g;
  const auto& [box, px] = *frame;
  g.valid = true;
  g.m_per_px = px.resolution_m / px.scale;
  g.x0_m = px.origin_m.x();
  g.y_top_m = px.origin_m.y() + px.height_cells * px.resolution_m;
  g.width_px = (box.col1 - box.col0 + 1) * px.scale;
  g.height_px = px.height_cells * px.scale;
  return g;
}

namespace {

cv::Mat render(const MergedMap& merged, const ExportOptions& options, const ExplorationPlan* plan) {
  const auto frame = image_frame(*merged.grid, options);
  if (!frame) {
    cv::Mat blank(240, 320, CV_8UC3, cv::Scalar(205, 205, 205));
    cv::putText(blank, "no map yet", {90, 125}, cv::FONT_HERSHEY_SIMPLEX, 0.8, {60, 60, 60}, 2, cv::LINE_AA);
    return blank;
  }
  const auto& [box, px] = *frame;
  cv::Mat img = grid_image(*merged.grid, box, px.scale);
  if (plan && plan->saliency) draw_saliency(*plan->saliency, px, &img);
  draw_trajectories(merged, px, &img);
  draw_objects(merged.objects, px, &img);
  if (plan) draw_goals(merged, *plan, px, &img);
  return img;
}

/// A robot's own map: the map image of its frame, its entry point marked, and a banner that says
/// it is not on the global map yet.
cv::Mat render_robot_frame(const RobotFrameMap& m, const ExportOptions& options) {
  MergedMap view;
  view.grid = &m.grid;
  view.trajectories[m.robot] = m.trajectory;
  view.objects = m.objects;
  cv::Mat img = render(view, options, nullptr);
  if (const auto frame = image_frame(m.grid, options)) {
    const cv::Point entry = frame->second(Eigen::Vector2d::Zero());
    cv::drawMarker(img, entry, robot_colour(m.robot), cv::MARKER_TRIANGLE_UP, 20, 3, cv::LINE_AA);
    cv::putText(img, "entry", entry + cv::Point(12, 16), cv::FONT_HERSHEY_SIMPLEX, 0.5, robot_colour(m.robot), 1,
                cv::LINE_AA);
  }
  const std::string banner = "robot " + std::to_string(m.robot.value) + ", not yet placed: its own map";
  cv::Mat framed;  // the banner above the map, not over it
  cv::copyMakeBorder(img, framed, 28, 0, 0, 0, cv::BORDER_CONSTANT, cv::Scalar(40, 40, 40));
  cv::putText(framed, banner, {8, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.6, {255, 255, 255}, 1, cv::LINE_AA);
  return framed;
}

}  // namespace

std::vector<uint8_t> render_robot_frame_png(const RobotFrameMap& map, const ExportOptions& options) {
  std::vector<uint8_t> png;
  try {
    if (!cv::imencode(".png", render_robot_frame(map, options), png)) png.clear();
  } catch (const cv::Exception&) {
    png.clear();
  }
  return png;
}

bool write_robot_frame_png(const RobotFrameMap& map, const std::string& path, const ExportOptions& options,
                           std::string* error) {
  try {
    if (cv::imwrite(path, render_robot_frame(map, options))) return true;
    *error = "cv::imwrite failed";
  } catch (const cv::Exception& e) {
    *error = std::string("OpenCV: ") + e.what();
  }
  return false;
}

std::vector<uint8_t> render_map_png(const MergedMap& merged, const ExportOptions& options,
                                    const ExplorationPlan* plan) {
  std::vector<uint8_t> png;
  try {
    if (!cv::imencode(".png", render(merged, options, plan), png)) png.clear();
  } catch (const cv::Exception&) {
    png.clear();
  }
  return png;
}

bool write_map_png(const MergedMap& merged, const std::string& path, const ExportOptions& options, std::string* error,
                   const ExplorationPlan* plan) {
  try {
    if (cv::imwrite(path, render(merged, options, plan))) return true;
    *error = "cv::imwrite failed";
  } catch (const cv::Exception& e) {
    *error = std::string("OpenCV: ") + e.what();
  }
  return false;
}

bool write_rgb_png(int width, int height, const std::vector<uint8_t>& rgb, const std::string& path,
                   std::string* error) {
  if (width <= 0 || height <= 0 || rgb.size() != size_t(width) * size_t(height) * 3) {
    *error = "image of " + std::to_string(width) + " x " + std::to_string(height) + " px needs " +
             std::to_string(size_t(std::max(width, 0)) * size_t(std::max(height, 0)) * 3) + " bytes, got " +
             std::to_string(rgb.size());
    return false;
  }
  try {
    cv::Mat bgr;
    cv::cvtColor(cv::Mat(height, width, CV_8UC3, const_cast<uint8_t*>(rgb.data())), bgr, cv::COLOR_RGB2BGR);
    if (cv::imwrite(path, bgr)) return true;
    *error = "cv::imwrite failed: " + path;
  } catch (const cv::Exception& e) {
    *error = std::string("OpenCV: ") + e.what();
  }
  return false;
}

}  // namespace cairn::base
