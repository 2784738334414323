#include "tools/mission/radio_map.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <vector>

namespace cairn::mission {
namespace {

constexpr double kCellM = 0.25;   ///< the coverage is evaluated on this grid
constexpr int kMinWidthPx = 800;  ///< small worlds are drawn larger, so that the legend fits

/// Each robot's link state changes: (t_s, up), in time order.
std::map<int, std::vector<std::pair<double, bool>>> read_link_states(const std::string& csv) {
  std::map<int, std::vector<std::pair<double, bool>>> states;
  std::ifstream in(csv);
  std::string line;
  while (std::getline(in, line)) {
    double t_s = 0, dbm = 0;
    int robot = 0, walls = 0, up = 0;
    if (std::sscanf(line.c_str(), "%lf,%d,%lf,%d,%d", &t_s, &robot, &dbm, &walls, &up) != 5) continue;
    states[robot].push_back({t_s, up == 1});
  }
  return states;
}

/// Link colour (BGR) for a margin above the receiver's sensitivity: red below it, yellow at the
/// edge, green with 20 dB to spare.
cv::Vec3b margin_colour(double margin_db) {
  if (!(margin_db >= 0)) return {170, 170, 250};
  const double a = std::clamp(margin_db / 20.0, 0.0, 1.0);
  return cv::Vec3b(uchar(150 + 40 * a), uchar(235), uchar(250 - 90 * a));
}

}  // namespace

bool write_radio_map(const sim::World& world, const std::string& radio_csv, const std::string& ground_truth_dir,
                     const std::string& png_path) {
  const sim::FloorPlan& plan = world.floor_plan;
  const Eigen::Vector2d size_m = plan.max_m() - plan.origin_m();
  // Whole pixels per coverage cell: 20 px a metre, more for a small world.
  const double kPixelsPerM = std::max(20.0, std::ceil(kMinWidthPx / size_m.x() * kCellM) / kCellM);
  const int width = int(std::ceil(size_m.x() * kPixelsPerM)), height = int(std::ceil(size_m.y() * kPixelsPerM));
  cv::Mat img(height + 50, width, CV_8UC3, cv::Scalar(255, 255, 255));
  auto px = [&](const Eigen::Vector2d& p_m) {
    return cv::Point(int((p_m.x() - plan.origin_m().x()) * kPixelsPerM),
                     height - 1 - int((p_m.y() - plan.origin_m().y()) * kPixelsPerM));
  };
  // Coverage, one cell at a time, then the walls over it.
  const int cell_px = int(kCellM * kPixelsPerM);
  for (int y = 0; y < height; y += cell_px) {
    for (int x = 0; x < width; x += cell_px) {
      const Eigen::Vector2d p_m =
          plan.origin_m() + Eigen::Vector2d(x + 0.5 * cell_px, height - y - 0.5 * cell_px) / kPixelsPerM;
      const double margin_db = sim::radio_reading(plan, world.radio, p_m).received_dbm - world.radio.sensitivity_dbm;
      img(cv::Rect(x, y, std::min(cell_px, width - x), std::min(cell_px, height - y))) = margin_colour(margin_db);
    }
  }
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const Eigen::Vector2d p_m = plan.origin_m() + Eigen::Vector2d(x + 0.5, height - y - 0.5) / kPixelsPerM;
      if (plan.wall_at(p_m)) img.at<cv::Vec3b>(y, x) = cv::Vec3b(60, 60, 60);
    }
  }
  // The robots' tracks: thin while in range, thick red where the link was cut.
  const auto states = read_link_states(radio_csv);
  for (const sim::RobotSpec& robot : world.robots) {
    std::ifstream in(ground_truth_dir + "/gt_robot" + std::to_string(robot.id.value) + ".csv");
    const auto it = states.find(robot.id.value);
    std::string line;
    std::getline(in, line);  // header
    cv::Point last(-1, -1);
    size_t k = 0;
    bool up = true;
    while (std::getline(in, line)) {
      long long stamp_ns = 0;
      double x = 0, y = 0, yaw = 0;
      if (std::sscanf(line.c_str(), "%lld,%lf,%lf,%lf", &stamp_ns, &x, &y, &yaw) != 4) continue;
      const double t_s = double(stamp_ns) * 1e-9;
      while (it != states.end() && k < it->second.size() && it->second[k].first <= t_s) up = it->second[k++].second;
      const cv::Point p = px({x, y});
      if (last.x >= 0) cv::line(img, last, p, up ? cv::Scalar(150, 90, 40) : cv::Scalar(30, 30, 220), up ? 1 : 3);
      last = p;
    }
  }
  for (const Eigen::Vector2d& a : world.radio.antennas_m) {
    cv::circle(img, px(a), 7, cv::Scalar(200, 80, 0), cv::FILLED, cv::LINE_AA);
    cv::putText(img, "A", px(a) + cv::Point(-4, 4), cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(255, 255, 255), 1);
  }
  const cv::Scalar ink(40, 40, 40);
  cv::putText(img,
              "simulated radio (COST 231 multi-wall, " + std::to_string(int(world.radio.wall_loss_db)) +
                  " dB a wall): green in range, yellow at the edge, red out of range",
              {8, height + 20}, cv::FONT_HERSHEY_SIMPLEX, 0.45, ink, 1, cv::LINE_AA);
  cv::putText(img, "A: the team's antennas; robots' true tracks, thick red where their link was cut", {8, height + 40},
              cv::FONT_HERSHEY_SIMPLEX, 0.45, ink, 1, cv::LINE_AA);
  try {
    return cv::imwrite(png_path, img);
  } catch (const cv::Exception&) {
    return false;
  }
}

}  // namespace cairn::mission
