#include "common/carmen_log.h"

#include <zlib.h>

#include <cmath>
#include <limits>
#include <sstream>

#include "common/errors.h"

namespace cairn {
namespace {

/// Reads lines from plain or gzip files alike (gzread passes plain files through).
class LineReader {
 public:
  explicit LineReader(const std::string& path) : file_(gzopen(path.c_str(), "rb")) {}
  ~LineReader() {
    if (file_) gzclose(file_);
  }
  bool ok() const { return file_ != nullptr; }
  bool next(std::string* line) {
    line->clear();
    char buf[8192];
    while (gzgets(file_, buf, sizeof(buf))) {
      line->append(buf);
      if (!line->empty() && line->back() == '\n') {
        line->pop_back();
        if (!line->empty() && line->back() == '\r') line->pop_back();
        return true;
      }
    }
    return !line->empty();
  }

 private:
  gzFile file_;
};

class Fields {
 public:
  Fields(const std::string& line, const std::string& where) : ss_(line), where_(where) { ss_ >> type_; }
  const std::string& type() const { return type_; }
  double number(const char* what) {
    std::string token;
    if (!(ss_ >> token)) throw InputError(where_ + ": " + type_ + " record ends before " + what + " (truncated?)");
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0') {
      throw InputError(where_ + ": " + type_ + " field " + what + " is not a number: '" + token + "'");
    }
    return v;
  }
  /// A time in seconds, as a stamp (refused beyond kMaxStampSec or NaN).
  StampNs stamp(const char* what) {
    const double t_s = number(what);
    if (!stamp_sec_in_range(t_s)) {
      throw InputError(where_ + ": " + type_ + " " + what + " must be a time within +-9e9 s, got " +
                       std::to_string(t_s));
    }
    return sec_to_ns(t_s);
  }
  int count(const char* what, int max) {
    const double v = number(what);
    if (v < 0 || v > max || v != std::floor(v)) {
      throw InputError(where_ + ": " + type_ + " " + what + " must be a whole number 0.." + std::to_string(max));
    }
    return int(v);
  }
  SE2 pose(const char* what) {
    const double x = number(what), y = number(what), th = number(what);
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(th)) {
      throw InputError(where_ + ": " + type_ + " " + what + " is not finite");
    }
    return SE2(x, y, th);
  }

 private:
  std::istringstream ss_;
  std::string where_;
  std::string type_;
};

float to_range(double r, const CarmenReadOptions& o) {
  if (std::isnan(r)) return std::numeric_limits<float>::quiet_NaN();
  if (r >= o.no_return_range_m) return std::numeric_limits<float>::infinity();
  return float(r);
}

CarmenScan read_flaser(Fields& f, const CarmenReadOptions& o) {
  CarmenScan s;
  const int n = f.count("num_readings", 4096);
  s.scan.ranges_m.reserve(n);
  for (int i = 0; i < n; ++i) s.scan.ranges_m.push_back(to_range(f.number("range"), o));
  const double step_deg = n >= 360 ? 0.5 : 1.0;
  s.scan.angle_min_rad = float(-M_PI / 2);
  s.scan.angle_increment_rad = float(step_deg * M_PI / 180.0);
  s.scan.range_min_m = o.range_min_m;
  s.scan.range_max_m = o.no_return_range_m;
  s.T_world_laser = f.pose("x y theta");
  s.T_odom_laser = f.pose("odom_x odom_y odom_theta");
  s.stamp_ns = f.stamp("ipc_timestamp");
  return s;
}

CarmenScan read_robotlaser(Fields& f, const CarmenReadOptions& o) {
  CarmenScan s;
  f.number("laser_type");
  const double start = f.number("start_angle"), fov = f.number("field_of_view");
  const double res = f.number("angular_resolution"), max_range = f.number("maximum_range");
  f.number("accuracy");
  f.number("remission_mode");
  const int n = f.count("num_readings", 4096);
  for (int i = 0; i < n; ++i) s.scan.ranges_m.push_back(to_range(f.number("range"), o));
  const int m = f.count("num_remissions", 4096);
  for (int i = 0; i < m; ++i) f.number("remission");
  s.scan.angle_min_rad = float(start);
  s.scan.angle_increment_rad = float(n > 1 && fov > 0 ? fov / (n - 1) : res);
  s.scan.range_min_m = o.range_min_m;
  s.scan.range_max_m = float(std::min<double>(max_range, o.no_return_range_m));
  s.T_world_laser = f.pose("laser_pose");
  s.T_odom_laser = f.pose("robot_pose");  // ROBOTLASER1 carries one (odometry) pose pair
  for (const char* what : {"laser_tv", "laser_rv", "forward_safety_dist", "side_safety_dist", "turn_axis"}) {
    f.number(what);
  }
  s.stamp_ns = f.stamp("ipc_timestamp");
  return s;
}

}  // namespace

bool is_corrected_log_name(const std::string& path) {
  const std::string name = path.substr(path.find_last_of('/') + 1);
  return name.find("corrected") != std::string::npos || name.find(".gfs.log") != std::string::npos;
}

CarmenLog read_carmen_log(const std::string& path, const CarmenReadOptions& options) {
  LineReader reader(path);
  if (!reader.ok()) throw InputError(path + ": cannot open CARMEN log");
  CarmenLog log;
  std::string line;
  while (reader.next(&line)) {
    ++log.stats.lines;
    const std::string where = path + ":" + std::to_string(log.stats.lines);
    Fields f(line, where);
    const std::string& type = f.type();
    if (type.empty() || type[0] == '#' || type == "PARAM" || type == "NEFF" || type == "SYNC") {
      ++log.stats.ignored_records;
    } else if (type == "FLASER" || type == "ROBOTLASER1") {
      CarmenScan s = type == "FLASER" ? read_flaser(f, options) : read_robotlaser(f, options);
      s.scan.stamp_ns = s.stamp_ns;
      s.line = log.stats.lines;
      log.scans.push_back(std::move(s));
      ++log.stats.laser_records;
    } else if (type == "ODOM") {
      CarmenOdometry o;
      o.T_odom_base = f.pose("x y theta");
      o.linear_mps = f.number("tv");
      o.angular_radps = f.number("rv");
      f.number("accel");
      o.stamp_ns = f.stamp("ipc_timestamp");
      log.odometry.push_back(o);
      ++log.stats.odometry_records;
    } else {
      ++log.stats.unknown_records;
    }
  }
  return log;
}

}  // namespace cairn
