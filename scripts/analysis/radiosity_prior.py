#!/usr/bin/env python3
"""radiosity_prior.py: does a visibility-free radiosity solve on the scene points predict E+ better
than the house-wide power balance?  (issue #10: a closed-form prior from the scene points alone.)

Each scene point j is a Lambertian disc of area a = A/M (estimated from the 8th-neighbour
spacing, a = pi r_8^2 / 8; the results barely depend on it), radiance L_e,j (emission columns), albedo rho_j. Transfer without visibility (cosines clamp back faces):
    G_ij = a * max(0, n_i.w_ij) * max(0, -n_j.w_ij) / (r_ij^2 + a/pi)     (w_ij = (p_j - p_i)/r_ij)
(on axis this is the exact irradiance of a disc of area a: L*a/(r^2 + a/pi)).
    L_1 = rho/pi * G L_e,  L_{k+1} = rho/pi * G L_k,  E+(q) = sum_j G_qj * sum_{k=1..D} L_k,j.
Variants: 'rad' (as above), 'rad-pb' (rad's shape rescaled so its area mean equals the global power
balance), 'norm' (each receiver's row normalised to sum 1, exitance B = pi L: what
transport/transport_prior.h implements), 'norm-pb' (its shape at the power-balance level), 'mix',
'global' (the flat model's output scale). Reported per house as MSE / flat-oracle MSE on
spread query points (every 4th row: records store queries mesh by mesh) and level mean(prior)/mean(ref).
Usage: python3 radiosity_prior.py DIR [max_records] [bounces]
"""
import os, sys
import numpy as np
from prior_fit import read_safetensors, pb, print_summary


def transfer(pr, nr, ps, ns, a, chunk=1024):
    """G [len(pr), len(ps)]: irradiance at receivers (pr, nr) per unit radiance of each sender disc."""
    out = np.empty((pr.shape[0], ps.shape[0]), dtype=np.float32)
    for s in range(0, pr.shape[0], chunk):
        d = ps[None] - pr[s:s + chunk, None]                      # [c, M, 3] receiver -> sender
        r2 = (d ** 2).sum(-1)
        r = np.sqrt(r2) + 1e-12
        cos_r = np.clip((d * nr[s:s + chunk, None]).sum(-1) / r, 0, None)
        cos_s = np.clip(-(d * ns[None]).sum(-1) / r, 0, None)
        out[s:s + chunk] = (a * cos_r * cos_s / (r2 + a / np.pi)).astype(np.float32)
    return out


def main():
    d = sys.argv[1]
    nmax = int(sys.argv[2]) if len(sys.argv) > 2 else 32
    D = int(sys.argv[3]) if len(sys.argv) > 3 else 5
    files = sorted(f for f in os.listdir(d) if f.endswith('.safetensors'))[:nmax]
    rows = {k: [] for k in ('global', 'rad', 'rad-pb', 'mix', 'norm', 'norm-pb')}
    for f in files:
        r = read_safetensors(os.path.join(d, f))
        sp = r['scene_points'].astype(np.float64)
        qp = r['query_points'][::4].astype(np.float64)
        E = r['E_indirect'][::4].astype(np.float64)
        S = r['emission_scale'].astype(np.float64) if 'emission_scale' in r else np.pi * sp[:, 9:12].mean(0)
        M = sp.shape[0]
        Le, rho = sp[:, 9:12], sp[:, 6:9]
        # Area per point from the point spacing: pi r_8^2 holds ~8 points of a uniform 2-D sample.
        sub = sp[np.random.default_rng(0).choice(M, 512, replace=False), 0:3]
        d2 = ((sub[:, None] - sp[None, :, 0:3]) ** 2).sum(-1)
        r8 = np.sqrt(np.sort(d2, 1)[:, 8])
        a = float(np.pi * np.mean(r8 ** 2) / 8)
        G = transfer(sp[:, 0:3], sp[:, 3:6], sp[:, 0:3], sp[:, 3:6], a)
        np.fill_diagonal(G, 0)
        L, tot = Le, np.zeros_like(Le)
        for _ in range(D):
            L = rho / np.pi * (G @ L)
            tot += L
        Gq = transfer(qp[:, 0:3], qp[:, 3:6], sp[:, 0:3], sp[:, 3:6], a)
        rad = Gq @ tot
        g = S * pb(rho.mean(0), D)
        # rescale rad's shape to the power balance level: area mean of rad at the scene points.
        rad_sp = G @ tot
        radpb = rad * (g / np.maximum(rad_sp.mean(0), 1e-30))
        # Row-normalised transport: visibility-free form factors over-count (they see through
        # walls); in a closed scene the true ones sum to 1 per receiver, so each row is scaled to 1.
        Gn = G / np.maximum(G.sum(1, keepdims=True), 1e-30)
        L, totn = Le * np.pi, np.zeros_like(Le)      # exitance pi*L; B_{k+1} = rho * Gn B_k
        for _ in range(D):
            L = rho * (Gn @ L)
            totn += L
        Gqn = Gq / np.maximum(Gq.sum(1, keepdims=True), 1e-30)
        nrm = Gqn @ totn
        nrm_pb = nrm * (g / np.maximum((Gn @ totn).mean(0), 1e-30))
        flat = ((E - E.mean(0)) ** 2).mean()
        fields = {'global': np.broadcast_to(g, E.shape), 'rad': rad, 'rad-pb': radpb, 'mix': 0.5 * (radpb + g), 'norm': nrm, 'norm-pb': nrm_pb}
        line = []
        for k, v in fields.items():
            rows[k].append((((v - E) ** 2).mean() / flat, v.mean() / E.mean()))
            line.append(f'{k} {rows[k][-1][0]:.2f}/{rows[k][-1][1]:.2f}')
        print(f, 'a=%.4f' % a, ' '.join(line), flush=True)
    print_summary(rows, f'{len(files)} records; MSE/flat (median, geomean, share<1) | level (geomean, share in [0.8,1.25])', width=8)

if __name__ == '__main__':
    main()
