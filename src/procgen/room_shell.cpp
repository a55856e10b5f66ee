// room_shell.cpp: the grid-based watertight room shell of a floor plan.
#include "ltm/procgen/room_shell.h"

#include <algorithm>
#include <array>
#include <map>

#include "ltm/core/error.h"

namespace ltm {

namespace {

enum class BoxKind { room, door, window, recess };

struct AirBox {
    int lo[3], hi[3];
    int room;
    BoxKind kind;
    int opening = -1;   // index into FloorPlan::openings
};

struct MeshWriter {
    TriangleMesh *mesh;
    // Keyed by position and face axis: the uv mapping depends on the face orientation.
    std::map<std::array<int, 4>, uint32_t> index;   // ordered: deterministic vertex order

    uint32_t vertex(const std::array<int, 3> &p, int normal_axis) {
        const std::array<int, 4> key{p[0], p[1], p[2], normal_axis};
        auto it = index.find(key);
        if (it != index.end()) return it->second;
        const uint32_t i = uint32_t(mesh->positions.size());
        const Vec3f pos{float(p[0]) / 1000.f, float(p[1]) / 1000.f, float(p[2]) / 1000.f};
        mesh->positions.push_back(pos);
        // World-space metric uvs: floors/ceilings (x, z), walls (along-wall, y).
        if (normal_axis == 1) mesh->uvs.push_back({pos.x, pos.z});
        else if (normal_axis == 0) mesh->uvs.push_back({pos.z, pos.y});
        else mesh->uvs.push_back({pos.x, pos.y});
        index.emplace(key, i);
        return i;
    }
};

std::vector<int> breakpoints(const std::vector<AirBox> &boxes, int axis) {
    std::vector<int> v;
    for (const AirBox &b : boxes) v.push_back(b.lo[axis]), v.push_back(b.hi[axis]);
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    return v;
}

// Labels every grid cell with the air box holding its centre (-1: solid). Doubled
// coordinates keep the cell centres integral.
std::vector<int> label_cells(const std::vector<AirBox> &boxes, const std::vector<int> (&coords)[3]) {
    const int n[3] = {int(coords[0].size()) - 1, int(coords[1].size()) - 1, int(coords[2].size()) - 1};
    const size_t n_cells = static_cast<size_t>(n[0]) * static_cast<size_t>(n[1]) * static_cast<size_t>(n[2]);
    std::vector<int> label(n_cells, -1);
    size_t c = 0;
    for (int i = 0; i < n[0]; ++i)
        for (int j = 0; j < n[1]; ++j)
            for (int k = 0; k < n[2]; ++k, ++c) {
                const int c2[3] = {coords[0][size_t(i)] + coords[0][size_t(i) + 1],
                                   coords[1][size_t(j)] + coords[1][size_t(j) + 1],
                                   coords[2][size_t(k)] + coords[2][size_t(k) + 1]};
                for (size_t b = 0; b < boxes.size(); ++b) {
                    bool inside = true;
                    for (int a = 0; a < 3; ++a) inside &= 2 * boxes[b].lo[a] < c2[a] && c2[a] < 2 * boxes[b].hi[a];
                    if (inside) {
                        label[c] = int(b);
                        break;
                    }
                }
            }
    return label;
}

}  // namespace

std::vector<RoomShell> build_room_shell(const FloorPlan &plan) {
    std::vector<AirBox> boxes;
    for (int r = 0; r < int(plan.rooms.size()); ++r)
        for (const RectMm &q : plan.rooms[size_t(r)].interiors)
            boxes.push_back({{q.x0, 0, q.z0}, {q.x1, plan.ceiling_mm, q.z1}, r, BoxKind::room});
    for (const PlanDoor &d : plan.doors)
        boxes.push_back({{d.opening.x0, 0, d.opening.z0}, {d.opening.x1, d.height_mm, d.opening.z1},
                         d.room_a, BoxKind::door});
    for (size_t o = 0; o < plan.openings.size(); ++o) {
        const PlanOpening &op = plan.openings[o];
        boxes.push_back({{op.lo[0], op.lo[1], op.lo[2]}, {op.hi[0], op.hi[1], op.hi[2]}, op.room,
                         op.kind == PlanOpening::Kind::window ? BoxKind::window : BoxKind::recess, int(o)});
    }
    const std::vector<int> coords[3] = {breakpoints(boxes, 0), breakpoints(boxes, 1), breakpoints(boxes, 2)};
    const int n[3] = {int(coords[0].size()) - 1, int(coords[1].size()) - 1, int(coords[2].size()) - 1};

    const std::vector<int> label = label_cells(boxes, coords);
    auto cell = [&](int i, int j, int k) { return (size_t(i) * size_t(n[1]) + size_t(j)) * size_t(n[2]) + size_t(k); };

    std::vector<RoomShell> shells(plan.rooms.size());
    std::vector<std::array<MeshWriter, 3>> writers(plan.rooms.size());
    for (size_t r = 0; r < shells.size(); ++r) {
        const std::string base = "room" + std::to_string(r);
        shells[r].floor.name = base + "_floor";
        shells[r].ceiling.name = base + "_ceiling";
        shells[r].walls.name = base + "_walls";
        writers[r] = {MeshWriter{&shells[r].floor, {}}, MeshWriter{&shells[r].ceiling, {}},
                      MeshWriter{&shells[r].walls, {}}};
    }
    std::map<int, MeshWriter> pane_writers;   // window opening -> its pane's writer
    // One quad per grid face between air and solid, facing the air. Quads share the grid's
    // vertices, so the surface is closed and has no T-junctions.
    for (int a = 0; a < 3; ++a) {
        const int u = (a + 1) % 3, v = (a + 2) % 3;   // (e_u × e_v) = e_a
        for (int i = 0; i <= n[a]; ++i)
            for (int j = 0; j < n[u]; ++j)
                for (int k = 0; k < n[v]; ++k) {
                    auto label_at = [&](int ia) {
                        if (ia < 0 || ia >= n[a]) return -1;
                        int idx[3];
                        idx[a] = ia, idx[u] = j, idx[v] = k;
                        return label[cell(idx[0], idx[1], idx[2])];
                    };
                    const int below = label_at(i - 1), above = label_at(i);
                    if ((below >= 0) == (above >= 0)) continue;
                    const bool positive = above >= 0;   // normal +e_a into the air cell above
                    const AirBox &box = boxes[size_t(positive ? above : below)];
                    int surface = 2;   // walls
                    const bool floor_box = box.kind == BoxKind::room || box.kind == BoxKind::door;
                    if (a == 1 && positive && floor_box) surface = 0;     // floor (door threshold too); sills are walls
                    else if (a == 1 && !positive && (box.kind == BoxKind::room || box.kind == BoxKind::recess))
                        surface = 1;                                      // ceiling; lintels and window heads are walls
                    MeshWriter *wp = &writers[size_t(box.room)][size_t(surface)];
                    if (box.kind == BoxKind::window) {
                        const PlanOpening &op = plan.openings[size_t(box.opening)];
                        const int end = op.outward_sign > 0 ? op.hi[a] : op.lo[a];
                        if (a == op.outward_axis && coords[a][size_t(i)] == end) {   // the pane
                            auto it = pane_writers.find(box.opening);
                            if (it == pane_writers.end()) {
                                TriangleMesh &pane = shells[size_t(box.room)].panes[box.opening];
                                pane.name = "room" + std::to_string(box.room) + "_window" + std::to_string(box.opening);
                                it = pane_writers.emplace(box.opening, MeshWriter{&pane, {}}).first;
                            }
                            wp = &it->second;
                        }
                    }
                    MeshWriter &w = *wp;
                    auto corner = [&](int du, int dv) {
                        std::array<int, 3> p;
                        p[size_t(a)] = coords[a][size_t(i)];
                        p[size_t(u)] = coords[u][size_t(j + du)];
                        p[size_t(v)] = coords[v][size_t(k + dv)];
                        return w.vertex(p, a);
                    };
                    uint32_t q[4] = {corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)};
                    if (!positive) std::swap(q[1], q[3]);
                    for (int t : {0, 1, 2, 0, 2, 3}) w.mesh->indices.push_back(q[t]);
                }
    }
    return shells;
}

}  // namespace ltm
