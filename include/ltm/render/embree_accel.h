// embree_accel.h: the ONLY interface to Embree. RAII over device and scene; Embree errors are
// recorded by the device callback and rethrown as ltm::Error after each call that can fail.
#pragma once

#include <cstdint>

#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ltm/core/sharded_counter.h"
#include "ltm/render/ray.h"
#include "ltm/scene/scene.h"

// Opaque Embree handles (from rtcore_device.h / rtcore_scene.h) without including Embree.
typedef struct RTCDeviceTy *RTCDevice;
typedef struct RTCSceneTy *RTCScene;

namespace ltm {

class EmbreeAccel {
public:
    /// Builds a BVH over all meshes (geometry id = mesh index). Keeps a reference to `scene`.
    explicit EmbreeAccel(const Scene &scene);
    /// A temporary scene would dangle (the accel keeps a reference): EmbreeAccel(load_scene(f))
    /// does not compile — keep the Scene in a variable.
    explicit EmbreeAccel(Scene &&) = delete;
    ~EmbreeAccel();
    EmbreeAccel(const EmbreeAccel &) = delete;
    EmbreeAccel &operator=(const EmbreeAccel &) = delete;

    /// Closest hit in (tmin, tmax), or nothing. Thread-safe.
    std::optional<Hit> intersect(const Ray &ray) const;
    /// True if anything is hit in (tmin, tmax). Thread-safe.
    bool occluded(const Ray &ray) const;
    /// Every hit in (tmin, tmax), sorted by t, then mesh, then triangle (coincident faces all
    /// appear, in an order that does not depend on the traversal). Thread-safe; counts one ray.
    std::vector<Hit> hits(const Ray &ray) const;
    const Scene &scene() const { return m_scene; }
    /// Rays traced so far by this accelerator (closest-hit + occlusion), for rays/s reports.
    uint64_t rays_traced() const { return m_rays.total(); }

private:
    void throw_if_error(const char *during) const;
    struct ReleaseDevice {
        void operator()(RTCDevice d) const;
    };
    struct ReleaseScene {
        void operator()(RTCScene s) const;
    };
    const Scene &m_scene;
    mutable std::string m_error;   // set by the device error callback; outlives the handles below
    // Owned handles: a constructor that throws half-way releases what it made (members are
    // destroyed in reverse order, the scene before its device).
    std::unique_ptr<RTCDeviceTy, ReleaseDevice> m_device;
    std::unique_ptr<RTCSceneTy, ReleaseScene> m_rtc_scene;
    mutable ShardedCounter m_rays;   // one shard a thread: a shared atomic cost 30 % of a frame
};

}  // namespace ltm
