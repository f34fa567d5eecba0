#!/usr/bin/env bash
# A capture of the loopback traffic (tcpdump, Debian) while sphctl submits a case and watches it
# over CURVE shows none of the case's JSON in clear text; the same capture of a plain sphd does
# show it (so the capture would see a leak). Skipped (77) only when nothing can be captured here
# (no CAP_NET_RAW: not root, or a sandbox without packet sockets).
# Usage: curve_capture.sh SPHD SPHCTL SOURCE_DIR
set -u
SPHD=$1 SPHCTL=$2 SRC=$3
. "$(dirname "$0")/lib.sh"
TCPDUMP=$(command -v tcpdump || echo /usr/bin/tcpdump)
if [ ! -x "$TCPDUMP" ]; then echo "SKIP: tcpdump is not installed (scripts/setup.sh)"; exit 77; fi
free_port() { /usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'; }
MARK="capture-marker-$$-zq"
/usr/bin/python3 - "$SRC/cases/dambreak.json" "$tmp/case.json" "$MARK" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))
c["name"] = sys.argv[3]
c["dx"], c["time"]["end"] = 0.02, 0.05
json.dump(c, open(sys.argv[2], "w"))
PY
tcpdump_pid=""
stop_capture() {
  [ -n "$tcpdump_pid" ] || return 0
  sleep 0.2
  kill -INT "$tcpdump_pid" 2>/dev/null; wait "$tcpdump_pid" 2>/dev/null; tcpdump_pid=""
}
trap 'stop_capture; cleanup' EXIT
# capture PCAP PORT1 PORT2: starts tcpdump on lo; returns 1 when it cannot capture. tcpdump says
# "listening" a while before packets reach it (and buffers them, without --immediate-mode): knock on a closed probe port (a SYN and a RST)
# until the capture file holds a packet.
capture() {
  local probe; probe=$(free_port)
  "$TCPDUMP" -i lo --immediate-mode -U -n -Z "$(id -un)" -w "$1" "tcp port $2 or tcp port $3 or tcp port $probe" \
    2>"$1.err" &
  tcpdump_pid=$!
  for _ in $(seq 1 200); do
    kill -0 "$tcpdump_pid" 2>/dev/null || { tcpdump_pid=""; return 1; }
    if grep -q "listening on" "$1.err"; then
      (echo >"/dev/tcp/127.0.0.1/$probe") 2>/dev/null
      [ "$(stat -c %s "$1" 2>/dev/null || echo 0)" -gt 24 ] && return 0
    fi
    sleep 0.05
  done
  return 1
}
packets() { "$TCPDUMP" -r "$1" -n 2>/dev/null | wc -l; }

# 1. plain sphd on loopback: the case is in the capture (the capture works)
P1=$(free_port) P2=$(free_port)
export SPHD_ENDPOINT="tcp://127.0.0.1:$P1"
STREAM="tcp://127.0.0.1:$P2"
if ! capture "$tmp/plain.pcap" "$P1" "$P2"; then
  echo "SKIP: cannot capture on lo: $(cat "$tmp/plain.pcap.err")"; exit 77
fi
start_sphd --threads 1
expect_rc "plain: submit and watch" 0 "$SPHCTL" submit "$tmp/case.json" --id plain --watch --json
stop_sphd
stop_capture
check "plain: packets captured" test "$(packets "$tmp/plain.pcap")" -gt 10
check "plain: the case's name is in clear text" grep -aq "$MARK" "$tmp/plain.pcap"
check "plain: the case's JSON is in clear text" grep -aq '"method"' "$tmp/plain.pcap"

# 2. CURVE: nothing of the case, nor of the replies and events, in clear text
srv="$tmp/srv" alice="$tmp/alice"
mkdir -p "$srv/clients"
"$SPHCTL" keygen --out "$srv/server" >/dev/null 2>&1
XDG_CONFIG_HOME="$alice" "$SPHCTL" keygen >/dev/null 2>&1
cp "$alice/sphctl/client.pub" "$srv/clients/"
P1=$(free_port) P2=$(free_port)
export SPHD_ENDPOINT="tcp://127.0.0.1:$P1"
STREAM="tcp://127.0.0.1:$P2"
capture "$tmp/curve.pcap" "$P1" "$P2" || { echo "FAIL: the second capture did not start"; exit 1; }
"$SPHD" --curve "$srv" --listen "$SPHD_ENDPOINT" --publish "$STREAM" --state-dir "$STATE" \
  --threads 1 2>>"$tmp/sphd.log" &
sphd_pid=$!
A() { XDG_CONFIG_HOME="$alice" "$SPHCTL" --server-key "$srv/server.pub" "$@"; }
for _ in $(seq 1 100); do A --timeout 1 ping >/dev/null 2>&1 && break; sleep 0.05; done
expect_rc "CURVE: submit and watch" 0 A submit "$tmp/case.json" --id secret --watch --json
check "CURVE: the job ran to the end" grep -q '"state": *"done"' "$tmp/out"
A shutdown >/dev/null
wait "$sphd_pid"; sphd_pid=""
stop_capture
n=$(packets "$tmp/curve.pcap")
check "CURVE: packets captured ($n)" test "$n" -gt 10
check "CURVE: the case's name is not in clear text" bash -c "! grep -aq '$MARK' '$tmp/curve.pcap'"
for s in '"method"' '"dambreak"' 'wendland' '"diag"' '"state"' '"ok"' 'hello'; do
  check "CURVE: no $s in clear text" bash -c "! grep -aq '$s' '$tmp/curve.pcap'"
done
echo "captured $(packets "$tmp/plain.pcap") plain and $n CURVE packets"
finish
