#!/usr/bin/env bash
# sphd --curve with sphctl over loopback TCP: keygen (private key mode 600), keys found from the
# config file, the environment and options; an authorised client submits and watches jobs; an
# unauthorised key and a plain client are refused and sphctl exits 77 at once (not a timeout);
# a key removed from clients/ stops working after SIGHUP, without a restart; unsafe or missing
# server keys are refused (78); a non-loopback endpoint needs no --insecure with --curve.
# Usage: curve_sphctl.sh SPHD SPHCTL SOURCE_DIR
set -u
SPHD=$1 SPHCTL=$2 SRC=$3
. "$(dirname "$0")/lib.sh"
watchdog 150 # under ctest's TIMEOUT of 180 s: a hang says where (one in CI was a plain sphctl blocked in a send to this CURVE server, fixed since)
free_port() { /usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'; }
P1=$(free_port) P2=$(free_port)
export SPHD_ENDPOINT="tcp://127.0.0.1:$P1"
STREAM="tcp://127.0.0.1:$P2"
srv="$tmp/srv" alice="$tmp/alice" bob="$tmp/bob" nobody="$tmp/nobody"
mkdir -p "$srv/clients" "$nobody"

# keys
expect_rc "keygen for the server" 0 "$SPHCTL" keygen --out "$srv/server"
check "the server's secret key is private" test "$(stat -c %a "$srv/server.key")" = 600
check "its public key is readable" test "$(stat -c %a "$srv/server.pub")" = 644
check "keygen prints the public key" grep -qxF -e "$(cat "$srv/server.pub")" "$tmp/out"
expect_rc "keygen keeps existing keys" 73 "$SPHCTL" keygen --out "$srv/server"
expect_rc "alice's keys in her config dir" 0 env XDG_CONFIG_HOME="$alice" "$SPHCTL" keygen
check "alice's secret key is private" test "$(stat -c %a "$alice/sphctl/client.key")" = 600
check "alice's config dir is private" test "$(stat -c %a "$alice/sphctl")" = 700
expect_rc "bob's keys" 0 env XDG_CONFIG_HOME="$bob" "$SPHCTL" keygen
cp "$alice/sphctl/client.pub" "$srv/clients/alice.pub"
printf 'endpoint = %s\nserver_key = %s\n' "$SPHD_ENDPOINT" "$srv/server.pub" \
  >"$alice/sphctl/config"

# unsafe or missing server keys
chmod 644 "$srv/server.key"
expect_rc "a server key others can read is refused" 78 \
  "$SPHD" --curve "$srv" --listen "$SPHD_ENDPOINT" --publish "$STREAM" --state-dir "$STATE"
check "and said why" grep -q "chmod 600" "$tmp/err"
chmod 600 "$srv/server.key"
expect_rc "no server key is refused" 78 \
  "$SPHD" --curve "$nobody" --listen "$SPHD_ENDPOINT" --publish "$STREAM" --state-dir "$STATE"

start_curve() { # the daemon with CURVE; ready when alice's ping answers
  "$SPHD" --curve "$srv" --listen "$SPHD_ENDPOINT" --publish "$STREAM" --state-dir "$STATE" \
    --threads 1 2>>"$tmp/sphd.log" &
  sphd_pid=$!
  for _ in $(seq 1 100); do
    XDG_CONFIG_HOME="$alice" "$SPHCTL" --timeout 1 ping >/dev/null 2>&1 && return 0
    sleep 0.05
  done
  echo "FAIL: sphd --curve did not start"; cat "$tmp/sphd.log"; exit 1
}
start_curve

# alice, from her config file (endpoint, server key, her key)
A() { env -u SPHD_ENDPOINT XDG_CONFIG_HOME="$alice" "$SPHCTL" "$@"; }
expect_rc "alice pings over CURVE" 0 A ping
expect_rc "alice submits a kernel study and watches it" 0 \
  A submit "$SRC/cases/kernel_study.json" --id ks --watch --json
check "it is done" grep -q '"state": *"done"' "$tmp/out"
expect_rc "alice submits a dam break and watches its stream" 0 \
  A submit "$SRC/cases/dambreak.json" --id db --set dx=0.02 --set time.end=0.5 --watch --json
check "the stream carried diag events" grep -q '"type": *"diag"' "$tmp/out"
check "and the final state" grep -q '"state": *"done"' "$tmp/out"
# the environment instead of the config file
expect_rc "keys from SPHD_SERVER_KEY and SPHCTL_KEY" 0 \
  env XDG_CONFIG_HOME="$nobody" SPHD_SERVER_KEY="$(cat "$srv/server.pub")" \
  SPHCTL_KEY="$alice/sphctl/client.key" "$SPHCTL" ping
# options win over the environment
expect_rc "--server-key and --key" 0 \
  env XDG_CONFIG_HOME="$nobody" SPHD_SERVER_KEY=nonsense "$SPHCTL" \
  --server-key "$(cat "$srv/server.pub")" --key "$alice/sphctl/client.key" ping
expect_rc "a malformed server key is a config error" 78 \
  env XDG_CONFIG_HOME="$nobody" SPHD_SERVER_KEY=nonsense "$SPHCTL" ping

# refusals: 77 at once, not a 10 s timeout
t0=$(date +%s)
expect_rc "bob (key not authorised) is refused: 77" 77 \
  env XDG_CONFIG_HOME="$bob" "$SPHCTL" --server-key "$srv/server.pub" status
check "sphctl says bob's key is not authorised" grep -q "not authorised" "$tmp/err"
expect_rc "a plain client is refused: 77" 77 env XDG_CONFIG_HOME="$nobody" "$SPHCTL" ping
check "sphctl says CURVE is required" grep -q "requires CURVE" "$tmp/err"
expect_rc "bob cannot watch either" 77 \
  env XDG_CONFIG_HOME="$bob" "$SPHCTL" --server-key "$srv/server.pub" watch db
check "the refusals took less than the timeout" test $(( $(date +%s) - t0 )) -lt 9
check "sphd logged bob's refusal" grep -q "refused a client from 127.0.0.1" "$tmp/sphd.log"

# revocation: remove alice's key, SIGHUP, and she is refused; sphd keeps running
rm "$srv/clients/alice.pub"
kill -HUP "$sphd_pid"
for _ in $(seq 1 50); do grep -q "after reload" "$tmp/sphd.log" && break; sleep 0.05; done
expect_rc "after SIGHUP alice's removed key is refused: 77" 77 A ping
check "sphd is still running" kill -0 "$sphd_pid"
cp "$alice/sphctl/client.pub" "$srv/clients/alice.pub"
kill -HUP "$sphd_pid"
for _ in $(seq 1 50); do [ "$(grep -c "after reload" "$tmp/sphd.log")" -ge 2 ] && break; sleep 0.05; done
expect_rc "her key added back, SIGHUP: she is in again" 0 A ping
expect_rc "shutdown over CURVE" 0 A shutdown
rc=0; wait "$sphd_pid" || rc=$?; sphd_pid=""
check "sphd exits 0" test "$rc" = 0

# a non-loopback endpoint: refused without CURVE or --insecure, accepted with --curve
P3=$(free_port) P4=$(free_port)
expect_rc "0.0.0.0 without --curve or --insecure is refused" 64 \
  "$SPHD" --listen "tcp://0.0.0.0:$P3" --publish "tcp://0.0.0.0:$P4" --state-dir "$STATE"
check "and pointed to --curve" grep -q -- "--curve" "$tmp/err"
"$SPHD" --curve "$srv" --listen "tcp://0.0.0.0:$P3" --publish "tcp://0.0.0.0:$P4" \
  --state-dir "$STATE" --threads 1 2>>"$tmp/sphd.log" &
sphd_pid=$!
ok=1
for _ in $(seq 1 100); do
  A --endpoint "tcp://127.0.0.1:$P3" --timeout 1 ping >/dev/null 2>&1 && { ok=0; break; }
  sleep 0.05
done
check "sphd --curve on 0.0.0.0 serves alice (no --insecure)" test "$ok" = 0
expect_rc "and refuses a plain client there" 77 \
  env XDG_CONFIG_HOME="$nobody" "$SPHCTL" --endpoint "tcp://127.0.0.1:$P3" ping
A --endpoint "tcp://127.0.0.1:$P3" shutdown >/dev/null
wait "$sphd_pid"; sphd_pid=""
finish
