#include "tools/mission/exploration_report.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace cairn::mission {

ExplorationFigures exploration_figures(const nlohmann::json& series, double final_coverage, int victims, double end_s) {
  ExplorationFigures f;
  if (!series.is_array() || series.empty()) return f;
  const double known_end_m2 = series.back().value("known_m2", 0.0);
  if (!(known_end_m2 > 0)) return f;
  size_t next = 0;
  double known_m2 = 0;
  int found = 0;
  const int seconds = int(std::ceil(std::max(0.0, end_s)));
  for (int t = 0; t <= seconds; ++t) {
    // The newest sample at or before t (the base samples when it plans, about every 2 s).
    while (next < series.size() && series[next].value("t_s", 0.0) <= t) {
      known_m2 = series[next].value("known_m2", 0.0);
      found = series[next].value("victims", 0);
      ++next;
    }
    const double coverage = std::min(1.0, known_m2 / known_end_m2) * final_coverage;
    f.per_second.push_back({{"t_s", t}, {"known_m2", known_m2}, {"coverage", coverage}, {"victims", found}});
    if (!f.t50_s && coverage >= 0.5) f.t50_s = t;
    if (!f.t90_s && coverage >= 0.9) f.t90_s = t;
    if (!f.t99_s && coverage >= 0.99) f.t99_s = t;
    if (!f.all_victims_s && victims > 0 && found >= victims) f.all_victims_s = t;
    f.final_coverage = coverage;
  }
  return f;
}

// Hand-drawn with OpenCV's primitives: a few lines on shared time axes need no plotting library,
// and none is packaged for C++ here.
bool write_coverage_plot(const std::vector<CoverageLine>& lines, int victims, const std::string& title,
                         const std::string& path) {
  const int W = 900, H = 420, left = 70, right = 70, top = 40, bottom = 50;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  double t_max = 1.0;
  for (const CoverageLine& l : lines) {
    if (!l.per_second.empty()) t_max = std::max(t_max, l.per_second.back().value("t_s", 1.0));
  }
  const int pw = W - left - right, ph = H - top - bottom;
  auto px = [&](double t) { return left + int(std::lround(pw * t / t_max)); };
  auto py = [&](double fraction) { return top + int(std::lround(ph * (1.0 - fraction))); };
  const cv::Scalar grey(210, 210, 210), black(40, 40, 40);
  const cv::Scalar palette[] = {{200, 90, 20}, {40, 40, 210}, {40, 150, 40}, {150, 40, 150}, {0, 140, 200}};
  for (int p = 0; p <= 100; p += 25) {
    cv::line(img, {left, py(p / 100.0)}, {W - right, py(p / 100.0)}, grey, 1);
    cv::putText(img, std::to_string(p) + "%", {8, py(p / 100.0) + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.45, black, 1,
                cv::LINE_AA);
  }
  const double step_s = t_max > 400 ? 100 : t_max > 100 ? 30 : 10;
  for (double t = 0; t <= t_max; t += step_s) {
    cv::line(img, {px(t), top}, {px(t), H - bottom}, grey, 1);
    cv::putText(img, std::to_string(int(t)) + " s", {px(t) - 12, H - bottom + 20}, cv::FONT_HERSHEY_SIMPLEX, 0.45,
                black, 1, cv::LINE_AA);
  }
  const int v_max = std::max(1, victims);
  for (int v = 0; v <= v_max; ++v) {
    cv::putText(img, std::to_string(v), {W - right + 10, py(double(v) / v_max) + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.45,
                black, 1, cv::LINE_AA);
  }
  cv::rectangle(img, {left, top}, {W - right, H - bottom}, black, 1);
  for (size_t i = 0; i < lines.size(); ++i) {
    const cv::Scalar colour = palette[i % (sizeof(palette) / sizeof(palette[0]))];
    std::vector<cv::Point> coverage, found;
    for (const auto& s : lines[i].per_second) {
      const double t = s.value("t_s", 0.0);
      coverage.emplace_back(px(t), py(s.value("coverage", 0.0)));
      const int y = py(double(s.value("victims", 0)) / v_max);
      if (!found.empty()) found.emplace_back(px(t), found.back().y);  // a step line
      found.emplace_back(px(t), y);
    }
    if (!coverage.empty()) cv::polylines(img, coverage, false, colour, 2, cv::LINE_AA);
    if (!found.empty()) cv::polylines(img, found, false, colour, 1, cv::LINE_AA);
    cv::putText(img, lines[i].label, {left + 10, top + 20 + 20 * int(i)}, cv::FONT_HERSHEY_SIMPLEX, 0.5, colour, 1,
                cv::LINE_AA);
  }
  cv::putText(img, title + "  (thick: coverage of the explorable area, left; thin: victims found, right)", {left, 25},
              cv::FONT_HERSHEY_SIMPLEX, 0.5, black, 1, cv::LINE_AA);
  cv::putText(img, "mission time", {W / 2 - 40, H - 10}, cv::FONT_HERSHEY_SIMPLEX, 0.5, black, 1, cv::LINE_AA);
  try {
    return cv::imwrite(path, img);
  } catch (const cv::Exception&) {
    return false;
  }
}

}  // namespace cairn::mission
