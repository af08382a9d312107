#include "methods/neighbours.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <nanoflann.hpp>

#include "methods/core/errors.hpp"
#include "methods/core/parallel.hpp"

namespace mfv {

namespace {
/// nanoflann dataset adaptor over the dim × N position matrix.
struct Cloud {
  const Eigen::MatrixXd* x;
  std::size_t kdtree_get_point_count() const { return static_cast<std::size_t>(x->cols()); }
  double kdtree_get_pt(std::size_t i, std::size_t d) const { return (*x)(d, i); }
  template <class B>
  bool kdtree_get_bbox(B&) const { return false; }
};
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>,
                                                 Cloud, -1, unsigned>;
}  // namespace

struct NeighbourSearch::Impl {
  Eigen::MatrixXd x;
  Cloud cloud;
  std::unique_ptr<Tree> tree;
};

NeighbourSearch::NeighbourSearch(const ParticleSet& p) : impl_(std::make_unique<Impl>()) {
  impl_->x = p.x;
  impl_->cloud.x = &impl_->x;
  impl_->tree = std::make_unique<Tree>(p.dim, impl_->cloud,
                                       nanoflann::KDTreeSingleIndexAdaptorParams(16));
  impl_->tree->buildIndex();
}

NeighbourSearch::~NeighbourSearch() = default;

void NeighbourSearch::within(const double* point, double radius, std::vector<int>& out) const {
  out.clear();
  std::vector<std::pair<unsigned, double>> hits;  // local: queries may run concurrently
  nanoflann::SearchParams params(32, 0.0, false);
  // nanoflann's L2_Simple metric works with squared distances.
  impl_->tree->radiusSearch(point, radius * radius * (1 + 1e-12), hits, params);
  out.reserve(hits.size());
  for (const auto& h : hits) out.push_back(static_cast<int>(h.first));
  std::sort(out.begin(), out.end());
}

NeighbourLists::NeighbourLists(double skin) : skin_(skin) {
  if (!(skin >= 0) || !std::isfinite(skin))
    throw InputError(fmt::format("the neighbour-list skin must be a finite length >= 0, got {}; "
                                 "0 searches afresh whenever anything moved",
                                 skin));
}

namespace {
/// The largest distance a column of `x` has moved from the same column of `x0`.
double largest_move(const Eigen::MatrixXd& x, const Eigen::MatrixXd& x0) {
  double m2 = 0;
  for (Eigen::Index j = 0; j < x.cols(); ++j) m2 = std::max(m2, (x.col(j) - x0.col(j)).squaredNorm());
  return std::sqrt(m2);
}
}  // namespace

bool NeighbourLists::update(const Eigen::MatrixXd& particles, const Eigen::MatrixXd& points,
                            double radius, int threads) {
  if (!(radius >= 0) || !std::isfinite(radius))
    throw std::logic_error("a neighbour search radius must be finite and >= 0");
  const bool same_shape = radius <= radius_ && particles.rows() == particles0_.rows() &&
                          particles.cols() == particles0_.cols() &&
                          points.rows() == points0_.rows() && points.cols() == points0_.cols();
  if (same_shape) {
    const double moved = largest_move(particles, particles0_) + largest_move(points, points0_);
    // skin 0: valid only while nothing moved (the plain search, bit for bit).
    if (skin_ > 0 ? moved <= skin_ : moved == 0) return false;
  }
  ParticleSet p;
  p.dim = static_cast<int>(particles.rows());
  p.x = particles;
  const NeighbourSearch search(p);
  const int nq = static_cast<int>(points.cols());
  const double reach = radius + skin_;
  // Per-point lists, then concatenated in point order: the same lists on any thread count.
  std::vector<std::vector<int>> found(nq);
#pragma omp parallel for schedule(static) num_threads(std::max(1, threads)) \
    if (run_parallel(threads, nq))
  for (int q = 0; q < nq; ++q) search.within(points.col(q).data(), reach, found[q]);
  offsets_.assign(nq + 1, 0);
  for (int q = 0; q < nq; ++q) offsets_[q + 1] = offsets_[q] + static_cast<int>(found[q].size());
  index_.resize(offsets_[nq]);
  for (int q = 0; q < nq; ++q) std::copy(found[q].begin(), found[q].end(), index_.begin() + offsets_[q]);
  particles0_ = particles;
  points0_ = points;
  radius_ = radius;
  ++rebuilds_;
  return true;
}

}  // namespace mfv
