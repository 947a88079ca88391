#!/usr/bin/env python3
"""Convert TSID/eiquadprog QP snapshots (shared/data/qp/tsid-talos-double/qp_*.json) into the
compact test file crates/corps-qp/tests/data/tsid_talos_double.json.

Only the fields the corps-qp tests and benchmarks need are kept: the QP (H, g, A, b, C, l, u),
eiquadprog's solution x, its objective and active-set iteration count, and its per-tick solve
time (median and minimum, in microseconds, measured by the TSID harness when the data was
recorded). Numbers are written with Python's repr (shortest string that round-trips), so every
binary64 value is kept bit for bit. Usage:

    python3 tools/convert_tsid_qps.py ../../../shared/data/qp/tsid-talos-double \
        tests/data/tsid_talos_double.json
"""
import json
import os
import re
import sys

KEYS = ("H", "g", "A", "b", "C", "l", "u", "x")


def main(src_dir: str, out_path: str) -> None:
    files = [f for f in os.listdir(src_dir) if re.fullmatch(r"qp_\d+\.json", f)]
    files.sort(key=lambda f: int(f[3:-5]))
    qps = []
    for f in files:
        with open(os.path.join(src_dir, f)) as fh:
            d = json.load(fh)
        assert (d["nVar"], d["nEq"], d["nIn"]) == (62, 18, 66), f
        entry = {"tick": d["tick"], "nVar": d["nVar"], "nEq": d["nEq"], "nIn": d["nIn"]}
        for k in KEYS:
            entry[k] = d[k]
        entry["objective"] = d["objective"]
        entry["iterations"] = d["iterations"]
        entry["eiquadprog_us"] = d["eiquadprog_us"]
        entry["eiquadprog_us_min"] = d["eiquadprog_us_min"]
        entry["contact_points"] = d["contact_points"]
        qps.append(entry)
    out = {
        "source": "shared/data/qp/tsid-talos-double (TSID 1.10.0, eiquadprog 1.3.2, TALOS, scenario double)",
        "note": "H, g, A, b, C, l, u, x exactly as in the source files; times in microseconds "
        "measured by the TSID anchor harness when the data was recorded",
        "qps": qps,
    }
    with open(out_path, "w") as fh:
        json.dump(out, fh, separators=(",", ":"))
        fh.write("\n")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
