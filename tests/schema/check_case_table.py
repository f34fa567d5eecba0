#!/usr/bin/python3
"""The case table (protocol/sph_case_table.h, dumped by the case_fields tool) against the JSON
Schema (protocol/schema/case.schema.json) and PROTOCOL.md: every row of every available method is
in the schema with the same type, bounds, names, default and requiredness, the schema has no field
the table lacks, and PROTOCOL.md section 1 names every field by its dotted path.
Usage: check_case_table.py CASE_FIELDS_TOOL SOURCE_DIR"""
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from tally import expect, finish  # noqa: E402

tool, src = sys.argv[1], sys.argv[2]
rows = json.loads(subprocess.run([tool], check=True, capture_output=True, text=True).stdout)
schema = json.load(open(os.path.join(src, "protocol", "schema", "case.schema.json")))
protocol = open(os.path.join(src, "protocol", "PROTOCOL.md")).read()
defs = schema["$defs"]


def resolve(node):
    while isinstance(node, dict) and "$ref" in node:
        node = defs[node["$ref"].split("/")[-1]]
    return node


def node_at(method, path):
    """The schema node of a JSON pointer under $defs[method], with its parent object."""
    node, parent = resolve(defs.get(method)), None
    for key in path.strip("/").split("/"):
        node = resolve(node)
        if key == "*":  # an element of an array row
            if not isinstance(node, dict) or "items" not in node:
                return None, None
            node = node["items"]
            continue
        if not isinstance(node, dict) or key not in node.get("properties", {}):
            return None, None
        parent, node = node, node["properties"][key]
    return resolve(node) if node is not True else True, parent


def never_default(row, method):
    """Whether a row's default can never apply to a method: the row and every object above it
    are required for it (e.g. mps requires kernel, and a kernel its type)."""
    if method not in row["required"] or row["when"] is not None:
        return False
    parts = row["path"].strip("/").split("/")
    for k in range(1, len(parts)):
        up = next((r for r in rows if r["path"] == "/" + "/".join(parts[:k])), None)
        if up is None or method not in up["required"]:
            return False
    return True


KIND = {"number": "number", "integer": "integer", "object": "object", "vector": "array",
        "names": "array", "box": "object", "array": "array", "string": "string"}
methods = sorted({m for r in rows for m in r["methods"]})
expect(len(methods) > 0, "the table has rows for at least one method")
for r in rows:
    for m in r["methods"]:
        where = f"{m} {r['path']}"
        node, parent = node_at(m, r["path"])
        expect(node is not None, f"{where}: in the schema")
        if node is None:
            continue
        if node is True:
            expect(r["type"] == "text", f"{where}: schema `true` only for text rows")
            continue
        t = r["type"]
        if t in KIND:
            expect(node.get("type") == KIND[t] or (t == "integer" and "const" in node),
                   f"{where}: schema type {node.get('type')} for a {t} row")
        if t == "enum":
            expect(node.get("enum") == r["names"], f"{where}: enum {node.get('enum')} vs {r['names']}")
        if t == "names":
            expect(node.get("items", {}).get("enum") == r["names"],
                   f"{where}: names {node.get('items', {}).get('enum')} vs {r['names']}")
        if t in ("number", "integer") and "const" not in node:
            if "exclusive_min" in r:
                expect(node.get("exclusiveMinimum") == r["exclusive_min"], f"{where}: exclusiveMinimum")
            else:
                expect(node.get("minimum") == r["min"], f"{where}: minimum {node.get('minimum')} vs {r['min']}")
            if "exclusive_max" in r:
                expect(node.get("exclusiveMaximum") == r["exclusive_max"], f"{where}: exclusiveMaximum")
            else:
                expect(node.get("maximum") == r["max"], f"{where}: maximum {node.get('maximum')} vs {r['max']}")
        if t == "array":
            expect(node.get("minItems") == r["min"] and node.get("maxItems") == r["max"],
                   f"{where}: items {node.get('minItems')}..{node.get('maxItems')} vs {r['min']}..{r['max']}")
        if "default" in r and t != "object" and never_default(r, m):
            expect("default" not in node, f"{where}: no default in the schema (the field and its "
                   "objects are required for this method, so the table's default never applies)")
        elif "default" in r and t != "object":
            expect(node.get("default") == r["default"],
                   f"{where}: default {node.get('default')} vs {r['default']}")
        if parent is not None and r["when"] is None:
            req = r["path"].split("/")[-1] in parent.get("required", [])
            expect(req == (m in r["required"]), f"{where}: required {req} in the schema")
        # PROTOCOL.md names the field by its dotted path
        if t != "text":
            dotted = r["path"].strip("/").replace("/", ".")
            expect(f"`{dotted}`" in protocol, f"{where}: PROTOCOL.md names `{dotted}`")


def walk(method, node, path):
    """Every schema field of a method has a row."""
    node = resolve(node)
    if not isinstance(node, dict):
        return
    for key, sub in node.get("properties", {}).items():
        p = f"{path}/{key}"
        row = next((r for r in rows if r["path"] == p and method in r["methods"]), None)
        expect(row is not None, f"{method} {p}: the schema's field is a row of the table")
        if row and row["type"] == "object":
            walk(method, sub, p)
        if row and row["type"] == "array":
            walk(method, resolve(sub).get("items", {}), p + "/*")


for m in methods:
    walk(m, defs.get(m, {}), "")
finish("case table")
