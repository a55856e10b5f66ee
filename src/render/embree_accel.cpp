// embree_accel.cpp: Embree 3 behind one file (STYLE.md rule 6).
#include "ltm/render/embree_accel.h"

#include <algorithm>
#include <cstring>
#include <tuple>

#include <unistd.h>

#include <embree3/rtcore.h>

#include "ltm/core/error.h"

namespace ltm {

namespace {
void on_embree_error(void *user, RTCError code, const char *str) {
    auto *msg = static_cast<std::string *>(user);
    if (msg->empty()) *msg = "Embree error " + std::to_string(int(code)) + ": " + (str ? str : "");
}
}  // namespace

namespace {
// Refuse scenes whose BVH cannot fit: Embree's high-quality triangle BVH plus our copies of the
// buffers take roughly 200 bytes per triangle (measured order of magnitude, kept conservative).
void check_memory(const Scene &scene) {
    const double need = 200.0 * double(scene.n_triangles());
    const double avail = double(sysconf(_SC_AVPHYS_PAGES)) * double(sysconf(_SC_PAGESIZE));
    if (avail > 0 && need > 0.9 * avail)
        LTM_THROW("scene '", scene.name, "' has ", scene.n_triangles(), " triangles: the ray-tracing BVH needs about ",
                  need / double(1 << 30), " GiB but only ", avail / double(1 << 30), " GiB of memory are available");
}
}  // namespace

EmbreeAccel::EmbreeAccel(const Scene &scene) : m_scene(scene) {
    check_memory(scene);
    m_device.reset(rtcNewDevice(nullptr));
    if (!m_device) LTM_THROW("EmbreeAccel: cannot create Embree device (error ", int(rtcGetDeviceError(nullptr)), ")");
    rtcSetDeviceErrorFunction(m_device.get(), on_embree_error, &m_error);
    m_rtc_scene.reset(rtcNewScene(m_device.get()));
    throw_if_error("creating the scene");
    if (!m_rtc_scene) LTM_THROW("EmbreeAccel: cannot create an Embree scene");
    rtcSetSceneBuildQuality(m_rtc_scene.get(), RTC_BUILD_QUALITY_HIGH);
    // hits() collects candidates through the intersection context's filter (null elsewhere).
    rtcSetSceneFlags(m_rtc_scene.get(), RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
    throw_if_error("creating the scene");
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const TriangleMesh &mesh = scene.meshes[m];
        // Embree reads indices unchecked: an index past the vertices would read out of bounds.
        for (const uint32_t i : mesh.indices)
            if (i >= mesh.positions.size())
                LTM_THROW("EmbreeAccel: mesh '", mesh.name, "' has vertex index ", i, " but ", mesh.positions.size(),
                          " vertices");
        RTCGeometry geom = rtcNewGeometry(m_device.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
        // New (Embree-owned, padded) buffers: Embree may read 16 bytes past the last vertex.
        auto *v = static_cast<float *>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), mesh.positions.size()));
        auto *idx = static_cast<uint32_t *>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                    3 * sizeof(uint32_t), mesh.n_triangles()));
        if (!v || !idx) {
            rtcReleaseGeometry(geom);
            throw_if_error("allocating geometry buffers");
            LTM_THROW("EmbreeAccel: out of memory for mesh '", mesh.name, "'");
        }
        std::memcpy(v, mesh.positions.data(), mesh.positions.size() * sizeof(Vec3f));
        std::memcpy(idx, mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t));
        rtcCommitGeometry(geom);
        rtcAttachGeometryByID(m_rtc_scene.get(), geom, unsigned(m));
        rtcReleaseGeometry(geom);
        throw_if_error("adding a mesh");
    }
    rtcCommitScene(m_rtc_scene.get());
    throw_if_error("building the BVH");
}

EmbreeAccel::~EmbreeAccel() = default;

void EmbreeAccel::ReleaseDevice::operator()(RTCDevice d) const { rtcReleaseDevice(d); }
void EmbreeAccel::ReleaseScene::operator()(RTCScene s) const { rtcReleaseScene(s); }

void EmbreeAccel::throw_if_error(const char *during) const {
    if (!m_error.empty()) {
        const std::string e = m_error;
        m_error.clear();
        LTM_THROW("EmbreeAccel: ", during, ": ", e);
    }
}

namespace {
RTCRay to_rtc(const Ray &r) {
    RTCRay q;
    q.org_x = r.o.x, q.org_y = r.o.y, q.org_z = r.o.z;
    q.dir_x = r.d.x, q.dir_y = r.d.y, q.dir_z = r.d.z;
    q.tnear = r.tmin, q.tfar = r.tmax;
    q.time = 0.f, q.mask = 0xffffffffu, q.id = 0, q.flags = 0;
    return q;
}
}  // namespace

std::optional<Hit> EmbreeAccel::intersect(const Ray &ray) const {
    m_rays.add();
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    rh.ray = to_rtc(ray);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(m_rtc_scene.get(), &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    Hit h;
    h.t = rh.ray.tfar;
    h.mesh = rh.hit.geomID;
    h.triangle = rh.hit.primID;
    h.b1 = rh.hit.u, h.b2 = rh.hit.v;
    h.n = normalize(m_scene.meshes[h.mesh].cross_normal(h.triangle));
    return h;
}

namespace {
// The context hits() passes to Embree: its filter sees every candidate hit (rtcIntersect1, N = 1;
// the candidate's distance is in the ray's tfar), records it and rejects it, so the traversal
// goes on to the next one.
struct CollectContext {
    RTCIntersectContext ctx;   // first member: Embree hands the filter this pointer
    std::vector<Hit> *hits;
};

void collect_hit(const RTCFilterFunctionNArguments *args) {
    const auto *c = reinterpret_cast<const CollectContext *>(args->context);
    const auto *ray = reinterpret_cast<const RTCRay *>(args->ray);
    const auto *hit = reinterpret_cast<const RTCHit *>(args->hit);
    Hit h;
    h.t = ray->tfar;
    h.mesh = hit->geomID, h.triangle = hit->primID;
    h.b1 = hit->u, h.b2 = hit->v;
    c->hits->push_back(h);
    args->valid[0] = 0;
}
}  // namespace

std::vector<Hit> EmbreeAccel::hits(const Ray &ray) const {
    m_rays.add();
    std::vector<Hit> out;
    CollectContext c;
    rtcInitIntersectContext(&c.ctx);
    c.ctx.filter = collect_hit;
    c.hits = &out;
    RTCRayHit rh;
    rh.ray = to_rtc(ray);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(m_rtc_scene.get(), &c.ctx, &rh);
    for (Hit &h : out) h.n = normalize(m_scene.meshes[h.mesh].cross_normal(h.triangle));
    std::sort(out.begin(), out.end(), [](const Hit &a, const Hit &b) {
        return std::tie(a.t, a.mesh, a.triangle) < std::tie(b.t, b.mesh, b.triangle);
    });
    // A triangle reported twice (Embree may test a primitive from two BVH leaves) counts once.
    out.erase(std::unique(out.begin(), out.end(), [](const Hit &a, const Hit &b) { return a.mesh == b.mesh && a.triangle == b.triangle; }),
              out.end());
    return out;
}

bool EmbreeAccel::occluded(const Ray &ray) const {
    m_rays.add();
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay r = to_rtc(ray);
    rtcOccluded1(m_rtc_scene.get(), &ctx, &r);
    return r.tfar < 0.f;   // Embree sets tfar = -inf on a hit
}

}  // namespace ltm
