#!/usr/bin/env python3
"""prior_fit.py: how well closed-form priors from the scene points alone predict E+ at the query points.

For each dataset record (safetensors; scene points [M,12] = p,n,albedo,emission; query points [N,9];
E_indirect [N,3]) compares, per scene, the MSE of a prior field against the flat oracle (the
record's own mean E+ colour at every query):
  global: S * sum_k rho^k with S = pi * mean emission, rho = mean albedo (the v0.4 model's scale)
  local(sigma): the same with S and rho Gaussian-weighted around each query point (sigma in metres)
Usage: python3 prior_fit.py DIR [max_records]
"""
import json, struct, sys, os
import numpy as np

def read_safetensors(path):
    with open(path, 'rb') as f:
        n = struct.unpack('<Q', f.read(8))[0]
        header = json.loads(f.read(n))
        data = f.read()
    out = {}
    for k, v in header.items():
        if k == '__metadata__':
            continue
        a, b = v['data_offsets']
        out[k] = np.frombuffer(data[a:b], dtype=np.float32).reshape(v['shape'])
    return out

def print_summary(rows, header, width=8):
    """One line per prior: MSE/flat (median, geomean, share < 1) | level (geomean, share in [0.8, 1.25])."""
    print(header)
    for k, v in rows.items():
        rr, lv = np.array([x[0] for x in v]), np.array([x[1] for x in v])
        print(f'{k:{width}s} {np.median(rr):7.3f} {np.exp(np.log(rr).mean()):7.3f} {np.mean(rr < 1):.2f} | '
              f'{np.exp(np.log(lv).mean()):.3f} {np.mean((lv > 0.8) & (lv < 1.25)):.2f}')


def pb(rho, D=5):
    r = np.clip(rho, 0, 1)
    return sum(r ** k for k in range(1, D + 1))

def local_prior(sp, q, sigma, chunk=2048):
    pos, alb, em = sp[:, 0:3], sp[:, 6:9], sp[:, 9:12]
    out = np.empty((q.shape[0], 3))
    for s in range(0, q.shape[0], chunk):
        d2 = ((q[s:s + chunk, None, 0:3] - pos[None]) ** 2).sum(-1)
        w = np.exp(-0.5 * d2 / sigma ** 2)
        w /= w.sum(1, keepdims=True) + 1e-30
        S = np.pi * w @ em
        rho = w @ alb
        out[s:s + chunk] = S * pb(rho)
    return out

def main():
    d = sys.argv[1]
    nmax = int(sys.argv[2]) if len(sys.argv) > 2 else 50
    files = sorted(f for f in os.listdir(d) if f.endswith('.safetensors'))[:nmax]
    sigmas = [0.5, 1.0, 2.0, 4.0]
    names = ['global'] + [f'local{s}' for s in sigmas] + [f'mix{s}' for s in sigmas]
    ratios = {k: [] for k in names}
    levels = {k: [] for k in names}
    for f in files:
        r = read_safetensors(os.path.join(d, f))
        sp, qp, E = r['scene_points'].astype(np.float64), r['query_points'].astype(np.float64), r['E_indirect'].astype(np.float64)
        q = qp[:4096]
        E = E[:4096]
        flat = ((E - E.mean(0)) ** 2).mean()
        S = np.pi * sp[:, 9:12].mean(0)
        g = S * pb(sp[:, 6:9].mean(0))
        fields = {'global': np.broadcast_to(g, E.shape)}
        for s in sigmas:
            loc = local_prior(sp, q, s)
            fields[f'local{s}'] = loc
            fields[f'mix{s}'] = 0.5 * (loc + g)
        for k, v in fields.items():
            ratios[k].append(((v - E) ** 2).mean() / flat)
            levels[k].append(v.mean() / E.mean())
    print(f'{len(files)} records; MSE/flat-oracle MSE (median, geomean, share<1) and level ratio (geomean, share in [0.8,1.25])')
    for k in names:
        rr, lv = np.array(ratios[k]), np.array(levels[k])
        print(f'{k:10s} mse/flat median {np.median(rr):7.3f} geomean {np.exp(np.log(rr).mean()):7.3f} beats {np.mean(rr < 1):.2f} | '
              f'level geomean {np.exp(np.log(lv).mean()):.3f} in-band {np.mean((lv > 0.8) & (lv < 1.25)):.2f}')

if __name__ == '__main__':
    main()
