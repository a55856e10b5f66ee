// bake.cpp: per-point ground truth, parallel over points (results indexed by point, so the
// output does not depend on the thread count).
#include "ltm/render/bake.h"

#include <cstdlib>

#include "ltm/core/error.h"
#include "ltm/core/parallel.h"
#include "ltm/core/progress.h"

namespace ltm {

Shard Shard::parse(const std::string &s) {
    Shard sh;
    const size_t slash = s.find('/');
    try {
        if (slash == std::string::npos) throw std::invalid_argument("");
        size_t used = 0;
        sh.index = std::stoi(s.substr(0, slash), &used);
        if (used != slash) throw std::invalid_argument("");
        sh.count = std::stoi(s.substr(slash + 1), &used);
        if (used != s.size() - slash - 1) throw std::invalid_argument("");
    } catch (const std::exception &) {
        LTM_THROW("--shard ", s, ": expected i/N, e.g. 0/4");
    }
    if (sh.count < 1 || sh.index < 0 || sh.index >= sh.count)
        LTM_THROW("--shard ", s, ": need 0 <= i < N");
    return sh;
}


std::string shard_path(const std::string &dir, const Shard &shard) {
    return dir + "/shard-" + std::to_string(shard.index) + "-of-" + std::to_string(shard.count) + ".safetensors";
}
std::string merged_path(const std::string &dir) { return dir + "/irradiance.safetensors"; }

BakedPoints bake_points(const PathTracer &pt, const PointSet &query, int64_t begin, int64_t end,
                        const BakeSettings &s) {
    LTM_CHECK(query.n_columns() == 9);
    const int64_t n = end - begin;
    BakedPoints out;
    out.direct.resize(size_t(n));
    out.indirect.resize(size_t(n));
    const int nb = s.bin_resolution * s.bin_resolution;
    if (s.bins) out.bins.resize(size_t(n) * size_t(nb));
    const uint64_t rays0 = pt.accel().rays_traced();
    Progress progress("bake", uint64_t(n), "points", s.progress);
    parallel_for(0, n, 16, [&](int64_t i0, int64_t i1) {
        for (int64_t i = i0; i < i1; ++i) {
            const int64_t k = begin + i;
            const Vec3f p = query.vec3(size_t(k), 0), nrm = query.vec3(size_t(k), 3);
            const IrradianceEstimate e = pt.irradiance(p, nrm, uint64_t(k), s.spp);
            out.direct[size_t(i)] = e.direct;
            out.indirect[size_t(i)] = e.indirect;
            if (s.bins) {
                const auto b = pt.incident_radiance_bins(p, nrm, uint64_t(k), s.bin_resolution, s.bin_spp, !s.bins_indirect);
                std::copy(b.begin(), b.end(), out.bins.begin() + i * nb);
            }
        }
        progress.add(uint64_t(i1 - i0));
    });
    out.seconds = progress.finish();
    out.rays = pt.accel().rays_traced() - rays0;
    return out;
}

void check_points_match_scene(const EmbreeAccel &accel, const PointSet &query, const std::string &where) {
    const Bounds3f b = accel.scene().bounds();
    const float tol = 1e-3f * (1.f + max_component(b.extent()));
    const size_t n = query.size();
    if (n == 0) LTM_THROW(where, ": no points");
    const size_t step = std::max<size_t>(1, n / 256);
    for (size_t i = 0; i < n; i += step) {
        const Vec3f p = query.vec3(i, 0), nrm = query.vec3(i, 3);
        if (!is_finite(p) || std::abs(length(nrm) - 1.f) > 1e-3f)
            LTM_THROW(where, ": point ", i, " has a non-finite position or a non-unit normal");
        if (p.x < b.lo.x - tol || p.y < b.lo.y - tol || p.z < b.lo.z - tol || p.x > b.hi.x + tol ||
            p.y > b.hi.y + tol || p.z > b.hi.z + tol)
            LTM_THROW(where, ": point ", i, " at ", p, " lies outside the scene bounds: the points belong to another scene");
        // A surface point is found again by a short ray from just above it back along -n.
        const Ray back{p + nrm * tol, -nrm, 0.f, 2.f * tol};
        if (!accel.occluded(back))
            LTM_THROW(where, ": point ", i, " at ", p, " is not on any surface of the scene: the points belong to another scene");
    }
}

}  // namespace ltm
