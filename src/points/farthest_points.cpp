// farthest_points.cpp: exact FPS (definition in the header), through a k-d tree of subtree maxima.
//
// Invariant: every node holds max_j dist[j] over its points and the lowest original index that
// attains it, so the root names the next sample exactly as the plain loop's argmax (ties to the lower
// index). A new sample c lowers dist[j] = min(dist[j], |x_j − c|²) only where |x_j − c|² < dist[j];
// when the node's box lies at least its maximum away from c, no point in it changes and the node is
// skipped. The per-point distance is the plain loop's float expression, so the values are identical,
// and the box bound is taken in double and shrunk by 10⁻⁶ (the float expression is within ~3·10⁻⁷
// of the exact one), so a skip never hides a change.
#include "ltm/points/farthest_points.h"

#include <algorithm>
#include <limits>

namespace ltm {

namespace {
constexpr uint32_t k_leaf = 32;   // points per leaf: one cache-friendly loop, few nodes

class FpsTree {
public:
    FpsTree(const float *x, size_t n) : m_x(x) {
        std::vector<uint32_t> order(n);
        for (uint32_t i = 0; i < uint32_t(n); ++i) order[i] = i;
        m_nodes.reserve(4 * (n / k_leaf + 1));
        m_nodes.emplace_back();
        build(0, order, 0, uint32_t(n));
        // Points in leaf order, one array per coordinate, so a leaf is one contiguous loop.
        m_px.resize(n), m_py.resize(n), m_pz.resize(n), m_index = order;
        m_dist.assign(n, std::numeric_limits<float>::infinity());
        for (size_t s = 0; s < n; ++s) m_px[s] = x[3 * order[s]], m_py[s] = x[3 * order[s] + 1], m_pz[s] = x[3 * order[s] + 2];
    }

    /// Lowers every distance by the sample at original index `c`; returns the next sample.
    int64_t add(int64_t c) {
        m_c[0] = m_x[3 * c], m_c[1] = m_x[3 * c + 1], m_c[2] = m_x[3 * c + 2];
        update(0);
        return m_nodes[0].arg;
    }

private:
    struct Node {
        float lo[3], hi[3];
        float max = std::numeric_limits<float>::infinity();
        int64_t arg = 0;
        uint32_t b = 0, e = 0, left = 0;   // left == 0: a leaf (the root is never a child)
    };

    void build(uint32_t id, std::vector<uint32_t> &order, uint32_t b, uint32_t e) {
        Node nd;
        nd.b = b, nd.e = e, nd.arg = b < e ? order[b] : 0;
        for (int a = 0; a < 3; ++a) nd.lo[a] = std::numeric_limits<float>::infinity(), nd.hi[a] = -nd.lo[a];
        for (uint32_t s = b; s < e; ++s)
            for (int a = 0; a < 3; ++a) nd.lo[a] = std::min(nd.lo[a], m_x[3 * order[s] + a]), nd.hi[a] = std::max(nd.hi[a], m_x[3 * order[s] + a]);
        if (e - b > k_leaf) {
            int axis = 0;
            for (int a = 1; a < 3; ++a)
                if (nd.hi[a] - nd.lo[a] > nd.hi[axis] - nd.lo[axis]) axis = a;
            const uint32_t mid = b + (e - b) / 2;
            // Ties ordered by index, so the split (and with it the tree) is a function of the input alone.
            std::nth_element(order.begin() + b, order.begin() + mid, order.begin() + e, [&](uint32_t i, uint32_t j) {
                const float xi = m_x[3 * i + axis], xj = m_x[3 * j + axis];
                return xi < xj || (xi == xj && i < j);
            });
            nd.left = uint32_t(m_nodes.size());
            m_nodes.emplace_back(), m_nodes.emplace_back();
            m_nodes[id] = nd;
            build(nd.left, order, b, mid);
            build(nd.left + 1, order, mid, e);
            return;
        }
        m_nodes[id] = nd;
    }

    void update(uint32_t id) {
        Node &nd = m_nodes[id];   // stable: m_nodes never grows after the constructor
        double lb = 0.0;   // squared distance from the sample to the node's box
        for (int a = 0; a < 3; ++a) {
            const double g = std::max({double(nd.lo[a]) - m_c[a], double(m_c[a]) - nd.hi[a], 0.0});
            lb += g * g;
        }
        if (lb * (1.0 - 1e-6) >= double(nd.max)) return;
        if (nd.left == 0) {
            const float lx = m_c[0], ly = m_c[1], lz = m_c[2];
            float best = -1.f;
            int64_t arg = 0;
            for (uint32_t s = nd.b; s < nd.e; ++s) {
                const float dx = m_px[s] - lx, dy = m_py[s] - ly, dz = m_pz[s] - lz;
                const float d = std::min(m_dist[s], dx * dx + dy * dy + dz * dz);
                m_dist[s] = d;
                if (d > best || (d == best && int64_t(m_index[s]) < arg)) best = d, arg = int64_t(m_index[s]);
            }
            nd.max = best, nd.arg = arg;
            return;
        }
        update(nd.left);
        update(nd.left + 1);
        const Node &l = m_nodes[nd.left], &r = m_nodes[nd.left + 1];
        const bool take_left = l.max > r.max || (l.max == r.max && l.arg < r.arg);
        nd.max = take_left ? l.max : r.max;
        nd.arg = take_left ? l.arg : r.arg;
    }

    const float *m_x;
    std::vector<Node> m_nodes;
    std::vector<float> m_px, m_py, m_pz, m_dist;
    std::vector<uint32_t> m_index;   // leaf order -> original index
    float m_c[3] = {0.f, 0.f, 0.f};
};
}  // namespace

std::vector<int64_t> farthest_points(const float *x, size_t n, size_t m) {
    std::vector<int64_t> out(m);
    if (m == 0) return out;
    FpsTree tree(x, n);
    out[0] = 0;
    for (size_t i = 1; i < m; ++i) out[i] = tree.add(out[i - 1]);
    return out;
}

std::vector<int64_t> farthest_points_reference(const float *x, size_t n, size_t m) {
    std::vector<float> dist(n, std::numeric_limits<float>::infinity());
    std::vector<int64_t> out(m);
    int64_t last = 0;
    if (m > 0) out[0] = 0;
    for (size_t i = 1; i < m; ++i) {
        const float lx = x[3 * last], ly = x[3 * last + 1], lz = x[3 * last + 2];
        float best = -1.f;
        int64_t best_j = 0;
        for (size_t j = 0; j < n; ++j) {
            const float dx = x[3 * j] - lx, dy = x[3 * j + 1] - ly, dz = x[3 * j + 2] - lz;
            const float d = std::min(dist[j], dx * dx + dy * dy + dz * dz);
            dist[j] = d;
            if (d > best) best = d, best_j = int64_t(j);   // strict: ties keep the lower index
        }
        out[i] = last = best_j;
    }
    return out;
}

}  // namespace ltm
