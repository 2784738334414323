#include "tools/mission/radio_map.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <vector>

#include "common/errors.h"
#include "common/trajectory.h"
#include "tools/mission/radio_follower.h"

namespace cairn::mission {
namespace {

constexpr double kCellM = 0.25;   ///< the coverage is evaluated on this grid
constexpr int kMinWidthPx = 800;  ///< small worlds are drawn larger, so that the legend fits

/// Each robot's link state at every radio reading: (t_s, up), in time order.
std::map<int, std::vector<std::pair<double, bool>>> read_link_states(const std::string& csv) {
  std::map<int, std::vector<std::pair<double, bool>>> states;
  std::ifstream in(csv);
  std::string line;
  while (std::getline(in, line)) {
    if (const auto row = parse_radio_row(line)) states[row->robot].push_back({row->t_s, row->up});
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
    Trajectory track;
    try {
      track = read_trajectory_csv(ground_truth_dir + "/gt_robot" + std::to_string(robot.id.value) + ".csv");
    } catch (const InputError&) {
      continue;  // no ground truth for this robot: its track is left out
    }
    const auto it = states.find(robot.id.value);
    cv::Point last(-1, -1);
    size_t k = 0;
    bool up = true;
    for (const StampedPose& p_true : track) {
      const double t_s = ns_to_sec(p_true.stamp_ns);
      while (it != states.end() && k < it->second.size() && it->second[k].first <= t_s) up = it->second[k++].second;
      const cv::Point p = px(p_true.pose.translation());
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
