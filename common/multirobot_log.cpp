#include "common/multirobot_log.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <tuple>

#include "common/errors.h"

namespace cairn {
namespace {

constexpr const char* kHeader = "CAIRN_MRLOG";

/// The fields of one record, consumed left to right; every error names file:line and the field.
class Record {
 public:
  Record(const std::string& line, std::string where) : ss_(line), where_(std::move(where)) { ss_ >> type_; }
  const std::string& type() const { return type_; }
  const std::string& where() const { return where_; }

  [[noreturn]] void fail(const std::string& what) const { throw InputError(where_ + ": " + type_ + " " + what); }

  /// Any double, including inf and nan (the caller decides what is allowed).
  double any_number(const char* what) {
    std::string token;
    if (!(ss_ >> token)) fail("record ends before field " + std::string(what) + " (truncated?)");
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0') fail("field " + std::string(what) + " is not a number: '" + token + "'");
    return v;
  }
  double finite(const char* what) {
    const double v = any_number(what);
    if (!std::isfinite(v)) fail("field " + std::string(what) + " must be finite, got " + std::to_string(v));
    return v;
  }
  double positive(const char* what) {
    const double v = finite(what);
    if (v <= 0.0) fail("field " + std::string(what) + " must be > 0, got " + std::to_string(v));
    return v;
  }
  int integer(const char* what, int min, int max) {
    const double v = any_number(what);
    if (!(v >= min && v <= max) || v != std::floor(v)) {
      fail("field " + std::string(what) + " must be a whole number " + std::to_string(min) + ".." +
           std::to_string(max) + ", got " + std::to_string(v));
    }
    return int(v);
  }
  StampNs stamp() {
    const double t_s = finite("t_s");
    if (!stamp_sec_in_range(t_s)) fail("field t_s must be a time within +-9e9 s, got " + std::to_string(t_s));
    return sec_to_ns(t_s);
  }
  void end() {
    std::string extra;
    if (ss_ >> extra) fail("has unexpected trailing field '" + extra + "'");
  }

 private:
  std::istringstream ss_;
  std::string where_;
  std::string type_;
};

template <typename T>
void check_order(Record& r, const std::vector<T>& list, StampNs t, const char* what) {
  if (!list.empty() && t < list.back().stamp_ns) {
    r.fail("stamp " + std::to_string(ns_to_sec(t)) + " s is older than the robot's previous " + what + " record (" +
           std::to_string(ns_to_sec(list.back().stamp_ns)) +
           " s): records of one robot and type must be in time order");
  }
}

void read_scan(Record& r, MultiRobotLog* log, RobotLogData& robot, StampNs t, const MultiRobotLogReadOptions& o) {
  LaserScan s;
  s.stamp_ns = t;
  s.angle_min_rad = float(r.finite("angle_min_rad"));
  s.angle_increment_rad = float(r.finite("angle_increment_rad"));
  s.range_max_m = float(r.positive("range_max_m"));
  s.range_min_m = o.range_min_m;
  const int n = r.integer("n", 1, o.max_beams);
  s.ranges_m.reserve(size_t(n));
  for (int i = 0; i < n; ++i) {
    const double v = r.any_number("range");
    if (std::isnan(v)) {
      ++log->stats.nan_ranges;
    } else if (std::isinf(v)) {
      if (v < 0) r.fail("beam " + std::to_string(i) + " is -inf (use inf for no return, nan for a broken reading)");
      ++log->stats.inf_ranges;
    }
    s.ranges_m.push_back(float(v));
  }
  std::string extra;
  r.end();
  check_order(r, robot.scans, t, "SCAN");
  robot.scans.push_back(std::move(s));
}

void read_landmark(Record& r, RobotLogData& robot, StampNs t) {
  LandmarkObservation o;
  o.stamp_ns = t;
  o.id = LandmarkId(r.integer("id", 0, std::numeric_limits<int32_t>::max()));
  o.range_m = r.finite("range_m");
  if (o.range_m < 0) r.fail("field range_m must be >= 0, got " + std::to_string(o.range_m));
  o.bearing_rad = r.finite("bearing_rad");
  o.sigma_range_m = r.positive("sigma_range_m");
  o.sigma_bearing_rad = r.positive("sigma_bearing_rad");
  r.end();
  check_order(r, robot.landmarks, t, "LANDMARK");
  robot.landmarks.push_back(o);
}

void read_record(Record& r, MultiRobotLog* log, const MultiRobotLogReadOptions& options) {
  const std::string& type = r.type();
  if (type == "MARKER") {
    const LandmarkId id(r.integer("id", 0, std::numeric_limits<int32_t>::max()));
    const double x = r.finite("x_m"), y = r.finite("y_m");
    r.end();
    if (log->markers.count(id)) r.fail("marker " + std::to_string(id.value) + " is defined twice");
    log->markers[id] = Eigen::Vector2d(x, y);
    return;
  }
  if (type != "ODOM" && type != "SCAN" && type != "LANDMARK" && type != "TRUTH") {
    throw InputError(r.where() + ": unknown record type '" + type +
                     "' (expected ODOM, SCAN, LANDMARK, TRUTH or MARKER)");
  }
  RobotLogData& robot = log->robot_data(RobotId(r.integer("robot", 0, 1000000)));
  const StampNs t = r.stamp();
  if (type == "SCAN") return read_scan(r, log, robot, t, options);
  if (type == "LANDMARK") return read_landmark(r, robot, t);
  const double x = r.finite("x_m"), y = r.finite("y_m"), yaw = r.finite("yaw_rad");
  r.end();
  if (type == "ODOM") {
    check_order(r, robot.odometry, t, "ODOM");
    robot.odometry.push_back(OdometryReading{t, SE2(x, y, yaw), 0.0, 0.0});
  } else {
    check_order(r, robot.truth, t, "TRUTH");
    robot.truth.push_back(StampedPose{t, SE2(x, y, yaw)});
  }
}

/// Formats a double so that it reads back identically enough: %.9g, and inf / nan spelled out.
std::string num(double v, const char* fmt = "%.9g") {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  std::snprintf(buf, sizeof(buf), fmt, v);
  return buf;
}

std::string stamp(StampNs t) { return num(ns_to_sec(t), "%.9f"); }

}  // namespace

MultiRobotLog parse_multirobot_log(std::istream& in, const std::string& name, const MultiRobotLogReadOptions& options) {
  MultiRobotLog log;
  bool header = false;
  std::string line;
  while (std::getline(in, line)) {
    ++log.stats.lines;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    Record r(line, name + ":" + std::to_string(log.stats.lines));
    if (r.type().empty() || r.type()[0] == '#') continue;
    if (!header) {
      if (r.type() != kHeader) {
        throw InputError(r.where() + ": not a Cairn multi-robot log: the first record must be '" + kHeader +
                         " <version>', got '" + r.type() + "'");
      }
      log.version = r.integer("version", 0, 1000000);
      r.end();
      if (log.version != kMultiRobotLogVersion) {
        r.fail("version " + std::to_string(log.version) + " is not supported (this reader reads version " +
               std::to_string(kMultiRobotLogVersion) + ")");
      }
      header = true;
      continue;
    }
    read_record(r, &log, options);
    ++log.stats.records;
  }
  if (!header) throw InputError(name + ": empty file, expected the header '" + std::string(kHeader) + " <version>'");
  return log;
}

MultiRobotLog read_multirobot_log(const std::string& path, const MultiRobotLogReadOptions& options) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open multi-robot log");
  return parse_multirobot_log(in, path, options);
}

bool is_multirobot_log(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ss(line);
    std::string type;
    if (!(ss >> type) || type[0] == '#') continue;
    return type == kHeader;
  }
  return false;
}

void write_multirobot_log(std::ostream& out, const MultiRobotLog& log, const std::string& comment) {
  out << kHeader << ' ' << kMultiRobotLogVersion << '\n';
  if (!comment.empty()) {
    std::istringstream ss(comment);
    for (std::string line; std::getline(ss, line);) out << "# " << line << '\n';
  }
  for (const auto& [id, p] : log.markers)
    out << "MARKER " << id.value << ' ' << num(p.x()) << ' ' << num(p.y()) << '\n';
  // (stamp, type order, robot, index) of every record, then written in that order.
  std::vector<std::tuple<StampNs, int, int32_t, size_t>> order;
  for (const auto& [id, r] : log.robots) {
    for (size_t i = 0; i < r.odometry.size(); ++i) order.emplace_back(r.odometry[i].stamp_ns, 0, id.value, i);
    for (size_t i = 0; i < r.scans.size(); ++i) order.emplace_back(r.scans[i].stamp_ns, 1, id.value, i);
    for (size_t i = 0; i < r.landmarks.size(); ++i) order.emplace_back(r.landmarks[i].stamp_ns, 2, id.value, i);
    for (size_t i = 0; i < r.truth.size(); ++i) order.emplace_back(r.truth[i].stamp_ns, 3, id.value, i);
  }
  std::stable_sort(order.begin(), order.end());
  for (const auto& [t, type, robot, i] : order) {
    const RobotLogData& r = log.robots.at(RobotId(robot));
    const std::string head = std::to_string(robot) + ' ' + stamp(t);
    if (type == 0 || type == 3) {
      const SE2& T = type == 0 ? r.odometry[i].T_odom_base : r.truth[i].pose;
      out << (type == 0 ? "ODOM " : "TRUTH ") << head << ' ' << num(T.x()) << ' ' << num(T.y()) << ' ' << num(T.yaw())
          << '\n';
    } else if (type == 1) {
      const LaserScan& s = r.scans[i];
      out << "SCAN " << head << ' ' << num(s.angle_min_rad) << ' ' << num(s.angle_increment_rad) << ' '
          << num(s.range_max_m) << ' ' << s.ranges_m.size();
      for (float v : s.ranges_m) out << ' ' << num(v, "%.4f");
      out << '\n';
    } else {
      const LandmarkObservation& o = r.landmarks[i];
      out << "LANDMARK " << head << ' ' << o.id.value << ' ' << num(o.range_m) << ' ' << num(o.bearing_rad) << ' '
          << num(o.sigma_range_m) << ' ' << num(o.sigma_bearing_rad) << '\n';
    }
  }
}

bool write_multirobot_log_file(const std::string& path, const MultiRobotLog& log, const std::string& comment) {
  std::ofstream out(path);
  if (!out) return false;
  write_multirobot_log(out, log, comment);
  out.flush();
  return bool(out);
}

}  // namespace cairn
