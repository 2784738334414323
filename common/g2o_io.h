#pragma once
// g2o pose-graph files, planar: VERTEX_SE2 / EDGE_SE2 and the planar multi-robot
// VERTEX_SE3:QUAT / EDGE_SE3:QUAT graphs whose keys carry the robot letter in the top byte
// (key = (letter << 56) | index, 'a' = robot 0; see ../shared/data/multirobot_g2o). SE3 entries are
// projected to the plane (x, y, yaw; the information block over x, y, rz).
// 2D landmarks: VERTEX_XY (a point) and EDGE_SE2_XY (the point observed in a pose's frame, information
// upper triangle I11 I12 I22), kept apart from the poses (G2oGraph::points / point_edges).
// Also the two objectives used to compare solutions: g2o's chi2 and SE-Sync's (Rosen et al. 2019).
#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "common/se2.h"

namespace cairn {

/// A g2o vertex key split into robot and index (robot 0 for plain integer keys).
struct G2oKey {
  int robot = 0;
  int64_t index = 0;
  friend bool operator<(G2oKey a, G2oKey b) { return a.robot != b.robot ? a.robot < b.robot : a.index < b.index; }
  friend bool operator==(G2oKey a, G2oKey b) { return a.robot == b.robot && a.index == b.index; }
};
/// Decodes a raw key: a top byte in 'a'..'z' is a robot letter, else robot 0 and the whole key.
G2oKey decode_g2o_key(uint64_t raw);
uint64_t encode_g2o_key(G2oKey key);

struct G2oEdge {
  G2oKey from, to;
  SE2 T_from_to;                                              ///< pose of `to` in `from`'s frame
  Eigen::Matrix3d information = Eigen::Matrix3d::Identity();  ///< over (x_m, y_m, yaw_rad)
  int line = 0;
};

/// EDGE_SE2_XY: point `to` observed from pose `from` (g2o's error: R_from^T (p_to - t_from) - p_from_to).
struct G2oPointEdge {
  G2oKey from, to;
  Eigen::Vector2d p_from_to = Eigen::Vector2d::Zero();
  Eigen::Matrix2d information = Eigen::Matrix2d::Identity();
  int line = 0;
};

struct G2oGraph {
  std::map<G2oKey, SE2> vertices;  ///< may be empty (edges-only files)
  std::vector<G2oEdge> edges;
  std::map<G2oKey, Eigen::Vector2d> points;  ///< VERTEX_XY; an id is never both a pose and a point
  std::vector<G2oPointEdge> point_edges;     ///< EDGE_SE2_XY: from a pose to a point
  bool se3 = false;                          ///< read from SE3:QUAT records
  bool robot_keys = false;                   ///< keys carried robot letters
};

/// Reads a g2o file. Throws InputError "<path>:<line>: <reason>" for a malformed line, a
/// non-finite number, an edge whose information is not positive definite, an id declared both as
/// VERTEX_SE2 and VERTEX_XY, or an edge joining the wrong kinds (EDGE_SE2 touching a point,
/// EDGE_SE2_XY not from a pose to a point). Unknown record types (FIX, PARAMS_..., ...) are skipped.
G2oGraph read_g2o(const std::string& path);
/// Appends the content of another file (e.g. each robot's k.g2o); duplicate edges are dropped.
void merge_g2o(const G2oGraph& other, G2oGraph* into);

/// Writes `poses` (or graph.vertices if empty) and the edges as VERTEX_SE2/EDGE_SE2 (plain keys)
/// or VERTEX_SE3:QUAT/EDGE_SE3:QUAT (robot keys, when `se3`), then the points and point edges as
/// VERTEX_XY/EDGE_SE2_XY (plain keys only; left out when `se3`). False on I/O failure.
bool write_g2o(const std::string& path, const G2oGraph& graph, const std::map<G2oKey, SE2>& poses = {},
               bool se3 = false);

/// Initial poses by composing edges along a breadth-first spanning tree from the first key,
/// preferring odometry edges (same robot, index + 1). Existing vertices are kept as they are for
/// components that have them. Keys unreachable from any vertex stay absent.
std::map<G2oKey, SE2> initialize_from_odometry(const G2oGraph& graph);

/// g2o's chi2 over the pose edges: sum e^T Omega e with e = log(Z^-1 (X_i^-1 X_j)) as (x, y, yaw).
double g2o_chi2(const G2oGraph& graph, const std::map<G2oKey, SE2>& poses);
/// SE-Sync's objective over the pose edges: sum kappa ||R_j - R_i R~_ij||_F^2 + tau ||t_j - t_i - R_i t~_ij||^2 with
/// kappa = Omega_yaw,yaw and tau = 2 / trace(Omega_tt^-1) (../shared/data/MANIFEST.md).
double sesync_objective(const G2oGraph& graph, const std::map<G2oKey, SE2>& poses);
/// chi2 of the point edges: sum e^T Omega e with e = R_i^T (p_j - t_i) - z (edges with an unknown end skipped).
double g2o_point_chi2(const G2oGraph& graph, const std::map<G2oKey, SE2>& poses,
                      const std::map<G2oKey, Eigen::Vector2d>& points);

}  // namespace cairn
