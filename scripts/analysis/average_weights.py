#!/usr/bin/env python3
"""average_weights.py OUT.safetensors IN1.safetensors IN2 ...: the element-wise mean of weights files.

Checkpoint averaging (Polyak; SWA without the cyclic schedule): the mean of one run's late
checkpoints, whose decoder outputs differ from step to step by more than they differ on average
(docs/results.md, session 38). Every input must hold the same tensors with the same shapes; the
first file's header (its config and metadata) is kept, with "averaged_from" added. F32 and F16
inputs; the output is F32. Pure Python (the array module), no numpy.
"""
import array
import json
import struct
import sys


def read(path):
    data = open(path, "rb").read()
    n = struct.unpack("<Q", data[:8])[0]
    header = json.loads(data[8:8 + n])
    return header, memoryview(data)[8 + n:]


def values(header, body, name):
    t = header[name]
    lo, hi = t["data_offsets"]
    raw = body[lo:hi]
    if t["dtype"] == "F32":
        a = array.array("f")
        a.frombytes(raw)
        return a
    if t["dtype"] == "F16":
        return array.array("f", [v[0] for v in struct.iter_unpack("<e", raw)])
    sys.exit(f"{name}: dtype {t['dtype']} is not F32 or F16")


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    out, inputs = sys.argv[1], sys.argv[2:]
    files = [read(p) for p in inputs]
    h0 = files[0][0]
    names = sorted(k for k in h0 if k != "__metadata__")
    for p, (h, _) in zip(inputs, files):
        mine = sorted(k for k in h if k != "__metadata__")
        if mine != names or any(h[k]["shape"] != h0[k]["shape"] for k in names):
            sys.exit(f"{p}: not the tensors of {inputs[0]} (another architecture)")
    header, chunks, offset = {}, [], 0
    for name in names:
        acc = values(h0, files[0][1], name)
        for h, body in files[1:]:
            v = values(h, body, name)
            for i in range(len(acc)):
                acc[i] += v[i]
        k = 1.0 / len(files)
        acc = array.array("f", [x * k for x in acc])
        raw = acc.tobytes()
        header[name] = {"dtype": "F32", "shape": h0[name]["shape"], "data_offsets": [offset, offset + len(raw)]}
        chunks.append(raw)
        offset += len(raw)
    meta = dict(h0.get("__metadata__", {}))
    meta["averaged_from"] = json.dumps(inputs)
    header["__metadata__"] = meta
    hb = json.dumps(header).encode()
    hb += b" " * ((8 - len(hb) % 8) % 8)
    with open(out, "wb") as f:
        f.write(struct.pack("<Q", len(hb)))
        f.write(hb)
        for c in chunks:
            f.write(c)
    print(f"{out}: the mean of {len(inputs)} files, {len(names)} tensors")


if __name__ == "__main__":
    main()
