#!/usr/bin/env bash
# A job's files for a client on another machine: `results` (names, kinds, sizes, CRC-32 against
# Python's zlib), `fetch --dest` (byte-identical copies), chunked `fetch` over the protocol,
# `export` (CSV rows against h5py), and the refusals (path traversal, missing file, offset past
# the end, length 0, unknown job, export of a kernel study); a long checksum does not hold up a
# ping.
# Usage: results_fetch.sh SPHD SPHCTL SOURCE_DIR
SPHD=$1; SPHCTL=$2; SRC=$3
. "$(dirname "$0")/lib.sh"
C=$SPHCTL
JOBDIR="$STATE/jobs/db"

start_sphd --threads 1
expect_rc "submit a small dam break and watch it" 0 "$C" submit "$SRC/cases/dambreak.json" --id db \
  --set dx=0.01 --set time.end=0.2 --watch
expect_rc "a kernel study" 0 "$C" submit "$SRC/cases/kernel_study.json" --id ks --watch

# results
expect_rc "results (table)" 0 "$C" results db
check "table lists the snapshots" grep -q "snap_000000.h5 .* snapshot" "$tmp/out"
expect_rc "results --checksums --json" 0 "$C" results db --checksums --json
cp "$tmp/out" "$tmp/results.json"
check "one JSON document" test "$(wc -l <"$tmp/results.json")" = 1
check "results: names, kinds, sizes and CRC-32 match the job dir" "$PY" - "$tmp/results.json" "$JOBDIR" <<'PYEOF'
import json, os, sys, zlib
d = json.load(open(sys.argv[1])); jd = sys.argv[2]
names = [f["name"] for f in d["files"]]
want = sorted(n for n in os.listdir(jd) if os.path.isfile(os.path.join(jd, n)) and ".tmp." not in n)
assert names == want, (names, want)
kinds = {"case.json": "case", "job.json": "record", "journal.jsonl": "journal",
         "result.json": "result", "diag.h5": "diagnostics", "particles.xmf": "xdmf",
         "checkpoint": "checkpoint", "checkpoint.prev": "checkpoint"}
assert {"case.json", "job.json", "result.json", "diag.h5", "particles.xmf"} <= set(names), names
assert any(n.startswith("snap_") for n in names), names
for f in d["files"]:
    p = os.path.join(jd, f["name"])
    assert f["kind"] == kinds.get(f["name"], "snapshot" if f["name"].startswith("snap_") else "?"), f
    assert f["size"] == os.stat(p).st_size, f
    assert f["crc32"] == "%08x" % (zlib.crc32(open(p, "rb").read()) & 0xffffffff), f
assert d["job"] == "db" and d["dir"]
PYEOF
touch "$JOBDIR/snap_000000.h5.tmp.999"
expect_rc "results --json" 0 "$C" results db --json
check "temporaries are not listed, nor crc32 without --checksums" jtrue "$tmp/out" \
  'all(".tmp." not in f["name"] and "crc32" not in f for f in d["files"])'
rm -f "$JOBDIR/snap_000000.h5.tmp.999"

# fetch
expect_rc "fetch --dest" 0 "$C" fetch db --dest "$tmp/dl"
check "summary line" grep -q "file(s)" "$tmp/out"
nfetched=0
for f in "$JOBDIR"/*; do
  n=$(basename "$f")
  case "$n" in checkpoint*) check "no checkpoints without --include-checkpoints" test ! -e "$tmp/dl/db/$n"; continue;; esac
  check "fetched $n is identical" cmp -s "$f" "$tmp/dl/db/$n"
  nfetched=$((nfetched+1))
done
check "every file fetched" test "$nfetched" -ge 6
check "no temporaries left" test -z "$(find "$tmp/dl" -name '.*part*')"
expect_rc "fetch --json --include-checkpoints" 0 "$C" fetch db --dest "$tmp/nested/dl2" --json --include-checkpoints
check "fetch --json: one document with every file" jtrue "$tmp/out" \
  'd["job"]=="db" and d["dest"].endswith("/db") and len(d["files"])==len(json.load(open("'"$tmp/results.json"'"))["files"]) and d["bytes"]==sum(f["size"] for f in d["files"])'
check "checkpoint fetched too" cmp -s "$JOBDIR/checkpoint" "$tmp/nested/dl2/db/checkpoint"

# chunks over the protocol: small lengths, offsets, eof, per-chunk CRC-32
check "fetch in 1000-byte chunks reassembles the snapshot" "$PY" - "$SPHD_ENDPOINT" "$JOBDIR" <<'PYEOF'
import base64, json, os, sys, zlib, zmq
s = zmq.Context().socket(zmq.DEALER); s.connect(sys.argv[1]); s.setsockopt(zmq.RCVTIMEO, 10000)
def call(op, **args):
    s.send_string(json.dumps({"v": 1, "id": 1, "op": op, "args": args})); return json.loads(s.recv())
want = open(os.path.join(sys.argv[2], "snap_000001.h5"), "rb").read()
got, off = b"", 0
while True:
    r = call("fetch", job="db", file="snap_000001.h5", offset=off, length=1000)["result"]
    data = base64.b64decode(r["data"])
    assert r["offset"] == off and r["length"] == len(data) and r["size"] == len(want), r
    assert r["crc32"] == "%08x" % (zlib.crc32(data) & 0xffffffff)
    got += data; off += len(data)
    if r["eof"]: break
assert got == want and off == len(want)
r = call("fetch", job="db", file="snap_000001.h5", offset=len(want))["result"]
assert r["eof"] and r["length"] == 0 and r["data"] == "", r
r = call("fetch", job="db", file="job.json", length=4 << 20)["result"]
assert r["eof"] and base64.b64decode(r["data"]) == open(os.path.join(sys.argv[2], "job.json"), "rb").read()
e = call("fetch", job="db", file="job.json", length=(4 << 20) + 1)["error"]
assert e["code"] == "bad_request" and e["path"] == "/args/length", e
e = call("fetch", job="db", file="job.json", offset=-1)["error"]
assert e["code"] == "bad_request" and e["path"] == "/args/offset", e
e = call("fetch", job="db", file="/etc/passwd")["error"]
assert e["code"] == "bad_request" and e["path"] == "/args/file", e
e = call("fetch", job="db", file=".hidden")["error"]
assert e["code"] == "bad_request" and e["path"] == "/args/file", e
e = call("export", job="db", format="xlsx")["error"]
assert e["code"] == "bad_request" and e["path"] == "/args/format", e
assert "results" in call("hello")["result"]["ops"]
PYEOF

# refusals through sphctl (--json: the error reply on stdout)
req() { "$PY" - "$SPHD_ENDPOINT" "$@" <<'PYEOF'
import json, sys, zmq
s = zmq.Context().socket(zmq.DEALER); s.connect(sys.argv[1]); s.setsockopt(zmq.RCVTIMEO, 10000)
s.send_string(json.dumps({"v": 1, "id": 1, "op": sys.argv[2], "args": json.loads(sys.argv[3])}))
r = json.loads(s.recv()); print(json.dumps(r))
sys.exit(0 if r["ok"] else 1)
PYEOF
}
expect_rc "fetch ../case.json refused" 1 req fetch '{"job": "db", "file": "../case.json"}'
check "bad_request at /args/file" jtrue "$tmp/out" 'd["error"]["code"]=="bad_request" and d["error"]["path"]=="/args/file"'
expect_rc "fetch of a missing file" 1 req fetch '{"job": "db", "file": "snap_999999.h5"}'
check "not_found at /args/file" jtrue "$tmp/out" 'd["error"]["code"]=="not_found" and d["error"]["path"]=="/args/file"'
expect_rc "offset past the end" 1 req fetch '{"job": "db", "file": "job.json", "offset": 100000000}'
check "bad_request at /args/offset" jtrue "$tmp/out" 'd["error"]["code"]=="bad_request" and d["error"]["path"]=="/args/offset"'
expect_rc "length 0" 1 req fetch '{"job": "db", "file": "job.json", "length": 0}'
check "bad_request at /args/length" jtrue "$tmp/out" 'd["error"]["code"]=="bad_request" and d["error"]["path"]=="/args/length"'
expect_rc "fetch of an unknown job (sphctl)" 1 "$C" --json fetch nosuchjob --dest "$tmp/dl3"
check "not_found at /args/job" jtrue "$tmp/out" 'd["error"]["code"]=="not_found" and d["error"]["path"]=="/args/job"'
check "nothing created for an unknown job" test ! -e "$tmp/dl3"
expect_rc "results of an unknown job" 1 "$C" results nosuchjob
expect_rc "fetch usage error" 64 "$C" fetch
expect_rc "export usage error" 64 "$C" export db extra

# export
expect_rc "export to stdout" 0 "$C" export db
cp "$tmp/out" "$tmp/diag_stdout.csv"
check "CSV header" grep -q "^step,t,dt,ekin," "$tmp/diag_stdout.csv"
expect_rc "export --out" 0 "$C" export db --out "$tmp/diag.csv"
check "--out holds the same CSV" cmp -s "$tmp/diag.csv" "$tmp/diag_stdout.csv"
check "CSV rows = rows of diag.h5 (h5py)" "$PY" - "$tmp/diag.csv" "$JOBDIR/diag.h5" <<'PYEOF'
import csv, sys, h5py
rows = list(csv.reader(open(sys.argv[1])))
with h5py.File(sys.argv[2], "r", swmr=True) as f:
    n = len(f["step"])
    steps = list(f["step"][:])
assert rows[0][:4] == ["step", "t", "dt", "ekin"], rows[0]
assert len(rows) - 1 == n and n > 1, (len(rows), n)
assert [int(r[0]) for r in rows[1:]] == steps
PYEOF
expect_rc "export --json" 0 "$C" export db --json
check "export --json: rows and csv" jtrue "$tmp/out" \
  'd["format"]=="csv" and d["rows"]==len(d["csv"].splitlines())-1 and d["csv"]==open("'"$tmp/diag.csv"'").read()'
expect_rc "export of a kernel study: refused" 1 "$C" --json export ks
check "bad_state, saying why" jtrue "$tmp/out" 'd["error"]["code"]=="bad_state" and "kernel study" in d["error"]["message"]'
expect_rc "export --out into a missing directory: 73" 73 "$C" export db --out "$tmp/no/such/dir.csv"

# a damaged transfer, from a fake sphd: a wrong whole-file CRC-32 (a.bin), a damaged chunk (b.bin)
"$PY" - "ipc://$tmp/fake" <<'PYEOF' &
import base64, json, sys, zlib, zmq
s = zmq.Context().socket(zmq.ROUTER); s.bind(sys.argv[1])
files = {"a.bin": (b"hello" * 100, "00000000", None), "b.bin": (b"world" * 100, None, "deadbeef")}
while s.poll(60000):  # every request it gets (a retry too), until killed or idle a minute
    env, body = s.recv_multipart()
    req = json.loads(body); a = req.get("args", {})
    if req["op"] == "results":
        want = [n for n in files if n == a["job"]]
        res = {"job": a["job"], "dir": "/x", "files": [
            {"name": n, "size": len(files[n][0]), "kind": "other",
             "crc32": files[n][1] or "%08x" % (zlib.crc32(files[n][0]) & 0xffffffff)} for n in want]}
    else:
        data = files[a["file"]][0]
        res = {"file": a["file"], "offset": 0, "length": len(data), "size": len(data), "eof": True,
               "crc32": files[a["file"]][2] or "%08x" % (zlib.crc32(data) & 0xffffffff),
               "data": base64.b64encode(data).decode()}
    s.send_multipart([env, json.dumps({"v": 1, "id": req["id"], "ok": True, "result": res}).encode()])
PYEOF
fake_pid=$!
for _ in $(seq 1 200); do [ -S "$tmp/fake" ] && break; sleep 0.05; done  # bound (slow on a busy machine)
sleep 0.3
# (replies within 30 s: a sanitizer build under load is slow to start)
expect_rc "whole-file CRC-32 mismatch: exit 1" 1 "$C" --timeout 30 --endpoint "ipc://$tmp/fake" fetch a.bin --dest "$tmp/bad"
check "says so" grep -q "CRC-32 mismatch" "$tmp/err"
check "no file left behind" test -z "$(ls -A "$tmp/bad/a.bin")"
expect_rc "damaged chunk: exit 1" 1 "$C" --timeout 30 --endpoint "ipc://$tmp/fake" --json fetch b.bin --dest "$tmp/bad"
check "one JSON document naming the error" jtrue "$tmp/out" 'd["error"]["code"]=="checksum"'
check "no file left behind" test -z "$(ls -A "$tmp/bad/b.bin")"
kill "$fake_pid" 2>/dev/null; wait "$fake_pid" 2>/dev/null

for cmd in results fetch export; do
  expect_rc "$cmd --help" 0 "$C" "$cmd" --help
done

# Reading files never holds up other requests: while sphd checksums a 1 GiB file (on its files
# thread), a ping sent after the `results` request is answered first.
truncate -s 1G "$JOBDIR/big.bin"
check "ping answered while a checksum runs" "$PY" - "$SPHD_ENDPOINT" <<'PYEOF'
import json, sys, time, zlib
import zmq
ctx = zmq.Context()
def dealer():
    s = ctx.socket(zmq.DEALER); s.setsockopt(zmq.LINGER, 0); s.connect(sys.argv[1]); return s
a, b = dealer(), dealer()
time.sleep(0.2)
t0 = time.time()
a.send(json.dumps({"v": 1, "id": "r", "op": "results", "args": {"job": "db", "checksums": True}}).encode())
time.sleep(0.02)
b.send(json.dumps({"v": 1, "id": "p", "op": "ping"}).encode())
poller = zmq.Poller(); poller.register(a, zmq.POLLIN); poller.register(b, zmq.POLLIN)
order = []
while len(order) < 2 and time.time() - t0 < 120:
    for s, _ in poller.poll(1000):
        r = json.loads(s.recv()); order.append((r["id"], time.time() - t0, r))
ids = [o[0] for o in order]
assert ids == ["p", "r"], [(i, round(t, 3)) for i, t, _ in order]
assert order[0][1] < 1.0, order[0][1]
big = [f for f in order[1][2]["result"]["files"] if f["name"] == "big.bin"][0]
crc, z = 0, bytes(1 << 24)
for _ in range(64):
    crc = zlib.crc32(z, crc)
assert big["crc32"] == "%08x" % crc, big
print(f"ping after {order[0][1]*1e3:.1f} ms, results (1 GiB checksummed) after {order[1][1]:.2f} s")
PYEOF
rm -f "$JOBDIR/big.bin"

stop_sphd
finish
