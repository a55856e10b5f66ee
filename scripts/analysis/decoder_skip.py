#!/usr/bin/env python3
"""decoder_skip.py: read or set the decoder's skip weights (ModelConfig::traced_queries) in a weights file.

The skip carries ln(R / Ê) — the regathered prior's ratio to the prior at each query — to the
output: w = 1 with the output layer at zero is the regathered prior exactly, w = 0 the prior. Setting
it on `--start-at-prior` weights gives the closed-form regather as a model, the row a trained
network must beat to show what it adds beyond the skip (docs/results.md, session 37).

  scripts/analysis/decoder_skip.py WEIGHTS.safetensors                  (print the skip)
  scripts/analysis/decoder_skip.py WEIGHTS.safetensors --set 1 -o OUT.safetensors
  scripts/analysis/decoder_skip.py WEIGHTS.safetensors --silence-body -o OUT.safetensors
      (zero 𝓦_out's last Linear, keep the learned skip: what the skip alone does, with the body silent;
       inference then folds the encoder and the attention away, nn/ltm_model.h fold_prior)
"""
import argparse
import json
import os
import struct
import sys


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("weights")
    ap.add_argument("--set", type=float, help="write a copy with every channel's skip weight at this value")
    ap.add_argument("--silence-body", action="store_true", help="write a copy with the output layer (decoder.out.3) zero")
    ap.add_argument("-o", "--out", help="the copy's path (with --set or --silence-body)")
    a = ap.parse_args()
    data = bytearray(open(a.weights, "rb").read())
    n = struct.unpack("<Q", data[:8])[0]
    header = json.loads(data[8:8 + n])
    if "decoder.skip" not in header:
        sys.exit(f"{a.weights}: no decoder.skip (the model has no traced_queries)")
    t = header["decoder.skip"]
    fmt = {"F32": "<3f", "F16": "<3e"}.get(t["dtype"])
    if fmt is None or t["shape"] != [3]:
        sys.exit(f"{a.weights}: decoder.skip is {t['dtype']} {t['shape']}, expected F32 or F16 [3]")
    at = 8 + n + t["data_offsets"][0]
    size = struct.calcsize(fmt)
    print(a.weights, "decoder.skip", " ".join(f"{v:.4f}" for v in struct.unpack(fmt, data[at:at + size])))
    if a.set is None and not a.silence_body:
        return
    if not a.out:
        sys.exit("--set and --silence-body need -o OUT (the input is left as it is)")
    if os.path.abspath(a.out) == os.path.abspath(a.weights):
        sys.exit("-o names the input: write the copy elsewhere (the input is left as it is)")
    if a.set is not None:
        data[at:at + size] = struct.pack(fmt, a.set, a.set, a.set)
        print(a.out, "decoder.skip", f"{a.set:.4f} ×3")
    if a.silence_body:
        for name in ("decoder.out.3.weight", "decoder.out.3.bias"):
            if name not in header:
                sys.exit(f"{a.weights}: no {name} (not the attention decoder's output layer)")
            lo, hi = header[name]["data_offsets"]
            data[8 + n + lo:8 + n + hi] = bytes(hi - lo)   # +0.0 in F32 and F16 alike
        print(a.out, "decoder.out.3 zero: the body is silent")
    with open(a.out, "wb") as f:
        f.write(data)


if __name__ == "__main__":
    main()
