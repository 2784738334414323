#include "robot_agent/core/objects/jpda_tracker.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <tuple>

namespace cairn::agent {

JpdaTracker::JpdaTracker(const JpdaOptions& options) : options_(options) {}

Eigen::MatrixXd JpdaTracker::H() const {
  const int n = options_.constant_velocity ? 2 * options_.dims : options_.dims;
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(options_.dims, n);
  h.leftCols(options_.dims).setIdentity();
  return h;
}

int JpdaTracker::add(const Eigen::VectorXd& z, const Eigen::MatrixXd& R, double velocity_var) {
  const int d = options_.dims, n = options_.constant_velocity ? 2 * d : d;
  JpdaTarget t;
  t.id = next_id_++;
  t.x = Eigen::VectorXd::Zero(n);
  t.x.head(d) = z;
  t.P = Eigen::MatrixXd::Identity(n, n) * velocity_var;
  t.P.topLeftCorner(d, d) = R;
  targets_.push_back(t);
  return t.id;
}

void JpdaTracker::predict(double dt_s) {
  if (!(dt_s > 0.0)) return;
  const int d = options_.dims;
  const double q = options_.process_noise;
  for (JpdaTarget& t : targets_) {
    if (!options_.constant_velocity) {
      t.P += Eigen::MatrixXd::Identity(d, d) * q * dt_s;
      continue;
    }
    Eigen::MatrixXd F = Eigen::MatrixXd::Identity(2 * d, 2 * d);
    F.topRightCorner(d, d) = Eigen::MatrixXd::Identity(d, d) * dt_s;
    Eigen::MatrixXd Q(2 * d, 2 * d);
    const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(d, d);
    Q << I * (q * dt_s * dt_s * dt_s / 3), I * (q * dt_s * dt_s / 2), I * (q * dt_s * dt_s / 2), I * (q * dt_s);
    t.x = F * t.x;
    t.P = F * t.P * F.transpose() + Q;
  }
}

// Exact JPDA over one cluster: every feasible joint event (each track takes at most one gated
// measurement, each measurement at most one track) weighted by prod (P_D g_tj / lambda) * prod (1 - P_D).
bool JpdaTracker::joint_probabilities(const std::vector<int>& tracks, const std::vector<std::vector<double>>& lik,
                                      const std::vector<std::vector<bool>>& in_gate,
                                      std::vector<std::vector<double>>* beta) const {
  const size_t m = lik.empty() ? 0 : lik[0].size();
  const double pd = options_.p_detection, lambda = std::max(1e-300, options_.clutter_density);
  std::vector<int> choice(tracks.size(), -1);
  std::vector<bool> used(m, false);
  std::vector<std::vector<double>> acc(tracks.size(), std::vector<double>(m + 1, 0.0));
  double total = 0.0;
  long events = 0;
  bool aborted = false;
  std::function<void(size_t, double)> rec = [&](size_t k, double w) {
    if (aborted) return;
    if (k == tracks.size()) {
      if (++events > options_.max_joint_events) aborted = true;
      total += w;
      for (size_t i = 0; i < tracks.size(); ++i) acc[i][choice[i] < 0 ? m : size_t(choice[i])] += w;
      return;
    }
    const int t = tracks[k];
    choice[k] = -1;
    rec(k + 1, w * (1.0 - pd));
    for (size_t j = 0; j < m; ++j) {
      if (used[j] || !in_gate[size_t(t)][j]) continue;
      used[j] = true;
      choice[k] = int(j);
      rec(k + 1, w * pd * lik[size_t(t)][j] / lambda);
      used[j] = false;
    }
    choice[k] = -1;
  };
  rec(0, 1.0);
  if (aborted || !(total > 0.0)) return false;
  for (size_t i = 0; i < tracks.size(); ++i) {
    for (size_t j = 0; j <= m; ++j) (*beta)[size_t(tracks[i])][j] = acc[i][j] / total;
  }
  return true;
}

void JpdaTracker::nearest_neighbour(const std::vector<int>& tracks, const std::vector<std::vector<double>>& d2,
                                    const std::vector<std::vector<bool>>& in_gate,
                                    std::vector<std::vector<double>>* beta) const {
  const size_t m = d2.empty() ? 0 : d2[0].size();
  std::vector<std::tuple<double, int, size_t>> pairs;
  for (int t : tracks)
    for (size_t j = 0; j < m; ++j)
      if (in_gate[size_t(t)][j]) pairs.emplace_back(d2[size_t(t)][j], t, j);
  std::sort(pairs.begin(), pairs.end());
  std::vector<bool> track_used(beta->size(), false), meas_used(m, false);
  for (int t : tracks) (*beta)[size_t(t)].assign(m + 1, 0.0), (*beta)[size_t(t)][m] = 1.0;
  for (const auto& [d, t, j] : pairs) {
    if (track_used[size_t(t)] || meas_used[j]) continue;
    track_used[size_t(t)] = meas_used[j] = true;
    (*beta)[size_t(t)][m] = 0.0;
    (*beta)[size_t(t)][j] = 1.0;
  }
}

void JpdaTracker::pda_update(JpdaTarget* t, const std::vector<Eigen::VectorXd>& z,
                             const std::vector<Eigen::MatrixXd>& R, const std::vector<double>& beta) const {
  const size_t m = z.size();
  const double b0 = beta[m];
  if (b0 >= 1.0 - 1e-12) return;
  const Eigen::MatrixXd h = H();
  Eigen::MatrixXd R_mean = Eigen::MatrixXd::Zero(options_.dims, options_.dims);
  for (size_t j = 0; j < m; ++j) R_mean += beta[j] * R[j];
  R_mean /= (1.0 - b0);
  const Eigen::MatrixXd S = h * t->P * h.transpose() + R_mean;
  const Eigen::MatrixXd K = t->P * h.transpose() * S.inverse();
  Eigen::VectorXd nu = Eigen::VectorXd::Zero(options_.dims);
  Eigen::MatrixXd spread = Eigen::MatrixXd::Zero(options_.dims, options_.dims);
  for (size_t j = 0; j < m; ++j) {
    if (beta[j] <= 0.0) continue;
    const Eigen::VectorXd nj = z[j] - h * t->x;
    nu += beta[j] * nj;
    spread += beta[j] * nj * nj.transpose();
  }
  const Eigen::MatrixXd Pc = t->P - K * S * K.transpose();
  t->x += K * nu;
  t->P = b0 * t->P + (1.0 - b0) * Pc + K * (spread - nu * nu.transpose()) * K.transpose();
  t->P = 0.5 * (t->P + t->P.transpose());
}

JpdaUpdate JpdaTracker::update(const std::vector<Eigen::VectorXd>& z, const std::vector<Eigen::MatrixXd>& R,
                               const std::vector<std::vector<bool>>* allowed) {
  const size_t n = targets_.size(), m = z.size();
  JpdaUpdate out;
  out.beta.assign(n, std::vector<double>(m + 1, 0.0));
  for (auto& b : out.beta) b[m] = 1.0;
  out.gated.assign(m, false);
  const Eigen::MatrixXd h = H();
  const double norm_pow = std::pow(2.0 * M_PI, 0.5 * options_.dims);
  std::vector<std::vector<double>> lik(n, std::vector<double>(m, 0.0)), d2(n, std::vector<double>(m, 1e300));
  std::vector<std::vector<bool>> in_gate(n, std::vector<bool>(m, false));
  for (size_t t = 0; t < n; ++t) {
    for (size_t j = 0; j < m; ++j) {
      const Eigen::MatrixXd S = h * targets_[t].P * h.transpose() + R[j];
      const Eigen::VectorXd nu = z[j] - h * targets_[t].x;
      d2[t][j] = nu.dot(S.ldlt().solve(nu));
      in_gate[t][j] = d2[t][j] <= options_.gate_chi2 && (!allowed || (*allowed)[t][j]);
      if (!in_gate[t][j]) continue;
      out.gated[j] = true;
      lik[t][j] = std::exp(-0.5 * d2[t][j]) / (norm_pow * std::sqrt(std::max(1e-300, S.determinant())));
    }
  }
  // Clusters: tracks connected through shared gated measurements (union-find).
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  std::function<int(int)> root = [&](int i) {
    return parent[size_t(i)] == i ? i : parent[size_t(i)] = root(parent[size_t(i)]);
  };
  for (size_t j = 0; j < m; ++j) {
    int first = -1;
    for (size_t t = 0; t < n; ++t) {
      if (!in_gate[t][j]) continue;
      if (first < 0)
        first = int(t);
      else
        parent[size_t(root(int(t)))] = root(first);
    }
  }
  std::vector<std::vector<int>> clusters(n);
  for (size_t t = 0; t < n; ++t) clusters[size_t(root(int(t)))].push_back(int(t));
  for (const std::vector<int>& c : clusters) {
    if (c.empty()) continue;
    const bool nn =
        options_.association == Association::kNearestNeighbour || !joint_probabilities(c, lik, in_gate, &out.beta);
    if (nn) nearest_neighbour(c, d2, in_gate, &out.beta);
    if (nn && options_.association == Association::kJpda) out.fell_back_to_nn = true;
  }
  for (size_t t = 0; t < n; ++t) pda_update(&targets_[t], z, R, out.beta[t]);
  return out;
}

void JpdaTracker::remove(int id) {
  targets_.erase(std::remove_if(targets_.begin(), targets_.end(), [id](const JpdaTarget& t) { return t.id == id; }),
                 targets_.end());
}

void JpdaTracker::merge(int into, int from) {
  auto a = std::find_if(targets_.begin(), targets_.end(), [into](const JpdaTarget& t) { return t.id == into; });
  auto b = std::find_if(targets_.begin(), targets_.end(), [from](const JpdaTarget& t) { return t.id == from; });
  if (a == targets_.end() || b == targets_.end() || a == b) return;
  const Eigen::MatrixXd Ia = a->P.inverse(), Ib = b->P.inverse();
  const Eigen::MatrixXd P = (Ia + Ib).inverse();
  a->x = P * (Ia * a->x + Ib * b->x);
  a->P = P;
  targets_.erase(b);
}

const JpdaTarget* JpdaTracker::find(int id) const {
  for (const JpdaTarget& t : targets_)
    if (t.id == id) return &t;
  return nullptr;
}

}  // namespace cairn::agent
