#include "methods/neighbours.hpp"

#include <algorithm>

#include <nanoflann.hpp>

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

}  // namespace mfv
