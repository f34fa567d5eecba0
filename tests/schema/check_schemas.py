#!/usr/bin/python3
"""The JSON Schemas in protocol/schema/ against the real thing: every case in cases/ and every
request the tests send must validate; the invalid case files the schema can judge and a table of
bad requests must not. Usage: check_schemas.py SOURCE_DIR"""
import glob
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from tally import expect, finish  # noqa: E402

import jsonschema
from jsonschema import Draft202012Validator

src = sys.argv[1]
sdir = os.path.join(src, "protocol", "schema")
schemas = {n: json.load(open(os.path.join(sdir, n))) for n in ("case.schema.json",
                                                                "request.schema.json")}
for s in schemas.values():
    Draft202012Validator.check_schema(s)
store = {s["$id"]: s for s in schemas.values()}
resolver = jsonschema.RefResolver.from_schema(schemas["request.schema.json"], store=store)
case_v = Draft202012Validator(schemas["case.schema.json"])
req_v = Draft202012Validator(schemas["request.schema.json"], resolver=resolver)


for f in sorted(glob.glob(os.path.join(src, "cases", "*.json")) +
                glob.glob(os.path.join(src, "tests", "cases", "*.json"))):
    c = json.load(open(f))
    errs = list(case_v.iter_errors(c))
    expect(not errs, f"{f} validates: {[e.message for e in errs][:3]}")
ks = json.load(open(os.path.join(src, "cases", "kernel_study.json")))
# every invalid case file is refused, except those whose fault needs arithmetic or is below JSON
# (the daemon and `sphd --run` check those)
beyond_schema = {"at_outside", "domain_reversed", "no_interior", "duplicate_key", "not_json",
                 "wcsph_fluid_outside", "wcsph_no_particles", "wcsph_mps_kernel",
                 "wcsph_body_outside", "wcsph_body_overlap", "wcsph_body_in_wall",
                 "wcsph_body_too_small", "wcsph_body_same_name", "wcsph_body_ghost_walls",
                 "wcsph_ghost_tilted_gravity", "wcsph_wave_half_tank", "wcsph_wave_wavelength",
                 "mps_layers", "mps_solitary_too_high", "mps_solitary_below_dx",
                 "mps_solitary_crest_outside", "mps_solitary_tank_low", "mps_solitary_half_tank",
                 "wcsph_gauge_outside", "mps_solitary_order3_too_high", "mps_koshizuka_long", "wcsph_dim3_vec2", "wcsph_gauge_y_2d",
                 "wcsph3d_box_flat", "wcsph3d_gauge_no_y", "wcsph3d_gauge_outside", "wcsph3d_obstacle_outside",
                 "wcsph3d_pressure_name_taken", "wcsph3d_pressure_outside",
                 "wcsph_device_gpu"}
for f in sorted(glob.glob(os.path.join(src, "tests", "cases", "invalid", "*.json"))):
    name = os.path.basename(f)[:-5]
    if name in beyond_schema:
        continue
    try:
        c = json.load(open(f))
    except ValueError:
        continue
    expect(not case_v.is_valid(c), f"{name}.json is refused by the schema")

good = [
    {"v": 1, "id": "a", "op": "hello"},
    {"op": "ping"},
    {"v": 1, "id": 3, "op": "submit", "args": {"case": ks, "job": "ks-1", "start": False,
                                                "set": ["particles=51"]}},
    {"op": "step", "args": {"job": "db", "n": 10}},
    {"op": "step", "args": {"job": "db", "until": 0.5}},
    {"op": "query", "args": {"job": "db", "fields": ["pos", "rho"], "max": 100}},
    {"op": "pause", "args": {"job": "db"}},
    {"op": "list", "args": {}},
    {"op": "results", "args": {"job": "db", "checksums": True}},
    {"op": "fetch", "args": {"job": "db", "file": "snap_000001.h5", "offset": 0, "length": 1048576}},
    {"op": "export", "args": {"job": "db", "format": "csv"}},
    {"op": "export", "args": {"sweep": "S", "format": "json"}},
    {"op": "list", "args": {"sweep": "S"}},
    {"op": "submit", "args": {"case": ks, "resources": {"executor": "slurm", "threads": 4,
                                                        "time_limit": 60, "partition": "short",
                                                        "sbatch": ["--mem=4G", "--exclusive"],
                                                        "retries": 2}}},
    {"op": "sweep", "args": {"case": ks, "sweep": "S", "set": ["particles=51"], "start": False,
                             "vary": [{"path": "kernel.h", "values": [0.1, 0.2]}]}},
]
bad = [
    {"v": 2, "op": "ping"},
    {"id": "x"},
    {"op": "frobnicate"},
    {"op": "ping", "args": {"x": 1}},
    {"op": "ping", "extra": 1},
    {"op": "submit", "args": {}},
    {"op": "submit", "args": {"case": ks, "job": "../x"}},
    {"op": "step", "args": {"job": "db"}},
    {"op": "export", "args": {"job": "db", "sweep": "S"}},
    {"op": "export", "args": {}},
    {"op": "sweep", "args": {"case": ks, "vary": []}},
    {"op": "sweep", "args": {"case": ks, "vary": [{"path": "dx"}]}},
    {"op": "list", "args": {"job": "x"}},
    {"op": "submit", "args": {"case": ks, "resources": {"gpus": 1}}},
    {"op": "submit", "args": {"case": ks, "resources": {"sbatch": ["--wrap=x"]}}},
    {"op": "submit", "args": {"case": ks, "resources": {"partition": "a b"}}},
    {"op": "step", "args": {"job": "db", "n": 1, "until": 1.0}},
    {"op": "step", "args": {"job": "db", "n": "3"}},
    {"op": "query", "args": {"job": "db", "max": 3}},
    {"op": "stop", "args": {}},
    {"op": "fetch", "args": {"job": "db", "file": "../case.json"}},
    {"op": "fetch", "args": {"job": "db", "file": ".hidden"}},
    {"op": "fetch", "args": {"job": "db", "file": "case.json", "length": 0}},
    {"op": "fetch", "args": {"job": "db", "file": "case.json", "offset": -1}},
    {"op": "fetch", "args": {"job": "db"}},
    {"op": "export", "args": {"job": "db", "format": "xlsx"}},
    {"op": "results", "args": {"job": "db", "checksums": 1}},
]
for r in good:
    errs = list(req_v.iter_errors(r))
    expect(not errs, f"request validates: {r['op']}: {[e.message for e in errs][:3]}")
for r in bad:
    expect(not req_v.is_valid(r), f"bad request refused by the schema: {json.dumps(r)[:80]}")
finish("check_schemas")
