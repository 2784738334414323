#include "common/registration/point_features.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace cairn::registration {
namespace {

constexpr int kBins = 11;
constexpr int kFeatureChecks = 0;  ///< exact: randomised trees (checks 128) measured slower here

Eigen::Vector3f p3(const ColoredPoint& p) { return Eigen::Vector3f(p.x, p.y, p.z); }

/// PCL's computePairFeatures: Darboux frame angles (f1 = theta, f2 = alpha, f3 = phi) of a pair.
bool pair_features(Eigen::Vector3f p1, Eigen::Vector3f n1, Eigen::Vector3f p2, Eigen::Vector3f n2, float* f) {
  Eigen::Vector3f d = p2 - p1;
  const float dist = d.norm();
  if (dist == 0.f) return false;
  const float a1 = n1.dot(d) / dist, a2 = n2.dot(d) / dist;
  if (std::acos(std::fabs(a1)) > std::acos(std::fabs(a2))) {
    std::swap(n1, n2);
    d = -d;
    f[2] = -a2;
  } else {
    f[2] = a1;
  }
  Eigen::Vector3f v = d.cross(n1);
  const float vn = v.norm();
  if (vn == 0.f) return false;
  v /= vn;
  const Eigen::Vector3f w = n1.cross(v);
  f[1] = v.dot(n2);
  f[0] = std::atan2(w.dot(n2), n1.dot(n2));
  return true;
}

bool empty(const Fpfh& f) {
  return std::all_of(f.begin(), f.end(), [](float v) { return v == 0.f; });
}

int bin(float value, float lo, float hi) {
  return std::clamp(int(std::floor(kBins * (value - lo) / (hi - lo))), 0, kBins - 1);
}

}  // namespace

std::vector<float> xyz_rows(const ColoredCloud& cloud) {
  std::vector<float> rows;
  rows.reserve(cloud.size() * 3);
  for (const ColoredPoint& p : cloud) rows.insert(rows.end(), {p.x, p.y, p.z});
  return rows;
}

std::vector<Eigen::Vector3f> estimate_normals(const ColoredCloud& cloud, const KnnIndex& xyz_index, int k,
                                              const Eigen::Vector3f& viewpoint) {
  const Eigen::Vector3f nan = Eigen::Vector3f::Constant(std::nanf(""));
  std::vector<Eigen::Vector3f> normals(cloud.size(), nan);
  std::vector<int> idx;
  std::vector<float> d2;
  xyz_index.knn(xyz_rows(cloud), k, &idx, &d2);
  for (size_t i = 0; i < cloud.size(); ++i) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    int n = 0;
    for (int j = 0; j < k; ++j)
      if (const int q = idx[i * size_t(k) + size_t(j)]; q >= 0) mean += p3(cloud[size_t(q)]).cast<double>(), ++n;
    if (n < 3) continue;
    mean /= n;
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (int j = 0; j < k; ++j)
      if (const int q = idx[i * size_t(k) + size_t(j)]; q >= 0) {
        const Eigen::Vector3d d = p3(cloud[size_t(q)]).cast<double>() - mean;
        cov += d * d.transpose();
      }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    Eigen::Vector3f nrm = eig.eigenvectors().col(0).cast<float>();
    if (nrm.dot(viewpoint - p3(cloud[i])) < 0.f) nrm = -nrm;
    normals[i] = nrm;
  }
  return normals;
}

std::vector<Fpfh> compute_fpfh(const ColoredCloud& cloud, const std::vector<Eigen::Vector3f>& normals,
                               const KnnIndex& xyz_index, double radius_m) {
  std::vector<std::vector<int>> nb;
  std::vector<std::vector<float>> d2;
  xyz_index.radius(xyz_rows(cloud), radius_m, &nb, &d2);
  // SPFH: histogram of the pair features between each point and its neighbours.
  std::vector<Fpfh> spfh(cloud.size(), Fpfh{});
  for (size_t i = 0; i < cloud.size(); ++i) {
    if (!normals[i].allFinite() || nb[i].size() < 2) continue;
    const float incr = 100.f / float(nb[i].size() - 1);
    for (int j : nb[i]) {
      if (size_t(j) == i || !normals[size_t(j)].allFinite()) continue;
      float f[3];
      if (!pair_features(p3(cloud[i]), normals[i], p3(cloud[size_t(j)]), normals[size_t(j)], f)) continue;
      spfh[i][size_t(bin(f[0], -float(M_PI), float(M_PI)))] += incr;
      spfh[i][size_t(kBins + bin(f[1], -1.f, 1.f))] += incr;
      spfh[i][size_t(2 * kBins + bin(f[2], -1.f, 1.f))] += incr;
    }
  }
  // FPFH: neighbours' SPFHs weighted by 1/d^2, each 11-bin block normalised to 100.
  std::vector<Fpfh> out(cloud.size(), Fpfh{});
  for (size_t i = 0; i < cloud.size(); ++i) {
    Fpfh h{};
    for (size_t m = 0; m < nb[i].size(); ++m) {
      if (d2[i][m] <= 0.f) continue;
      const float w = 1.f / d2[i][m];
      for (size_t b = 0; b < h.size(); ++b) h[b] += w * spfh[size_t(nb[i][m])][b];
    }
    for (int block = 0; block < 3; ++block) {
      float sum = 0.f;
      for (int b = 0; b < kBins; ++b) sum += h[size_t(block * kBins + b)];
      if (sum <= 0.f) continue;
      for (int b = 0; b < kBins; ++b) out[i][size_t(block * kBins + b)] = h[size_t(block * kBins + b)] * 100.f / sum;
    }
  }
  return out;
}

std::vector<std::pair<int, int>> match_features(const ColoredCloud& source, const std::vector<Fpfh>& fs,
                                                const ColoredCloud& target, const std::vector<Fpfh>& ft,
                                                double max_colour_diff) {
  auto rows = [](const std::vector<Fpfh>& f) {
    std::vector<float> r;
    r.reserve(f.size() * 33);
    for (const Fpfh& h : f) r.insert(r.end(), h.begin(), h.end());
    return r;
  };
  const std::vector<float> rs = rows(fs), rt = rows(ft);
  const KnnIndex index_t(rt, 33, kFeatureChecks), index_s(rs, 33, kFeatureChecks);
  std::vector<int> st, ts;
  std::vector<float> d2;
  index_t.knn(rs, 1, &st, &d2);
  index_s.knn(rt, 1, &ts, &d2);
  std::vector<std::pair<int, int>> matches;
  for (size_t i = 0; i < fs.size(); ++i) {
    const int j = st[i];
    if (j < 0 || ts[size_t(j)] != int(i) || empty(fs[i]) || empty(ft[size_t(j)])) continue;
    const ColoredPoint& a = source[i];
    const ColoredPoint& b = target[size_t(j)];
    const double dc = std::sqrt(std::pow(a.r - b.r, 2) + std::pow(a.g - b.g, 2) + std::pow(a.b - b.b, 2));
    if (dc <= max_colour_diff) matches.emplace_back(int(i), j);
  }
  return matches;
}

}  // namespace cairn::registration
