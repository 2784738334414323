#pragma once
// Exact nearest neighbours over fixed-dimension float rows (a FLANN single kd-tree) with batched
// queries: one call answers every query. PCL's per-point KdTreeFLANN queries cost ~10 us each in
// OpenMP/futex overhead on our VMs, which dominated RGB-ICP; batching removes it. FLANN stays in
// knn_index.cpp.
#include <memory>
#include <vector>

namespace cairn::registration {

class KnnIndex {
 public:
  /// `rows` holds n * dim floats (row-major); the index keeps its own copy. approximate_checks > 0:
  /// 4 randomised kd-trees visiting at most that many leaves (for high-dimensional descriptors).
  KnnIndex(std::vector<float> rows, int dim, int approximate_checks = 0);
  ~KnnIndex();
  KnnIndex(KnnIndex&&) noexcept;
  KnnIndex& operator=(KnnIndex&&) noexcept;

  int size() const { return n_; }
  int dim() const { return dim_; }
  /// k nearest rows of each query (n_q * dim floats): indices and squared distances, n_q * k each,
  /// nearest first; -1 / +inf where fewer than k rows exist.
  void knn(const std::vector<float>& queries, int k, std::vector<int>* index, std::vector<float>* dist_sq) const;
  /// All rows within radius_m of each query (squared distances alongside).
  void radius(const std::vector<float>& queries, double radius_m, std::vector<std::vector<int>>* index,
              std::vector<std::vector<float>>* dist_sq) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int n_ = 0;
  int dim_ = 0;
  int checks_ = 0;
};

}  // namespace cairn::registration
