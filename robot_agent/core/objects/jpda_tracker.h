#pragma once
// Multi-target Kalman filter with joint probabilistic data association (seed paper Sec. 3.3:
// "EKF improved by JPDA" so that several objects in clutter keep their identities). State per
// target: position (constant-position model) or position + velocity (constant-velocity model) in
// `dims` dimensions; measurements are positions with their own covariance (the caller linearises
// its sensor model into R, which is the EKF step). Joint association events are enumerated exactly
// per cluster of gate-sharing tracks (Bar-Shalom & Fortmann); a greedy nearest-neighbour mode is
// kept as the baseline. Pure Eigen; no track birth/death policy (the caller owns that).
#include <Eigen/Core>
#include <string>
#include <vector>

namespace cairn::agent {

enum class Association { kJpda, kNearestNeighbour };

struct JpdaOptions {
  int dims = 3;
  bool constant_velocity = false;
  double process_noise = 1e-4;  ///< q: m^2/s (position random walk) or m^2/s^3 (white acceleration)
  double gate_chi2 = 16.0;      ///< Mahalanobis^2 gate on the innovation
  double p_detection = 0.9;
  double clutter_density = 1e-2;  ///< false measurements per unit volume (m^dims)
  Association association = Association::kJpda;
  long max_joint_events = 200000;  ///< beyond this a cluster falls back to nearest neighbour
};

struct JpdaTarget {
  int id = 0;
  Eigen::VectorXd x;  ///< [position; velocity?]
  Eigen::MatrixXd P;
};

struct JpdaUpdate {
  /// beta[t][j]: probability that measurement j came from track t; beta[t].back(): none.
  std::vector<std::vector<double>> beta;
  std::vector<bool> gated;  ///< per measurement: inside some track's gate
  bool fell_back_to_nn = false;
};

class JpdaTracker {
 public:
  explicit JpdaTracker(const JpdaOptions& options = {});
  /// New target at measurement z (velocity 0 with variance `velocity_var` in CV mode). Returns its id.
  int add(const Eigen::VectorXd& z, const Eigen::MatrixXd& R, double velocity_var = 1.0);
  void predict(double dt_s);
  /// `allowed` (optional, [target index in targets()][measurement]): false keeps that measurement
  /// out of that target's gate whatever its distance (the caller knows they are different objects,
  /// e.g. from their 3D extent).
  JpdaUpdate update(const std::vector<Eigen::VectorXd>& z, const std::vector<Eigen::MatrixXd>& R,
                    const std::vector<std::vector<bool>>* allowed = nullptr);
  void remove(int id);
  /// Fuses target `from` into `into` (product of Gaussians on the whole state), removes `from`.
  void merge(int into, int from);
  const std::vector<JpdaTarget>& targets() const { return targets_; }
  const JpdaTarget* find(int id) const;
  Eigen::VectorXd position(const JpdaTarget& t) const { return t.x.head(options_.dims); }
  Eigen::MatrixXd position_covariance(const JpdaTarget& t) const {
    return t.P.topLeftCorner(options_.dims, options_.dims);
  }
  const JpdaOptions& options() const { return options_; }

 private:
  Eigen::MatrixXd H() const;
  void pda_update(JpdaTarget* t, const std::vector<Eigen::VectorXd>& z, const std::vector<Eigen::MatrixXd>& R,
                  const std::vector<double>& beta) const;
  bool joint_probabilities(const std::vector<int>& tracks, const std::vector<std::vector<double>>& lik,
                           const std::vector<std::vector<bool>>& in_gate, std::vector<std::vector<double>>* beta) const;
  void nearest_neighbour(const std::vector<int>& tracks, const std::vector<std::vector<double>>& d2,
                         const std::vector<std::vector<bool>>& in_gate, std::vector<std::vector<double>>* beta) const;

  JpdaOptions options_;
  std::vector<JpdaTarget> targets_;
  int next_id_ = 0;
};

}  // namespace cairn::agent
