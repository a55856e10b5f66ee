// knn_points.cpp: nanoflann's k-d tree, each query's neighbours sorted by (distance, index).
#include "ltm/points/knn_points.h"

#include <algorithm>
#include <utility>

#include <nanoflann.hpp>

#include "ltm/core/error.h"
#include "ltm/core/parallel.h"

namespace ltm {

namespace {
struct PointCloudAdaptor {
    const float *pts;
    size_t n;
    size_t kdtree_get_point_count() const { return n; }
    float kdtree_get_pt(size_t i, size_t dim) const { return pts[3 * i + dim]; }
    template <class B> bool kdtree_get_bbox(B &) const { return false; }
};
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, PointCloudAdaptor>,
                                                   PointCloudAdaptor, 3, uint32_t>;
}  // namespace

std::vector<int64_t> knn_points(const float *query, size_t n, const float *ref, size_t m, int64_t k) {
    if (k < 1 || size_t(k) > m) LTM_THROW("knn: k = ", k, " but only ", m, " reference points");
    PointCloudAdaptor adaptor{ref, m};
    KdTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(/*leaf_max_size=*/16));
    tree.buildIndex();
    std::vector<int64_t> out(n * size_t(k));
    parallel_for(0, int64_t(n), 256, [&](int64_t b, int64_t e) {
        const size_t kk = static_cast<size_t>(k);
        std::vector<uint32_t> idx(kk);
        std::vector<float> d2(kk);
        std::vector<std::pair<float, uint32_t>> sorted(kk);
        for (int64_t i = b; i < e; ++i) {
            nanoflann::KNNResultSet<float, uint32_t> rs(kk);
            rs.init(idx.data(), d2.data());
            tree.findNeighbors(rs, query + 3 * i, nanoflann::SearchParams(/*checks=*/32, /*eps=*/0.f, /*sorted=*/true));
            for (size_t j = 0; j < kk; ++j) sorted[j] = {d2[j], idx[j]};
            std::sort(sorted.begin(), sorted.end());   // ties by lower index
            for (size_t j = 0; j < kk; ++j) out[size_t(i) * kk + j] = int64_t(sorted[j].second);
        }
    });
    return out;
}

}  // namespace ltm
