#!/usr/bin/env python3
"""set_config.py: copy a weights file with fields of its model config (the `config` metadata) changed.

Only for fields that change no tensor's shape — how many paths the traced inputs trace
(traced_inputs), the prior's settings under physics.* — the loader checks the config against the
tensors and refuses the rest. Made v0.15 from v0.14 (docs/results.md, session 40):

  scripts/analysis/set_config.py models/ltm-cpu.safetensors -o OUT.safetensors traced_inputs=32

Keys are dotted paths into the config (physics.prior_theta=0.5), values JSON. A key the config does
not already hold is refused: a typo must not pass as a new field.
"""
import argparse
import json
import os
import struct
import sys


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("weights")
    ap.add_argument("fields", nargs="+", metavar="KEY=JSON")
    ap.add_argument("-o", "--out", required=True, help="the copy's path (the input is left as it is)")
    a = ap.parse_args()
    if os.path.abspath(a.out) == os.path.abspath(a.weights):
        sys.exit("-o names the input: write the copy elsewhere")
    data = open(a.weights, "rb").read()
    n = struct.unpack("<Q", data[:8])[0]
    header = json.loads(data[8:8 + n])
    meta = header.get("__metadata__", {})
    if "config" not in meta:
        sys.exit(f"{a.weights}: no config metadata (not an ltm weights file)")
    cfg = json.loads(meta["config"])
    for field in a.fields:
        key, sep, text = field.partition("=")
        if not sep:
            sys.exit(f"{field}: expected KEY=JSON")
        try:
            value = json.loads(text)
        except json.JSONDecodeError as e:
            sys.exit(f"{field}: the value is not JSON ({e})")
        node, parts = cfg, key.split(".")
        for p in parts[:-1]:
            if not isinstance(node.get(p), dict):
                sys.exit(f"{a.weights}: the config has no section '{p}' (in {key})")
            node = node[p]
        if parts[-1] not in node:
            sys.exit(f"{a.weights}: the config has no field '{key}'")
        print(f"{key}: {json.dumps(node[parts[-1]])} -> {json.dumps(value)}")
        node[parts[-1]] = value
    meta["config"] = json.dumps(cfg, separators=(",", ":"))
    header["__metadata__"] = meta
    text = json.dumps(header, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 8)   # the tensors' data stays 8-byte aligned
    with open(a.out, "wb") as f:
        f.write(struct.pack("<Q", len(text)) + text + data[8 + n:])


if __name__ == "__main__":
    main()
