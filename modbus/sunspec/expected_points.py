#!/usr/bin/env python3
"""Writes the point table the map is checked against (tests/data/sunspec_points.tsv).

Models 1, 601 and 305 come from the SunSpec Alliance's model definitions as the
`pysunspec2` package ships them (sunspec2/models/json/model_N.json); the vendor
model 64201 from its definition beside this script. Offsets count from the
model's ID register; a repeating group is laid out once (our one tracker).

  python3 modbus/sunspec/expected_points.py > modbus/tests/data/sunspec_points.tsv
  python3 modbus/sunspec/expected_points.py --check modbus/tests/data/sunspec_points.tsv
"""
import json
import os
import sys

import sunspec2
from importlib.metadata import version

HERE = os.path.dirname(os.path.abspath(__file__))
MODELS = os.path.join(os.path.dirname(sunspec2.__file__), "models", "json")


def points(group, offset, out, model, prefix=""):
    for p in group.get("points", []):
        symbols = ",".join("%s=%d" % (s["name"], s["value"]) for s in p.get("symbols", []))
        out.append((model, prefix + p["name"], offset, p["size"], p["type"], str(p.get("sf", "")),
                    p.get("units", ""), p.get("access", "R"), symbols))
        offset += p["size"]
    for g in group.get("groups", []):
        offset = points(g, offset, out, model, prefix + g["name"] + ".")
    return offset


def table():
    rows = []
    for model, path in [(1, MODELS), (601, MODELS), (305, MODELS), (64201, HERE)]:
        with open(os.path.join(path, "model_%d.json" % model)) as f:
            d = json.load(f)
        length = points(d["group"], 0, rows, model) - 2
        rows.append((model, "(L)", length, 0, "", "", "", "", ""))
    lines = ["# model\tpoint\toffset\tsize\ttype\tsf\tunits\taccess\tsymbols",
             "# from pysunspec2 %s's JSON models (SunSpec Alliance) and modbus/sunspec/model_64201.json"
             % version("pysunspec2")]
    lines += ["\t".join(str(c) for c in r) for r in rows]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    text = table()
    if len(sys.argv) == 3 and sys.argv[1] == "--check":
        with open(sys.argv[2]) as f:
            if f.read() != text:
                sys.exit("%s differs from the models: regenerate it" % sys.argv[2])
        print("%s matches the models" % sys.argv[2])
    else:
        sys.stdout.write(text)
