// reference_cache.cpp: on-disk cache of path-traced reference E⁺ images (see the header).
#include "ltm/eval/reference_cache.h"

#include <cstdio>
#include <cstring>
#include <filesystem>

#include "ltm/core/error.h"
#include "ltm/core/exr.h"
#include "ltm/core/file_util.h"
#include "ltm/core/json_util.h"
#include "ltm/core/log.h"
#include "ltm/scene/scene_json.h"

namespace ltm {
namespace {

// FNV-1a, 64 bit: a stable content hash (std::hash is not stable across builds).
struct Fnv1a {
    uint64_t h = 0xcbf29ce484222325ull;
    void bytes(const void *data, size_t n) {
        const auto *p = static_cast<const unsigned char *>(data);
        for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
    }
    template <class T>
    void vec(const std::vector<T> &v) {
        const uint64_t n = v.size();
        bytes(&n, sizeof n);
        if (!v.empty()) bytes(v.data(), v.size() * sizeof(T));
    }
    void str(const std::string &s) {
        const uint64_t n = s.size();
        bytes(&n, sizeof n);
        bytes(s.data(), s.size());
    }
    template <class T>
    void pod(const T &x) { bytes(&x, sizeof x); }
};

void hash_texture(Fnv1a &f, const Texture &t) {
    // The JSON of the material names the image file; its pixels are what the tracer sees.
    if (t.image) {
        f.pod(t.image->width);
        f.pod(t.image->height);
        f.vec(t.image->pixels);
    }
}

}  // namespace

std::string reference_cache_key(const Scene &scene, const Camera &camera, int spp, const PathTracerConfig &cfg) {
    Fnv1a f;
    f.pod(k_reference_cache_version);
    // Materials (and everything else but the meshes) through their JSON form: every field the
    // scene format knows. Meshes as raw arrays: exact bits, and faster than printing floats.
    OrderedJson j = scene_to_json(scene);
    j.erase("meshes");
    j.erase("cameras");    // only the camera that is rendered matters
    j.erase("metadata");   // provenance, not content (the name stays: it seeds the tracer's streams)
    f.str(j.dump());
    for (const auto &m : scene.materials) {
        hash_texture(f, m.albedo);
        hash_texture(f, m.emission);
    }
    for (const auto &m : scene.meshes) {
        f.vec(m.positions);
        f.vec(m.uvs);
        f.vec(m.indices);
        f.pod(m.material);
    }
    for (const float v : {camera.eye.x, camera.eye.y, camera.eye.z, camera.target.x, camera.target.y, camera.target.z,
                          camera.up.x, camera.up.y, camera.up.z, camera.fov_y_deg})
        f.pod(v);
    f.pod(camera.width);
    f.pod(camera.height);
    f.pod(spp);
    f.pod(cfg.seed);
    f.pod(cfg.scene_id);
    f.pod(cfg.max_depth);
    f.pod(cfg.rr_depth);
    if (cfg.offset_length != 1.f) f.pod(cfg.offset_length);   // the default keeps the keys written before it
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(f.h));
    return hex;
}

std::optional<CachedReference> load_cached_reference(const std::string &dir, const std::string &key, int width,
                                                     int height) {
    const std::string exr = dir + "/" + key + ".exr", meta = dir + "/" + key + ".json";
    if (!std::filesystem::exists(exr) || !std::filesystem::exists(meta)) return std::nullopt;
    try {
        CachedReference ref;
        ref.seconds = parse_json_file(meta).at("seconds").get<double>();
        int w = 0, h = 0;
        std::vector<float> ch[3];
        const char *names[3] = {"R", "G", "B"};
        for (int c = 0; c < 3; ++c) {
            ch[c] = read_exr_channel(exr, names[c], &w, &h);
            if (w != width || h != height) LTM_THROW(exr, ": ", w, "×", h, " image, expected ", width, "×", height);
        }
        ref.indirect = Image(width, height);
        for (size_t i = 0; i < ref.indirect.pixels.size(); ++i) {
            ref.indirect.pixels[i] = Vec3f(ch[0][i], ch[1][i], ch[2][i]);
            if (!std::isfinite(ch[0][i] + ch[1][i] + ch[2][i])) LTM_THROW(exr, ": non-finite pixel ", i);
        }
        return ref;
    } catch (const Error &e) {
        // A damaged cache entry is bad data, not a bug: render it again. Anything else (bad_alloc,
        // a logic error) is not ours to swallow and propagates.
        log_warn("reference cache: ", e.what(), "; rendering it again");
        return std::nullopt;
    } catch (const nlohmann::json::exception &e) {
        log_warn("reference cache: ", meta, ": ", e.what(), "; rendering it again");
        return std::nullopt;
    }
}

void store_cached_reference(const std::string &dir, const std::string &key, const CachedReference &ref,
                            const OrderedJson &provenance) {
    create_directories(dir);
    const Image &img = ref.indirect;
    static_assert(sizeof(Vec3f) == 3 * sizeof(float), "Vec3f must be packed RGB");
    const float *rgb = reinterpret_cast<const float *>(img.pixels.data());
    // The EXR first: a JSON without its image is never seen by load (it needs both).
    write_exr(dir + "/" + key + ".exr", img.width, img.height, {{"R", rgb, 3}, {"G", rgb + 1, 3}, {"B", rgb + 2, 3}});
    OrderedJson j = provenance;
    j["seconds"] = ref.seconds;
    j["cache_version"] = k_reference_cache_version;
    write_file_atomic(dir + "/" + key + ".json", j.dump(2) + "\n");
}

CachedReference reference_irradiance(const std::string &dir, const Scene &scene, const Camera &camera, const GBuffer &gb,
                                     const PathTracer &pt, const PathTracerConfig &cfg, int spp,
                                     const OrderedJson &provenance, bool *from_cache) {
    if (from_cache) *from_cache = false;
    const std::string key = dir.empty() ? "" : reference_cache_key(scene, camera, spp, cfg);
    if (!key.empty())
        if (auto cached = load_cached_reference(dir, key, camera.width, camera.height)) {
            if (from_cache) *from_cache = true;
            return std::move(*cached);
        }
    const IrradianceImages r = irradiance_images(pt, gb, spp, true);
    CachedReference ref{r.indirect, r.seconds};
    if (!key.empty()) store_cached_reference(dir, key, ref, provenance);
    return ref;
}

}  // namespace ltm
