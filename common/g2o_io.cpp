#include "common/g2o_io.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>

#include "common/errors.h"

namespace cairn {
namespace {

constexpr int kRobotShift = 56;
constexpr uint64_t kIndexMask = (uint64_t(1) << kRobotShift) - 1;

[[noreturn]] void fail(const std::string& path, int line, const std::string& why) {
  throw InputError(path + ":" + std::to_string(line) + ": " + why);
}

/// Reads `n` finite doubles from `in`, or fails naming the line.
std::vector<double> read_numbers(std::istringstream& in, int n, const std::string& path, int line,
                                 const std::string& tag) {
  std::vector<double> v(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    std::string tok;
    if (!(in >> tok)) fail(path, line, tag + " expects " + std::to_string(n) + " numbers, got " + std::to_string(i));
    char* end = nullptr;
    v[size_t(i)] = std::strtod(tok.c_str(), &end);
    if (end == tok.c_str() || *end != '\0') fail(path, line, tag + ": not a number: '" + tok + "'");
    if (!std::isfinite(v[size_t(i)])) fail(path, line, tag + ": non-finite value '" + tok + "'");
  }
  return v;
}

uint64_t read_key(std::istringstream& in, const std::string& path, int line, const std::string& tag) {
  std::string tok;
  if (!(in >> tok)) fail(path, line, tag + ": missing vertex id");
  char* end = nullptr;
  errno = 0;
  const unsigned long long k = std::strtoull(tok.c_str(), &end, 10);
  if (end == tok.c_str() || *end != '\0' || errno != 0 || tok[0] == '-') {
    fail(path, line, tag + ": bad vertex id '" + tok + "'");
  }
  return uint64_t(k);
}

double yaw_of_quaternion(double qx, double qy, double qz, double qw) {
  const Eigen::Quaterniond q(qw, qx, qy, qz);
  const Eigen::Vector3d x_axis = q.normalized().toRotationMatrix().col(0);
  return std::atan2(x_axis.y(), x_axis.x());
}

/// Upper triangle (row-major) of an n x n symmetric matrix.
Eigen::MatrixXd from_upper(const std::vector<double>& v, int n) {
  Eigen::MatrixXd m(n, n);
  size_t k = 0;
  for (int r = 0; r < n; ++r) {
    for (int c = r; c < n; ++c) m(r, c) = m(c, r) = v[k++];
  }
  return m;
}

bool positive_definite(const Eigen::Matrix3d& m) {
  Eigen::LLT<Eigen::Matrix3d> llt(m);
  return llt.info() == Eigen::Success;
}

void parse_line(const std::string& tag, std::istringstream& in, const std::string& path, int line, G2oGraph* g) {
  const bool se3 = tag.find("SE3") != std::string::npos;
  if (tag == "VERTEX_SE2" || tag == "VERTEX_SE3:QUAT") {
    const uint64_t raw = read_key(in, path, line, tag);
    const std::vector<double> v = read_numbers(in, se3 ? 7 : 3, path, line, tag);
    const G2oKey key = decode_g2o_key(raw);
    if (g->points.count(key)) fail(path, line, tag + ": id " + std::to_string(raw) + " is already a VERTEX_XY");
    g->robot_keys |= key.robot != 0 || (raw >> kRobotShift) != 0;
    g->se3 |= se3;
    g->vertices[key] = se3 ? SE2(v[0], v[1], yaw_of_quaternion(v[3], v[4], v[5], v[6])) : SE2(v[0], v[1], v[2]);
    return;
  }
  G2oEdge e;
  e.line = line;
  const uint64_t a = read_key(in, path, line, tag), b = read_key(in, path, line, tag);
  e.from = decode_g2o_key(a);
  e.to = decode_g2o_key(b);
  g->robot_keys |= (a >> kRobotShift) != 0 || (b >> kRobotShift) != 0;
  if (se3) {
    const std::vector<double> m = read_numbers(in, 7, path, line, tag);
    const Eigen::MatrixXd info = from_upper(read_numbers(in, 21, path, line, tag), 6);
    e.T_from_to = SE2(m[0], m[1], yaw_of_quaternion(m[3], m[4], m[5], m[6]));
    const int idx[3] = {0, 1, 5};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) e.information(r, c) = info(idx[r], idx[c]);
    }
    g->se3 = true;
  } else {
    const std::vector<double> m = read_numbers(in, 3, path, line, tag);
    e.T_from_to = SE2(m[0], m[1], m[2]);
    e.information = from_upper(read_numbers(in, 6, path, line, tag), 3);
  }
  if (e.from == e.to) fail(path, line, tag + ": edge from a vertex to itself");
  if (!positive_definite(e.information)) fail(path, line, tag + ": information not positive definite");
  g->edges.push_back(e);
}

/// VERTEX_XY / EDGE_SE2_XY (2D landmarks); both end kinds are checked by check_kinds().
void parse_point_line(const std::string& tag, std::istringstream& in, const std::string& path, int line, G2oGraph* g) {
  if (tag == "VERTEX_XY") {
    const uint64_t raw = read_key(in, path, line, tag);
    const std::vector<double> v = read_numbers(in, 2, path, line, tag);
    const G2oKey key = decode_g2o_key(raw);
    if (g->vertices.count(key)) fail(path, line, tag + ": id " + std::to_string(raw) + " is already a VERTEX_SE2");
    g->points[key] = Eigen::Vector2d(v[0], v[1]);
    return;
  }
  G2oPointEdge e;
  e.line = line;
  e.from = decode_g2o_key(read_key(in, path, line, tag));
  e.to = decode_g2o_key(read_key(in, path, line, tag));
  const std::vector<double> m = read_numbers(in, 2, path, line, tag);
  const std::vector<double> info = read_numbers(in, 3, path, line, tag);
  e.p_from_to = Eigen::Vector2d(m[0], m[1]);
  e.information << info[0], info[1], info[1], info[2];
  if (e.from == e.to) fail(path, line, tag + ": edge from a vertex to itself");
  Eigen::LLT<Eigen::Matrix2d> llt(e.information);
  if (llt.info() != Eigen::Success) fail(path, line, tag + ": information not positive definite");
  g->point_edges.push_back(e);
}

/// Poses and points are distinct vertex kinds (a vertex declared as both fails where it is parsed):
/// an edge must join the kinds its type names.
void check_kinds(const G2oGraph& g, const std::string& path) {
  for (const G2oEdge& e : g.edges) {
    if (g.points.count(e.from) || g.points.count(e.to)) fail(path, e.line, "EDGE_SE2/SE3 joins a VERTEX_XY point");
  }
  for (const G2oPointEdge& e : g.point_edges) {
    if (g.points.count(e.from)) fail(path, e.line, "EDGE_SE2_XY: first vertex is a VERTEX_XY point, not a pose");
    if (g.vertices.count(e.to)) fail(path, e.line, "EDGE_SE2_XY: second vertex is a VERTEX_SE2 pose, not a point");
  }
}

}  // namespace

G2oKey decode_g2o_key(uint64_t raw) {
  const uint64_t letter = raw >> kRobotShift;
  if (letter >= uint64_t('a') && letter <= uint64_t('z')) {
    return G2oKey{int(letter - 'a'), int64_t(raw & kIndexMask)};
  }
  return G2oKey{0, int64_t(raw)};
}

uint64_t encode_g2o_key(G2oKey key) {
  return (uint64_t('a' + key.robot) << kRobotShift) | (uint64_t(key.index) & kIndexMask);
}

G2oGraph read_g2o(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open");
  G2oGraph graph;
  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    std::istringstream ls(text);
    std::string tag;
    if (!(ls >> tag) || tag[0] == '#') continue;
    const bool pose = tag == "VERTEX_SE2" || tag == "EDGE_SE2" || tag == "VERTEX_SE3:QUAT" || tag == "EDGE_SE3:QUAT";
    const bool point = tag == "VERTEX_XY" || tag == "EDGE_SE2_XY";
    if (pose) parse_line(tag, ls, path, line, &graph);
    if (point) parse_point_line(tag, ls, path, line, &graph);
    std::string extra;
    if ((pose || point) && ls >> extra) fail(path, line, tag + ": unexpected extra field '" + extra + "'");
  }
  check_kinds(graph, path);
  return graph;
}

void merge_g2o(const G2oGraph& other, G2oGraph* into) {
  for (const auto& [k, v] : other.vertices) into->vertices.emplace(k, v);
  std::set<std::pair<G2oKey, G2oKey>> seen;
  for (const G2oEdge& e : into->edges) seen.insert({e.from, e.to});
  for (const G2oEdge& e : other.edges) {
    // Only edges already present (another robot's file) are duplicates; repeated measurements
    // inside one file are kept.
    if (!seen.count({e.from, e.to})) into->edges.push_back(e);
  }
  for (const auto& [k, p] : other.points) into->points.emplace(k, p);
  std::set<std::pair<G2oKey, G2oKey>> seen_points;
  for (const G2oPointEdge& e : into->point_edges) seen_points.insert({e.from, e.to});
  for (const G2oPointEdge& e : other.point_edges) {
    if (!seen_points.count({e.from, e.to})) into->point_edges.push_back(e);
  }
  into->se3 |= other.se3;
  into->robot_keys |= other.robot_keys;
}

bool write_g2o(const std::string& path, const G2oGraph& graph, const std::map<G2oKey, SE2>& poses, bool se3) {
  std::ofstream out(path);
  if (!out) return false;
  out << std::setprecision(10);
  const std::map<G2oKey, SE2>& v = poses.empty() ? graph.vertices : poses;
  auto key = [&](G2oKey k) { return se3 ? encode_g2o_key(k) : uint64_t(k.index); };
  for (const auto& [k, p] : v) {
    if (se3) {
      out << "VERTEX_SE3:QUAT " << key(k) << ' ' << p.x() << ' ' << p.y() << " 0 0 0 " << std::sin(p.yaw() / 2) << ' '
          << std::cos(p.yaw() / 2) << '\n';
    } else {
      out << "VERTEX_SE2 " << key(k) << ' ' << p.x() << ' ' << p.y() << ' ' << p.yaw() << '\n';
    }
  }
  for (const G2oEdge& e : graph.edges) {
    const SE2& m = e.T_from_to;
    const Eigen::Matrix3d& I = e.information;
    if (se3) {
      out << "EDGE_SE3:QUAT " << key(e.from) << ' ' << key(e.to) << ' ' << m.x() << ' ' << m.y() << " 0 0 0 "
          << std::sin(m.yaw() / 2) << ' ' << std::cos(m.yaw() / 2);
      // 6x6 upper triangle over (x, y, z, rx, ry, rz); z, rx, ry get a stiff 1e4.
      const int map6[6] = {0, 1, -1, -1, -1, 2};
      for (int r = 0; r < 6; ++r) {
        for (int c = r; c < 6; ++c) {
          const double val = map6[r] >= 0 && map6[c] >= 0 ? I(map6[r], map6[c]) : (r == c ? 1e4 : 0.0);
          out << ' ' << val;
        }
      }
      out << '\n';
    } else {
      out << "EDGE_SE2 " << key(e.from) << ' ' << key(e.to) << ' ' << m.x() << ' ' << m.y() << ' ' << m.yaw() << ' '
          << I(0, 0) << ' ' << I(0, 1) << ' ' << I(0, 2) << ' ' << I(1, 1) << ' ' << I(1, 2) << ' ' << I(2, 2) << '\n';
    }
  }
  if (!se3) {
    for (const auto& [k, p] : graph.points) out << "VERTEX_XY " << key(k) << ' ' << p.x() << ' ' << p.y() << '\n';
    for (const G2oPointEdge& e : graph.point_edges) {
      out << "EDGE_SE2_XY " << key(e.from) << ' ' << key(e.to) << ' ' << e.p_from_to.x() << ' ' << e.p_from_to.y()
          << ' ' << e.information(0, 0) << ' ' << e.information(0, 1) << ' ' << e.information(1, 1) << '\n';
    }
  }
  return bool(out);
}

std::map<G2oKey, SE2> initialize_from_odometry(const G2oGraph& graph) {
  std::map<G2oKey, std::vector<std::pair<size_t, bool>>> adj;  // edge index, forward
  for (size_t i = 0; i < graph.edges.size(); ++i) {
    adj[graph.edges[i].from].push_back({i, true});
    adj[graph.edges[i].to].push_back({i, false});
  }
  auto is_odometry = [&](size_t i) {
    const G2oEdge& e = graph.edges[i];
    return e.from.robot == e.to.robot && std::llabs(e.to.index - e.from.index) == 1;
  };
  std::map<G2oKey, SE2> poses = graph.vertices;
  // Two passes: odometry edges only, then every edge for what odometry could not reach.
  for (int pass = 0; pass < 2; ++pass) {
    std::deque<G2oKey> queue;
    for (const auto& [k, p] : poses) queue.push_back(k);
    if (poses.empty() && !adj.empty()) {
      poses[adj.begin()->first] = SE2();
      queue.push_back(adj.begin()->first);
    }
    std::set<G2oKey> visited(queue.begin(), queue.end());
    while (!queue.empty()) {
      const G2oKey k = queue.front();
      queue.pop_front();
      for (const auto& [i, forward] : adj[k]) {
        if (pass == 0 && !is_odometry(i)) continue;
        const G2oEdge& e = graph.edges[i];
        const G2oKey other = forward ? e.to : e.from;
        if (visited.count(other) || poses.count(other)) continue;
        poses[other] = forward ? poses[k] * e.T_from_to : poses[k] * e.T_from_to.inverse();
        visited.insert(other);
        queue.push_back(other);
      }
    }
  }
  return poses;
}

double g2o_chi2(const G2oGraph& graph, const std::map<G2oKey, SE2>& poses) {
  double chi2 = 0.0;
  for (const G2oEdge& e : graph.edges) {
    auto a = poses.find(e.from), b = poses.find(e.to);
    if (a == poses.end() || b == poses.end()) continue;
    const Eigen::Vector3d r = (e.T_from_to.inverse() * a->second.between(b->second)).vector();
    chi2 += r.dot(e.information * r);
  }
  return chi2;
}

double g2o_point_chi2(const G2oGraph& graph, const std::map<G2oKey, SE2>& poses,
                      const std::map<G2oKey, Eigen::Vector2d>& points) {
  double chi2 = 0.0;
  for (const G2oPointEdge& e : graph.point_edges) {
    auto a = poses.find(e.from);
    auto b = points.find(e.to);
    if (a == poses.end() || b == points.end()) continue;
    const Eigen::Vector2d r = a->second.inverse() * b->second - e.p_from_to;
    chi2 += r.dot(e.information * r);
  }
  return chi2;
}

double sesync_objective(const G2oGraph& graph, const std::map<G2oKey, SE2>& poses) {
  double f = 0.0;
  for (const G2oEdge& e : graph.edges) {
    auto a = poses.find(e.from), b = poses.find(e.to);
    if (a == poses.end() || b == poses.end()) continue;
    const double kappa = e.information(2, 2);
    const double tau = 2.0 / e.information.topLeftCorner<2, 2>().inverse().trace();
    const SE2& Ti = a->second;
    const SE2& Tj = b->second;
    const Eigen::Matrix2d dR = Tj.rotation() - Ti.rotation() * e.T_from_to.rotation();
    const Eigen::Vector2d dt = Tj.translation() - Ti.translation() - Ti.rotation() * e.T_from_to.translation();
    f += kappa * dR.squaredNorm() + tau * dt.squaredNorm();
  }
  return f;
}

}  // namespace cairn
