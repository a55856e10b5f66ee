#!/usr/bin/env python3
"""visibility_prior.py: does a visibility test made from the scene points alone fix the transport
prior's main failure (light seen through walls)?  (issue #10, measured before building it in C++.)

The prior of transport/transport_prior.h (row-normalised disc transfer, D bounces from B0 = pi L),
once without visibility and once with V_ij from a voxel occupancy grid of the scene points: a voxel
of edge h = c * spacing (spacing = sqrt(A/M) from the 8th-neighbour distance) is solid when a
scene point lies in it; the segment between two points (each moved eps = h/2 along its normal)
is blocked when one of its samples (every h/2, the first and last h skipped) lands in a solid
voxel. No ray tracing of the meshes: a function of the point cloud only, as the model's input.
Nodes: N random scene points (exact per-pair visibility; the C++ version may cluster).
Reported per house: MSE / flat-oracle MSE on spread query points, level mean(prior)/mean(ref).
Usage: python3 visibility_prior.py DIR [max_records] [nodes] [c]
"""
import os, sys, time
import numpy as np
from prior_fit import read_safetensors, print_summary


def transfer(pr, nr, ps, ns, a):
    d = ps[None] - pr[:, None]
    r2 = (d ** 2).sum(-1)
    r = np.sqrt(r2) + 1e-12
    cos_r = np.clip((d * nr[:, None]).sum(-1) / r, 0, None)
    cos_s = np.clip(-(d * ns[None]).sum(-1) / r, 0, None)
    return a * cos_r * cos_s / (r2 + a / np.pi)


class Grid:
    def __init__(self, pts, h):
        self.lo = pts.min(0) - 2 * h
        self.h = h
        self.dim = np.ceil((pts.max(0) + 2 * h - self.lo) / h).astype(int) + 1
        self.occ = np.zeros(self.dim, dtype=bool)
        idx = ((pts - self.lo) / h).astype(int)
        self.occ[idx[:, 0], idx[:, 1], idx[:, 2]] = True

    def blocked(self, a, b):
        """a [n,3], b [n,3] -> bool [n]: does the segment a->b pass a solid voxel (ends skipped)?"""
        d = b - a
        L = np.linalg.norm(d, axis=-1)
        step = 0.5 * self.h
        K = int(np.ceil(L.max() / step)) + 1
        t = np.arange(K) * step                                          # [K]
        ok = (t[None] > SKIP * self.h) & (t[None] < L[:, None] - SKIP * self.h)        # [n, K]
        p = a[:, None] + d[:, None] / np.maximum(L[:, None, None], 1e-12) * t[None, :, None]
        idx = ((p - self.lo) / self.h).astype(int)
        idx = np.clip(idx, 0, self.dim - 1)
        hit = self.occ[idx[..., 0], idx[..., 1], idx[..., 2]] & ok
        return hit.any(-1)


def visibility(grid, pr, nr, ps, ns, eps, chunk=32):
    V = np.ones((pr.shape[0], ps.shape[0]), dtype=np.float32)
    a_all = pr + eps * nr
    b_all = ps + eps * ns
    for s in range(0, pr.shape[0], chunk):
        a = np.repeat(a_all[s:s + chunk], ps.shape[0], 0)
        b = np.tile(b_all, (min(chunk, pr.shape[0] - s), 1))
        V[s:s + chunk] = (~grid.blocked(a, b)).reshape(-1, ps.shape[0])
    return V


def solve(G, Le, rho, D):
    Gn = G / np.maximum(G.sum(1, keepdims=True), 1e-30)
    B, tot = np.pi * Le, np.zeros_like(Le)
    for _ in range(D):
        B = rho * (Gn @ B)
        tot += B
    return tot


def main():
    d = sys.argv[1]
    nmax = int(sys.argv[2]) if len(sys.argv) > 2 else 6
    N = int(sys.argv[3]) if len(sys.argv) > 3 else 1024
    c = float(sys.argv[4]) if len(sys.argv) > 4 else 1.0
    D = 8
    global SKIP
    SKIP = float(sys.argv[5]) if len(sys.argv) > 5 else 1.0
    files = sorted(f for f in os.listdir(d) if f.endswith('.safetensors'))[:nmax]
    res = {'none': [], 'voxel': []}
    for f in files:
        t0 = time.time()
        r = read_safetensors(os.path.join(d, f))
        sp = r['scene_points'].astype(np.float64)
        qp = r['query_points'][::8].astype(np.float64)
        E = r['E_indirect'][::8].astype(np.float64)
        S = r['emission_scale'].astype(np.float64)
        M = sp.shape[0]
        rng = np.random.default_rng(0)
        sub = sp[rng.choice(M, 512, replace=False), 0:3]
        r8 = np.sqrt(np.sort(((sub[:, None] - sp[None, :, 0:3]) ** 2).sum(-1), 1)[:, 8])
        a_pt = float(np.pi * np.mean(r8 ** 2) / 8)
        # Every emitting point is a node (lamps are a few points; a random subset would miss them).
        em = np.flatnonzero(sp[:, 9:12].sum(1) > 0)
        rest = np.setdiff1d(np.arange(M), em)
        nodes = sp[np.concatenate([em, rng.choice(rest, max(N - len(em), 0), replace=False)])]
        Le = nodes[:, 9:12].copy()
        # Emission rescaled so that pi * mean node radiance = S (as the C++ solver does).
        m = Le.mean(0)
        Le *= np.where(m > 0, S / np.pi / np.maximum(m, 1e-30), 0)
        a = a_pt * M / N
        pn, nn, rho = nodes[:, 0:3], nodes[:, 3:6], nodes[:, 6:9]
        G = transfer(pn, nn, pn, nn, a)
        np.fill_diagonal(G, 0)
        Gq = transfer(qp[:, 0:3], qp[:, 3:6], pn, nn, a)
        h = c * np.sqrt(a_pt)
        grid = Grid(sp[:, 0:3], h)
        flat = ((E - E.mean(0)) ** 2).mean()
        line = []
        for name in ('none', 'voxel'):
            if name == 'voxel':
                V = visibility(grid, pn, nn, pn, nn, 0.5 * h)
                Vq = visibility(grid, qp[:, 0:3], qp[:, 3:6], pn, nn, 0.5 * h)
                Gv, Gqv = G * V, Gq * Vq
                print(f"  V mean {V.mean():.3f} weighted {(G*V).sum()/G.sum():.3f}; Vq mean {Vq.mean():.3f} weighted {(Gq*Vq).sum()/Gq.sum():.3f}")
            else:
                Gv, Gqv = G, Gq
            tot = solve(Gv, Le, rho, D)
            Gqn = Gqv / np.maximum(Gqv.sum(1, keepdims=True), 1e-30)
            pred = Gqn @ tot
            res[name].append((((pred - E) ** 2).mean() / flat, pred.mean() / E.mean()))
            line.append(f'{name} {res[name][-1][0]:.3f}/{res[name][-1][1]:.2f}')
        print(f, f'h={h:.3f} solid voxels {grid.occ.sum()} ', ' '.join(line), f'{time.time() - t0:.0f}s', flush=True)
    print_summary(res, f'{len(files)} records, {N} nodes, c={c}; MSE/flat (median, geomean, share<1) | level (geomean, in band)', width=6)

if __name__ == '__main__':
    main()
