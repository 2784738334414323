#include "tools/eval/coverage_eval.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include "common/errors.h"
#include "common/yaml_config.h"

namespace cairn::eval {
namespace {

constexpr uint8_t kUnknownPixel = 205;  // OccupancyGrid::to_image

/// Next header token of a PGM, skipping whitespace and '#' comments.
std::string token(std::istream& in) {
  std::string t;
  char c;
  while (in.get(c)) {
    if (c == '#') {
      std::string rest;
      std::getline(in, rest);
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      if (!t.empty()) return t;
    } else {
      t += c;
    }
  }
  return t;
}

}  // namespace

std::optional<uint8_t> MapImage::at(const Eigen::Vector2d& p_m) const {
  const int col = int(std::floor((p_m.x() - origin_m.x()) / resolution_m));
  const int row = int(std::floor((p_m.y() - origin_m.y()) / resolution_m));
  if (col < 0 || row < 0 || col >= width || row >= height) return std::nullopt;
  return pixels[size_t(height - 1 - row) * size_t(width) + size_t(col)];
}

Eigen::Vector2d MapImage::centre_m(int col, int row_from_bottom) const {
  return origin_m + resolution_m * Eigen::Vector2d(col + 0.5, row_from_bottom + 0.5);
}

MapImage read_map_image(const std::string& yaml_path) {
  const YamlConfig cfg = YamlConfig::load(yaml_path);
  MapImage m;
  m.resolution_m = cfg.require<double>("resolution");
  const std::vector<double> origin = cfg.require<std::vector<double>>("origin");
  if (!(m.resolution_m > 0) || origin.size() < 2 || !std::isfinite(origin[0]) || !std::isfinite(origin[1])) {
    throw InputError(yaml_path + ": resolution must be > 0 and origin [x, y, yaw] finite");
  }
  m.origin_m = {origin[0], origin[1]};
  const std::string image =
      (std::filesystem::path(yaml_path).parent_path() / cfg.require<std::string>("image")).string();
  std::ifstream in(image, std::ios::binary);
  if (!in) throw InputError(image + ": cannot open file");
  if (token(in) != "P5") throw InputError(image + ": not a binary PGM (P5)");
  try {
    m.width = std::stoi(token(in));
    m.height = std::stoi(token(in));
    if (std::stoi(token(in)) != 255) throw InputError(image + ": max value must be 255");
  } catch (const std::logic_error&) {
    throw InputError(image + ": malformed PGM header");
  }
  if (m.width <= 0 || m.height <= 0 || m.width > 100000 || m.height > 100000) {
    throw InputError(image + ": image size out of range");
  }
  m.pixels.resize(size_t(m.width) * size_t(m.height));
  in.read(reinterpret_cast<char*>(m.pixels.data()), std::streamsize(m.pixels.size()));
  if (in.gcount() != std::streamsize(m.pixels.size())) throw InputError(image + ": truncated pixel data");
  return m;
}

std::optional<CoverageScore> evaluate_coverage(const std::string& ground_truth_dir, const std::string& results_dir,
                                               const SE2& T_world_map) {
  const std::string truth_yaml = ground_truth_dir + "/gt_reachable.yaml";
  if (!std::filesystem::exists(truth_yaml)) return std::nullopt;
  const MapImage truth = read_map_image(truth_yaml);
  const MapImage map = read_map_image(results_dir + "/map.yaml");
  const SE2 T_map_world = T_world_map.inverse();
  CoverageScore s;
  const double cell_m2 = truth.resolution_m * truth.resolution_m;
  for (int r = 0; r < truth.height; ++r) {
    for (int c = 0; c < truth.width; ++c) {
      if (truth.pixels[size_t(truth.height - 1 - r) * size_t(truth.width) + size_t(c)] == 0) continue;
      s.reachable_m2 += cell_m2;
      const auto seen = map.at(T_map_world * truth.centre_m(c, r));
      if (seen && *seen != kUnknownPixel) s.covered_m2 += cell_m2;
    }
  }
  return s;
}

}  // namespace cairn::eval
