// direct_light.cpp: analytic unshadowed irradiance of triangle emitters + the visibility ratio.
#include "ltm/render/direct_light.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>

#include "ltm/core/error.h"
#include "ltm/core/rng.h"
#include "ltm/core/sampling.h"
#include "ltm/render/ray.h"

namespace ltm {

namespace {
constexpr uint64_t k_ratio_domain = 5ull << 60;   // streams disjoint from the path tracer's
// share_factor: the exact E_unocc shares the samples out within this many bounding radii of a
// light; beyond, the small-source approximation (a disc seen from 3 radii: within ~5 %).
constexpr float k_near_radii = 3.f;

// Bounds on n̂_t·(p − v) over the triangles t of a node (centre c, radius R, normal cone of half-angle
// α about its axis): n̂_t·(p − v) = n̂_t·d + n̂_t·(c − v) with d = p − c and |n̂_t·(c − v)| ≤ R, and n̂_t·d
// lies between |d| cos(min(π, β + α)) and |d| cos(max(0, β − α)), β the angle of d to the axis.
struct ConeBounds {
    float most, least, r;   // the bounds on n̂_t·d, and R with a margin for rounding
};
template <class Node>
ConeBounds cone_bounds(const Node &node, Vec3f p) {
    const Vec3f d = p - node.centre;
    const float dist = length(d), r = node.radius * 1.0001f + 1e-6f * dist;
    // sin β from the cross product: √(1 − cos²β) loses ~1e-4 near β = 0 or π, more than the margin.
    const float cb = dist > 0.f ? std::clamp(dot(node.axis, d) / dist, -1.f, 1.f) : 1.f,
                sb = dist > 0.f ? std::min(1.f, length(cross(node.axis, d)) / dist) : 0.f;
    const float ca = node.cos_cone, sa = node.sin_cone;
    return {cb >= ca ? dist : dist * (cb * ca + sb * sa),            // β ≤ α: cos 0
            ca + cb <= 0.f ? -dist : dist * (cb * ca - sb * sa),   // β + α ≥ π: cos π
            r};
}
}  // namespace

namespace {
using D3 = std::array<double, 3>;
D3 diff(Vec3f a, Vec3f b) { return {double(a.x) - double(b.x), double(a.y) - double(b.y), double(a.z) - double(b.z)}; }   // a − b
double dot3(const D3 &a, const D3 &b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
D3 cross3(const D3 &a, const D3 &b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }

// One edge's term of Lambert's formula, θ · n·(â × b̂)/|â × b̂| for the directions a, b from the
// receiver to its ends (0 for an edge through the receiver or of zero angle: no area from it). In
// double: a lamp's terms are each of the order of its angular size and their sum of its square, so
// a far lamp's sum cancels most of its terms' digits (in float, a 0.2 m sphere 3 m away came out
// 0.5 % off).
double edge_term(D3 a, D3 b, const D3 &n) {
    const double la = std::sqrt(dot3(a, a)), lb = std::sqrt(dot3(b, b));
    if (!(la > 0.0) || !(lb > 0.0)) return 0.0;
    for (int i = 0; i < 3; ++i) a[i] /= la, b[i] /= lb;
    const D3 c = cross3(a, b);
    const double len = std::sqrt(dot3(c, c));
    if (!(len > 0.0)) return 0.0;
    return std::atan2(len, dot3(a, b)) * dot3(n, c) / len;   // atan2: accurate for small angles
}

// Lambert's sum for one triangle clipped to the hemisphere, before its sign is dropped: the terms of
// every front-facing triangle share one sign (header), so a mesh's sum can cancel shared edges.
double triangle_sum(Vec3f p, Vec3f nf, Vec3f v0, Vec3f v1, Vec3f v2) {
    // One-sided emitter: the receiver must be on the side its normal points to.
    if (!(dot(cross(v1 - v0, v2 - v0), p - v0) > 0.f)) return 0.0;
    // Clip to the receiver's upper hemisphere (Sutherland–Hodgman against n·(x − p) = 0), in
    // coordinates relative to p: a convex polygon of at most 4 vertices above the horizon.
    const D3 n{nf.x, nf.y, nf.z};
    const D3 in[3] = {diff(v0, p), diff(v1, p), diff(v2, p)};
    D3 poly[4];
    int m = 0;
    for (int i = 0; i < 3; ++i) {
        const D3 &a = in[i], &b = in[(i + 1) % 3];
        const double da = dot3(n, a), db = dot3(n, b);
        if (da >= 0.0) poly[m++] = a;
        if ((da >= 0.0) != (db >= 0.0)) {
            const double t = da / (da - db);
            poly[m++] = {a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, a[2] + (b[2] - a[2]) * t};
        }
    }
    if (m < 3) return 0.0;
    // Lambert: E = 1/2 · Σ_i θ_i · n·(r_i × r_{i+1})/|r_i × r_{i+1}| with unit r_i; the clipped
    // polygon is convex and above the horizon, so the terms share one sign (the winding's).
    double sum = 0.0;
    for (int i = 0; i < m; ++i) sum += edge_term(poly[i], poly[(i + 1) % m], n);
    return 0.5 * sum;
}
}  // namespace

float triangle_irradiance(Vec3f p, Vec3f n, Vec3f v0, Vec3f v1, Vec3f v2) {
    return float(std::abs(triangle_sum(p, n, v0, v1, v2)));
}

bool RatioDirectLight::supports(const Scene &scene) {
    for (const auto &m : scene.materials)
        if (m.is_emissive() && !m.emission.is_constant()) return false;
    return true;
}

RatioDirectLight::RatioDirectLight(const EmbreeAccel &accel, uint64_t seed) : m_accel(accel), m_seed(seed) {
    const Scene &scene = accel.scene();
    for (const auto &mesh : scene.meshes) {
        const Material &mat = scene.materials[size_t(mesh.material)];
        if (!mat.is_emissive()) continue;
        if (!mat.emission.is_constant())
            LTM_THROW(scene.name, ": material '", mat.name, "' has textured emission; the ratio estimator needs constant radiance");
        Light l;
        l.radiance = mat.emission.color_a;
        double total = 0.0;
        D3 centroid{0.0, 0.0, 0.0};
        for (size_t t = 0; t < mesh.n_triangles(); ++t) {
            if (!(mesh.area(t) > 0.f)) continue;
            for (int k = 0; k < 3; ++k) l.v.push_back(mesh.vertex(t, k));
            l.plane.push_back(mesh.cross_normal(t));
            l.normal.push_back(normalize(l.plane.back()));
            const double a = double(mesh.area(t));
            total += a;
            l.cdf.push_back(total);
            const Vec3f c = (mesh.vertex(t, 0) + mesh.vertex(t, 1) + mesh.vertex(t, 2)) / 3.f;
            for (int k = 0; k < 3; ++k) centroid[size_t(k)] += a * double(c[k]);
        }
        if (l.cdf.empty()) continue;
        l.area = float(total);
        l.centroid = Vec3f(float(centroid[0] / total), float(centroid[1] / total), float(centroid[2] / total));
        for (double &c : l.cdf) c /= total;
        l.cdf.back() = 1.0;
        l.index_edges();
        m_lights.push_back(std::move(l));
    }
}

void RatioDirectLight::Light::index_edges() {
    const size_t T = v.size() / 3;
    // Directed edge (a → b) of triangle t, side k: v[3t + k] → v[3t + (k + 1) % 3], keyed by its
    // ends' coordinates (files repeat a shared vertex as often as they index it). An edge is paired
    // with the one traversing it the other way when exactly one does and no third side runs along it.
    using Key = std::array<float, 6>;
    std::map<Key, std::vector<uint32_t>> by_edge;   // ordered key: the pairing does not depend on hashing
    auto key = [](Vec3f a, Vec3f b) { return Key{a.x, a.y, a.z, b.x, b.y, b.z}; };
    for (uint32_t s = 0; s < uint32_t(3 * T); ++s) {
        const uint32_t t = s / 3, k = s % 3;
        const Vec3f a = v[3 * t + k], b = v[3 * t + (k + 1) % 3];
        // Undirected: the smaller end first.
        const bool forward = std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
        by_edge[forward ? key(a, b) : key(b, a)].push_back(s);
    }
    twin.assign(3 * T, -1);
    for (const auto &[k, list] : by_edge) {
        if (list.size() != 2) continue;
        const uint32_t s0 = list[0], s1 = list[1];
        const Vec3f a0 = v[3 * (s0 / 3) + s0 % 3], a1 = v[3 * (s1 / 3) + s1 % 3];
        if (a0 == a1) continue;   // the same direction: the two faces disagree on their winding, no cancellation
        twin[s0] = int32_t(s1 / 3), twin[s1] = int32_t(s0 / 3);
    }
    // The triangles' tree (header): leaves of ≤ 8, split at the median of the centroids' longest
    // extent (ties by index), each node with its bounding sphere and normal cone.
    order.resize(T);
    for (uint32_t t = 0; t < uint32_t(T); ++t) order[t] = t;
    tree.clear();
    sides.clear();
    build_node(0, uint32_t(T));
    // Each node's sides whose twin lies outside it (or has none): all a node wholly in view adds,
    // its inner edges cancelling.
    std::vector<uint32_t> slot(T);   // triangle -> its place in `order`
    for (uint32_t i = 0; i < uint32_t(T); ++i) slot[order[i]] = i;
    // A node whose outline is more than twice its triangles (a soup, no shared edges) keeps none and
    // is never taken whole (its triangles are tested one by one): the stored sides stay O(triangles)
    // per level for a connected mesh, not 3 per triangle per level.
    for (Node &node : tree) {
        node.sides_lo = uint32_t(sides.size());
        for (uint32_t i = node.lo; i < node.hi; ++i)
            for (uint32_t k = 0; k < 3; ++k) {
                const uint32_t sd = 3 * order[i] + k;
                const int32_t tw = twin[sd];
                if (tw < 0 || slot[size_t(tw)] < node.lo || slot[size_t(tw)] >= node.hi) sides.push_back(sd);
            }
        node.whole_ok = sides.size() - node.sides_lo <= 2 * size_t(node.hi - node.lo);
        if (!node.whole_ok) sides.resize(node.sides_lo);
        node.sides_hi = uint32_t(sides.size());
    }
}

int32_t RatioDirectLight::Light::build_node(uint32_t lo, uint32_t hi) {
    const int32_t id = int32_t(tree.size());
    tree.push_back({});
    Vec3f blo = v[3 * order[lo]], bhi = blo, clo(std::numeric_limits<float>::infinity()), chi(-std::numeric_limits<float>::infinity());
    Vec3f nsum(0.f);
    for (uint32_t i = lo; i < hi; ++i) {
        const uint32_t t = order[i];
        for (int k = 0; k < 3; ++k) blo = min(blo, v[3 * t + size_t(k)]), bhi = max(bhi, v[3 * t + size_t(k)]);
        const Vec3f ct = (v[3 * t] + v[3 * t + 1] + v[3 * t + 2]) / 3.f;
        clo = min(clo, ct), chi = max(chi, ct);
        nsum += normal[t];
    }
    Node node;
    node.lo = lo, node.hi = hi;
    node.centre = (blo + bhi) * 0.5f;
    for (uint32_t i = lo; i < hi; ++i)
        for (int k = 0; k < 3; ++k) node.radius = std::max(node.radius, length(v[3 * order[i] + size_t(k)] - node.centre));
    const float len = length(nsum);
    node.axis = len > 0.f ? nsum / len : Vec3f(0.f, 0.f, 1.f);
    node.cos_cone = len > 0.f ? 1.f : -1.f;
    for (uint32_t i = lo; i < hi && len > 0.f; ++i) node.cos_cone = std::min(node.cos_cone, dot(node.axis, normal[order[i]]));
    // Rounding in the members' normals: a cone a hair wider than measured.
    node.cos_cone = std::max(-1.f, node.cos_cone - 1e-5f);
    node.sin_cone = std::sqrt(std::max(0.f, 1.f - node.cos_cone * node.cos_cone));
    if (hi - lo > 8) {
        int axis = 0;
        for (int a = 1; a < 3; ++a)
            if (chi[a] - clo[a] > chi[axis] - clo[axis]) axis = a;
        const uint32_t mid = lo + (hi - lo) / 2;
        auto key = [&](uint32_t t) { return v[3 * t][axis] + v[3 * t + 1][axis] + v[3 * t + 2][axis]; };
        std::nth_element(order.begin() + lo, order.begin() + mid, order.begin() + hi,
                         [&](uint32_t x, uint32_t y) { return key(x) != key(y) ? key(x) < key(y) : x < y; });
        node.child[0] = build_node(lo, mid);
        node.child[1] = build_node(mid, hi);
    }
    tree[size_t(id)] = node;
    return id;
}

float RatioDirectLight::unoccluded_factor(const Light &l, Vec3f p, Vec3f n) const {
    // Σ_t |S_t| over the triangles = |Σ_t S_t| (their signs agree, header). An edge shared by two
    // front-facing triangles that lie wholly above the horizon appears in both with opposite
    // directions, and its terms cancel exactly: only the edges around that region are summed (a
    // tessellated sphere: its outline, not its ~1 000 faces in view). Triangles that the horizon
    // cuts keep their clipped sums whole. The tree skips subtrees wholly behind their faces and takes
    // subtrees wholly in view by their boundary sides.
    const size_t T = l.plane.size();
    struct Scratch {
        std::vector<uint8_t> whole;          // per triangle: front-facing and wholly above the horizon
        std::vector<int32_t> stack, nodes;   // the walk; the nodes wholly in view
        std::vector<uint32_t> loose;         // triangles in view found one by one (in leaves)
    };
    thread_local Scratch sc;
    if (sc.whole.size() < T) sc.whole.resize(T, 0);   // all 0 between calls: each call clears what it set
    sc.stack.assign(1, 0), sc.nodes.clear(), sc.loose.clear();
    const D3 nd{n.x, n.y, n.z};
    double sum = 0.0;
    while (!sc.stack.empty()) {
        const Light::Node &node = l.tree[size_t(sc.stack.back())];
        const int32_t id = sc.stack.back();
        sc.stack.pop_back();
        const bool leaf = node.child[0] < 0;
        if (!leaf || node.hi - node.lo > 2) {   // (a quad's two triangles are tested faster one by one)
            const ConeBounds b = cone_bounds(node, p);
            if (b.most + b.r <= 0.f) continue;   // every face turned away from p: adds 0
            // Every face towards p and above its horizon (and the node's outline kept: index_edges).
            if (node.whole_ok && b.least - b.r > 0.f && dot(n, node.centre - p) > b.r) {
                for (uint32_t i = node.lo; i < node.hi; ++i) sc.whole[l.order[i]] = 1;
                sc.nodes.push_back(id);
                continue;
            }
        }
        if (!leaf) {
            sc.stack.push_back(node.child[1]), sc.stack.push_back(node.child[0]);
            continue;
        }
        for (uint32_t i = node.lo; i < node.hi; ++i) {
            const uint32_t t = l.order[i];
            const Vec3f v0 = l.v[3 * t];
            if (!(dot(l.plane[t], p - v0) > 0.f)) continue;   // behind the emitter or edge-on: 0
            // Wholly above as triangle_sum clips (in double): its sum is then its three edges' terms.
            if (dot3(nd, diff(v0, p)) >= 0.0 && dot3(nd, diff(l.v[3 * t + 1], p)) >= 0.0 && dot3(nd, diff(l.v[3 * t + 2], p)) >= 0.0)
                sc.whole[t] = 1, sc.loose.push_back(t);
            else
                sum += triangle_sum(p, n, v0, l.v[3 * t + 1], l.v[3 * t + 2]);
        }
    }
    const auto side_term = [&](uint32_t sd) {
        const int32_t tw = l.twin[sd];
        if (tw >= 0 && sc.whole[size_t(tw)]) return 0.0;   // cancels against its twin's
        const size_t t = sd / 3, k = sd % 3;
        return 0.5 * edge_term(diff(l.v[3 * t + k], p), diff(l.v[3 * t + (k + 1) % 3], p), nd);
    };
    for (const int32_t id : sc.nodes)
        for (uint32_t i = l.tree[size_t(id)].sides_lo; i < l.tree[size_t(id)].sides_hi; ++i) sum += side_term(l.sides[i]);
    for (const uint32_t t : sc.loose)
        for (uint32_t k = 0; k < 3; ++k) sum += side_term(3 * t + k);
    // Clear only what this call set: O(what it visited), not O(triangles) a receiver.
    for (const int32_t id : sc.nodes)
        for (uint32_t i = l.tree[size_t(id)].lo; i < l.tree[size_t(id)].hi; ++i) sc.whole[l.order[i]] = 0;
    for (const uint32_t t : sc.loose) sc.whole[t] = 0;
    return float(std::abs(sum));
}

Vec3f RatioDirectLight::unoccluded(Vec3f p, Vec3f n) const {
    Vec3f e(0.f);
    for (const Light &l : m_lights) e += l.radiance * unoccluded_factor(l, p, n);
    return e;
}

float RatioDirectLight::share_factor(const Light &l, Vec3f p, Vec3f n, bool &exact) const {
    exact = true;
    const Light::Node &root = l.tree[0];
    const ConeBounds b = cone_bounds(root, p);
    // Wholly below the horizon (unoccluded_factor clips there) or behind every face: exactly 0.
    const float above = dot(n, root.centre - p);
    if (above + b.r <= 0.f || b.most + b.r <= 0.f) return 0.f;
    // Near the lamp, or where the horizon or the lamp's own faces cut it (the approximation is worst
    // there, and a share too small would leave the part in view without a sample): the exact sum.
    if (length(p - root.centre) <= k_near_radii * root.radius || above - b.r <= 0.f || b.least - b.r <= 0.f)
        return unoccluded_factor(l, p, n);
    exact = false;
    const Vec3f to = l.centroid - p;
    const float d2 = dot(to, to);
    if (!(d2 > 0.f)) return unoccluded_factor(l, p, n);   // (a closed lamp's centroid inside it)
    const Vec3f w = to / std::sqrt(d2);
    // Every face towards p (b.least > r above): the mean normal's cosine stands for the faces'.
    const float approx = l.area * std::max(0.f, dot(n, w)) * std::max(0.f, -dot(root.axis, w)) / d2;
    return std::max(approx, 1e-3f * l.area / d2);   // (wholly in view: > 0 but for rounding)
}

Vec3f RatioDirectLight::irradiance(Vec3f p, Vec3f n, uint64_t key, int n_samples) const {
    if (n_samples <= 0) LTM_THROW("direct light: samples per point must be > 0, got ", n_samples);
    // The luminance that shares the samples out (share_factor), and which lights have their exact
    // E_unocc already.
    const size_t n_lights = m_lights.size();
    thread_local std::vector<float> g;
    thread_local std::vector<uint8_t> exact;
    g.assign(n_lights, 0.f), exact.assign(n_lights, 0);
    double total = 0.0;
    for (size_t i = 0; i < n_lights; ++i) {
        bool ex = false;
        g[i] = share_factor(m_lights[i], p, n, ex);
        exact[i] = ex;
        total += double(g[i]) * double(luminance(m_lights[i].radiance));
    }
    if (!(total > 0.0)) return Vec3f(0.f);
    Pcg32 rng(hash_keys({m_seed, k_ratio_domain, key}));
    Vec3f e(0.f);
    for (size_t i = 0; i < n_lights; ++i) {
        const Light &l = m_lights[i];
        const double share = double(g[i]) * double(luminance(l.radiance)) / total;
        if (!(share > 0.0)) continue;
        const int k = std::max(1, int(std::lround(share * double(n_samples))));
        double seen = 0.0, all = 0.0;
        for (int s = 0; s < k; ++s) {
            // Uniform on the light's area: triangle by area, then a uniform point on it.
            const double u0 = double(rng.next_float());
            const size_t tri = size_t(std::lower_bound(l.cdf.begin(), l.cdf.end(), u0) - l.cdf.begin()), t = 3 * tri;
            const Vec2f b = sample_uniform_triangle({rng.next_float(), rng.next_float()});
            const Vec3f q = l.v[t] * b.x + l.v[t + 1] * b.y + l.v[t + 2] * (1.f - b.x - b.y);
            const Vec3f to = q - p;
            const float d2 = dot(to, to);
            if (!(d2 > 0.f)) continue;
            const Vec3f wl = to / std::sqrt(d2);
            const float cos_x = dot(n, wl), cos_light = -dot(l.normal[tri], wl);
            if (cos_x <= 0.f || cos_light <= 0.f) continue;   // w = 0 in both sums
            const double w = double(cos_x) * double(cos_light) / double(d2);   // the constant area pdf cancels
            all += w;
            if (!m_accel.occluded(shadow_ray(p, n, q))) seen += w;
        }
        // No sample on the part above the horizon (a sliver): its visibility is unknown; 0, as
        // the MIS estimator would give from these samples. No sample seen: 0 whatever E_unocc is.
        if (!(all > 0.0) || !(seen > 0.0)) continue;
        const float e_unocc = exact[i] ? g[i] : unoccluded_factor(l, p, n);
        e += l.radiance * (e_unocc * float(seen / all));
    }
    return e;
}

IrradianceImages direct_images_ratio(const RatioDirectLight &light, const GBuffer &gb, int spp) {
    if (spp <= 0) LTM_THROW("direct light: samples per pixel must be > 0, got ", spp);
    return estimate_images(gb, "direct light", [&](size_t k) {
        return IrradianceEstimate{light.irradiance(gb.position[k], gb.normal[k], uint64_t(gb.hit_pixels[k]), spp), Vec3f(0.f)};
    });
}

}  // namespace ltm
