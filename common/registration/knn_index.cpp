#include "common/registration/knn_index.h"

#include <flann/flann.hpp>

#include <limits>

namespace cairn::registration {

struct KnnIndex::Impl {
  std::vector<float> rows;
  std::unique_ptr<flann::Index<flann::L2_Simple<float>>> index;
};

KnnIndex::KnnIndex(std::vector<float> rows, int dim, int approximate_checks)
    : impl_(std::make_unique<Impl>()), dim_(dim), checks_(approximate_checks) {
  n_ = dim > 0 ? int(rows.size()) / dim : 0;
  impl_->rows = std::move(rows);
  if (n_ == 0) return;
  const flann::Matrix<float> data(impl_->rows.data(), size_t(n_), size_t(dim_));
  if (checks_ > 0) {
    impl_->index = std::make_unique<flann::Index<flann::L2_Simple<float>>>(data, flann::KDTreeIndexParams(4));
  } else {
    impl_->index = std::make_unique<flann::Index<flann::L2_Simple<float>>>(data, flann::KDTreeSingleIndexParams(15));
  }
  impl_->index->buildIndex();
}

KnnIndex::~KnnIndex() = default;
KnnIndex::KnnIndex(KnnIndex&&) noexcept = default;
KnnIndex& KnnIndex::operator=(KnnIndex&&) noexcept = default;

void KnnIndex::knn(const std::vector<float>& queries, int k, std::vector<int>* index,
                   std::vector<float>* dist_sq) const {
  const size_t nq = dim_ > 0 ? queries.size() / size_t(dim_) : 0;
  index->assign(nq * size_t(std::max(k, 0)), -1);
  dist_sq->assign(index->size(), std::numeric_limits<float>::infinity());
  const int kk = std::min(k, n_);
  if (nq == 0 || kk <= 0) return;
  std::vector<int> idx(nq * size_t(kk));
  std::vector<float> d2(idx.size());
  flann::Matrix<int> idx_m(idx.data(), nq, size_t(kk));
  flann::Matrix<float> d2_m(d2.data(), nq, size_t(kk));
  const flann::Matrix<float> q(const_cast<float*>(queries.data()), nq, size_t(dim_));
  const int checks = checks_ > 0 ? checks_ : int(flann::FLANN_CHECKS_UNLIMITED);
  impl_->index->knnSearch(q, idx_m, d2_m, size_t(kk), flann::SearchParams(checks, 0.f, true));
  for (size_t i = 0; i < nq; ++i)
    for (int j = 0; j < kk; ++j) {
      (*index)[i * size_t(k) + size_t(j)] = idx[i * size_t(kk) + size_t(j)];
      (*dist_sq)[i * size_t(k) + size_t(j)] = d2[i * size_t(kk) + size_t(j)];
    }
}

void KnnIndex::radius(const std::vector<float>& queries, double radius_m, std::vector<std::vector<int>>* index,
                      std::vector<std::vector<float>>* dist_sq) const {
  const size_t nq = dim_ > 0 ? queries.size() / size_t(dim_) : 0;
  index->assign(nq, {});
  dist_sq->assign(nq, {});
  if (nq == 0 || n_ == 0) return;
  const flann::Matrix<float> q(const_cast<float*>(queries.data()), nq, size_t(dim_));
  impl_->index->radiusSearch(q, *index, *dist_sq, float(radius_m * radius_m),
                             flann::SearchParams(flann::FLANN_CHECKS_UNLIMITED, 0.f, /*sorted=*/false));
}

}  // namespace cairn::registration
