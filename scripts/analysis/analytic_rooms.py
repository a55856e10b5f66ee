#!/usr/bin/env python3
"""analytic_rooms.py OUTDIR: the real-room failures in their simplest form (issue #29), as ltm scene
JSON files for `ltm eval` and bench/prior_ablation, each a 4 × 2.6 × 4 m room against the path tracer:

  closed-box      a closed room, a 0.6 m square ceiling light: the prior's home ground
  open-side       the same room without its front wall (the Cornell box's case)
  window          the closed room with a 1.6 × 1.2 m hole in one wall, onto nothing
  lamp-shade      the ceiling light replaced by a lamp: a 0.3 m light facing down inside an opaque
                  shade (a box open at the bottom) hanging 0.9 m below the ceiling
  recessed        the ceiling light set 0.3 m up into a recess of its own size in the ceiling

Walls ρ = 0.6, floor 0.4 (warm), ceiling 0.75; light L = 12 (W m⁻² sr⁻¹) per channel, the
lamp's 4× brighter for a similar power. The camera stands in a corner looking at the far corner.
"""
import json
import os
import sys

W, H, D = 4.0, 2.6, 4.0


def quad(a, b, c, d):
    """Two triangles a-b-c, a-c-d (normal (b - a) × (d - a))."""
    return [a, b, c, d], [0, 1, 2, 0, 2, 3]


def mesh(name, material, quads):
    pos, idx = [], []
    for q in quads:
        p, i = quad(*q)
        base = len(pos)
        pos += p
        idx += [base + k for k in i]
    return {"name": name, "material": material, "positions": [x for v in pos for x in v], "indices": idx}


def box_faces(lo, hi, outward=True, skip=()):
    """The faces of an axis-aligned box, normals outward (or inward), minus the named ones."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    faces = {
        "-y": [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)],
        "+y": [(x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0)],
        "-x": [(x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)],
        "+x": [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)],
        "-z": [(x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0)],
        "+z": [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)],
    }
    out = []
    for k, q in faces.items():
        if k in skip:
            continue
        out.append(q if outward else [q[0], q[3], q[2], q[1]])
    return out


def orient(q, want):
    """q with its winding flipped where its normal does not point along `want`."""
    a, b, _, d = q
    u = [b[i] - a[i] for i in range(3)]
    v = [d[i] - a[i] for i in range(3)]
    n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    return q if sum(n[i] * want[i] for i in range(3)) > 0 else [q[0], q[3], q[2], q[1]]


def wall_with_hole(z, x0, x1, y0, y1):
    """The wall at z facing +z (into the room), around a hole [x0, x1] × [y0, y1]."""
    quads = [[(0, 0, z), (0, H, z), (x0, H, z), (x0, 0, z)],
             [(x1, 0, z), (x1, H, z), (W, H, z), (W, 0, z)],
             [(x0, 0, z), (x0, y0, z), (x1, y0, z), (x1, 0, z)],
             [(x0, y1, z), (x0, H, z), (x1, H, z), (x1, y1, z)]]
    return [orient(q, (0, 0, 1)) for q in quads]


def room(kind):
    mats = [{"name": "wall", "type": "diffuse", "albedo": [0.6, 0.6, 0.6]},
            {"name": "floor", "type": "diffuse", "albedo": [0.45, 0.4, 0.32]},
            {"name": "ceiling", "type": "diffuse", "albedo": [0.75, 0.75, 0.75]},
            {"name": "shade", "type": "diffuse", "albedo": [0.5, 0.5, 0.5]},
            {"name": "light", "type": "emissive", "albedo": [0.8, 0.8, 0.8],
             "radiance": [48.0] * 3 if kind == "lamp-shade" else [12.0] * 3}]
    inner = box_faces((0, 0, 0), (W, H, D), outward=False)
    floor, ceiling = inner[0], inner[1]
    walls = inner[2:]   # -x, +x, -z, +z
    meshes = [mesh("floor", "floor", [floor])]
    cx, cz, s = W / 2, D / 2, 0.3
    if kind == "recessed":
        # The ceiling with a hole where the recess is, the recess's four sides and its lit top.
        h = H
        ring = [[(0, h, 0), (0, h, D), (cx - s, h, D), (cx - s, h, 0)],
                [(cx + s, h, 0), (cx + s, h, D), (W, h, D), (W, h, 0)],
                [(cx - s, h, 0), (cx - s, h, cz - s), (cx + s, h, cz - s), (cx + s, h, 0)],
                [(cx - s, h, cz + s), (cx - s, h, D), (cx + s, h, D), (cx + s, h, cz + s)]]
        ring = [orient(q, (0, -1, 0)) for q in ring]
        meshes.append(mesh("ceiling", "ceiling", ring))
        sides = box_faces((cx - s, H, cz - s), (cx + s, H + 0.3, cz + s), outward=False, skip=("-y", "+y"))
        meshes.append(mesh("recess", "ceiling", sides))
        meshes.append(mesh("light", "light", [[(cx - s, H + 0.3, cz - s), (cx + s, H + 0.3, cz - s),
                                              (cx + s, H + 0.3, cz + s), (cx - s, H + 0.3, cz + s)]]))
    else:
        meshes.append(mesh("ceiling", "ceiling", [ceiling]))
    if kind == "lamp-shade":
        y = H - 0.9
        # A 0.15 m light facing down, inside a 0.5 m shade (open at the bottom) 0.02 m below its top.
        t = 0.15
        meshes.append(mesh("light", "light", [[(cx - t, y + 0.28, cz - t), (cx + t, y + 0.28, cz - t),
                                              (cx + t, y + 0.28, cz + t), (cx - t, y + 0.28, cz + t)]]))
        shade_lo, shade_hi = (cx - 0.25, y, cz - 0.25), (cx + 0.25, y + 0.3, cz + 0.25)
        meshes.append(mesh("shade", "shade", box_faces(shade_lo, shade_hi, outward=True, skip=("-y",)) +
                           box_faces(shade_lo, shade_hi, outward=False, skip=("-y",))))
    elif kind != "recessed":
        meshes.append(mesh("light", "light", [[(cx - s, H - 0.001, cz - s), (cx + s, H - 0.001, cz - s),
                                              (cx + s, H - 0.001, cz + s), (cx - s, H - 0.001, cz + s)]]))
    wall_quads = []
    for k, q in zip(("-x", "+x", "-z", "+z"), walls):
        if kind == "open-side" and k == "-z":
            continue
        if kind == "window" and k == "-z":
            wall_quads += wall_with_hole(0.0, 1.2, 2.8, 0.9, 2.1)
            continue
        wall_quads.append(q)
    meshes.append(mesh("walls", "wall", wall_quads))
    cam = {"name": "main", "eye": [W - 0.3, 1.6, D - 0.3], "target": [0.4, 0.8, 0.4], "up": [0, 1, 0],
           "fov_y": 70.0, "width": 128, "height": 128}
    return {"format": "ltm-scene", "version": 1, "name": kind, "materials": mats, "meshes": meshes,
            "cameras": [cam], "metadata": {"made_by": "scripts/analysis/analytic_rooms.py"}}


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "analytic-rooms"
    os.makedirs(out, exist_ok=True)
    for kind in ("closed-box", "open-side", "window", "lamp-shade", "recessed"):
        path = os.path.join(out, kind + ".json")
        with open(path, "w") as f:
            json.dump(room(kind), f)
        print(path)


if __name__ == "__main__":
    main()
