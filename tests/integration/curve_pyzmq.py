"""sphd --curve with pyzmq clients (Debian's python3-zmq) over loopback TCP: an authorised
client submits a job and follows it on the stream; a plain client and an unauthorised key get
nothing from the control socket or the stream, and their socket monitors report the failed
handshake; an authorised client already connected loses the control socket and the stream once
its key is removed and sphd gets SIGHUP.
Usage: curve_pyzmq.py SPHD SOURCE_DIR"""
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

import zmq
from zmq.utils.monitor import recv_monitor_message

sys.path.insert(0, os.path.dirname(__file__))
from sphd_harness import Failures  # noqa: E402

FAILED = (zmq.EVENT_HANDSHAKE_FAILED_AUTH | zmq.EVENT_HANDSHAKE_FAILED_PROTOCOL
          | zmq.EVENT_HANDSHAKE_FAILED_NO_DETAIL)


def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def main():
    sphd, src = sys.argv[1], sys.argv[2]
    f = Failures("curve_pyzmq")
    tmp = tempfile.mkdtemp(prefix="sphd-curve-")
    os.makedirs(f"{tmp}/srv/clients")
    server_pub, server_sec = zmq.curve_keypair()
    alice_pub, alice_sec = zmq.curve_keypair()
    bob_pub, bob_sec = zmq.curve_keypair()
    fd = os.open(f"{tmp}/srv/server.key", os.O_WRONLY | os.O_CREAT, 0o600)
    os.write(fd, server_sec + b"\n")
    os.close(fd)
    with open(f"{tmp}/srv/clients/alice.pub", "wb") as fh:
        fh.write(alice_pub + b"\n")
    control = f"tcp://127.0.0.1:{free_port()}"
    stream = f"tcp://127.0.0.1:{free_port()}"
    log = open(f"{tmp}/sphd.log", "w")
    proc = subprocess.Popen([sphd, "--curve", f"{tmp}/srv", "--listen", control, "--publish",
                             stream, "--state-dir", f"{tmp}/state", "--threads", "1"],
                            stderr=log)
    ctx = zmq.Context()

    def sock(kind, endpoint, keys=None, topic=None):
        s = ctx.socket(kind)
        s.setsockopt(zmq.LINGER, 0)
        if keys:
            s.curve_serverkey = server_pub
            s.curve_publickey, s.curve_secretkey = keys
        if topic is not None:
            s.setsockopt(zmq.SUBSCRIBE, topic)
        mon = s.get_monitor_socket(FAILED)
        s.connect(endpoint)
        return s, mon

    counter = [0]

    def request(s, op, args=None, timeout=5.0):
        """The reply to this request (replies to earlier ones that timed out are skipped)."""
        counter[0] += 1
        rid = f"{op}-{counter[0]}"
        s.send(json.dumps({"v": 1, "id": rid, "op": op, "args": args or {}}).encode())
        deadline = time.time() + timeout
        while True:
            left = deadline - time.time()
            if left <= 0 or not s.poll(int(left * 1000)):
                return None
            r = json.loads(s.recv())
            if r.get("id") == rid:
                return r

    def reloaded(count, timeout=20.0):
        """Waits until sphd has logged its count-th reload of the keys (SIGHUP)."""
        deadline = time.time() + timeout
        while time.time() < deadline:
            with open(f"{tmp}/sphd.log") as fh:
                if fh.read().count("after reload") >= count:
                    return True
            time.sleep(0.05)
        return False

    def refusal(mon, timeout=5.0):
        """The first handshake failure the monitor reports: its event, or None."""
        if not mon.poll(int(timeout * 1000)):
            return None
        return recv_monitor_message(mon)["event"]

    try:
        alice, _ = sock(zmq.DEALER, control, (alice_pub, alice_sec))
        r = None
        for _ in range(100):
            r = request(alice, "hello", timeout=0.2)
            if r:
                break
        f.check(r and r["ok"], "alice's hello over CURVE", r)
        f.check(r and r["result"].get("security") == "curve", "hello says the sockets use CURVE",
                r)
        # subscribe first, then submit and start: every event of the job arrives, encrypted
        sub, _ = sock(zmq.SUB, stream, (alice_pub, alice_sec), b"db")
        bob_sub, bob_sub_mon = sock(zmq.SUB, stream, (bob_pub, bob_sec), b"")
        plain_sub, plain_sub_mon = sock(zmq.SUB, stream, None, b"")
        time.sleep(0.5)
        with open(os.path.join(src, "cases", "dambreak.json")) as fh:
            case = json.load(fh)
        r = request(alice, "submit", {"case": case, "job": "db",
                                      "set": ["dx=0.02", "time.end=0.05"]})
        f.check(r and r["ok"], "alice submits over CURVE", r)
        events, deadline = [], time.time() + 60
        while time.time() < deadline and not (events and events[-1].get("type") == "state"
                                               and events[-1].get("state") == "done"):
            if sub.poll(500):
                topic, body = sub.recv_multipart()
                events.append(json.loads(body))
        types = [e["type"] for e in events]
        f.check("diag" in types, "alice's subscriber got diag events", types)
        f.check(events and events[-1].get("state") == "done", "and the final state", events[-1:])
        f.check(bob_sub.poll(200) == 0, "bob's subscriber (key not authorised) got nothing")
        f.check(refusal(bob_sub_mon) == zmq.EVENT_HANDSHAKE_FAILED_AUTH,
                "bob's stream handshake failed for authentication")
        f.check(plain_sub.poll(200) == 0, "a plain subscriber got nothing")
        f.check(refusal(plain_sub_mon) in (zmq.EVENT_HANDSHAKE_FAILED_PROTOCOL,
                                           zmq.EVENT_HANDSHAKE_FAILED_NO_DETAIL),
                "a plain subscriber's handshake failed")

        bob, bob_mon = sock(zmq.DEALER, control, (bob_pub, bob_sec))
        f.check(request(bob, "ping", timeout=1.0) is None, "bob's ping gets no reply")
        f.check(refusal(bob_mon) == zmq.EVENT_HANDSHAKE_FAILED_AUTH,
                "bob's handshake failed for authentication")
        plain, plain_mon = sock(zmq.DEALER, control)
        f.check(request(plain, "ping", timeout=1.0) is None, "a plain client's ping gets no reply")
        f.check(refusal(plain_mon) is not None, "a plain client's handshake failed")

        # alice stays connected; her key is removed and sphd gets SIGHUP
        sub2, sub2_mon = sock(zmq.SUB, stream, (alice_pub, alice_sec), b"")
        time.sleep(0.3)
        f.check(request(alice, "ping")["ok"], "alice's live connection works before the revocation")
        os.remove(f"{tmp}/srv/clients/alice.pub")
        proc.send_signal(signal.SIGHUP)
        f.check(reloaded(1), "sphd reloads the keys on SIGHUP")
        f.check(request(alice, "ping", timeout=1.5) is None,
                "alice's live connection gets no reply after her key is revoked")
        f.check(refusal(sub2_mon) == zmq.EVENT_HANDSHAKE_FAILED_AUTH,
                "her live subscriber is dropped and refused on reconnecting")
        f.check(proc.poll() is None, "sphd keeps running")
        # bob's key added: he gets in without a restart
        with open(f"{tmp}/srv/clients/bob.pub", "wb") as fh:
            fh.write(bob_pub + b"\n")
        proc.send_signal(signal.SIGHUP)
        f.check(reloaded(2), "and again")
        bob2, _ = sock(zmq.DEALER, control, (bob_pub, bob_sec))
        r = request(bob2, "query", {"job": "db"})
        f.check(r and r["ok"] and r["result"]["state"] == "done", "bob, added, queries the job", r)
        r = request(bob2, "shutdown")
        f.check(r and r["ok"], "bob shuts sphd down", r)
        f.check(proc.wait(timeout=20) == 0, "sphd exits 0")
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        ctx.destroy(linger=0)
        log.close()
        text = open(f"{tmp}/sphd.log").read()
        shutil.rmtree(tmp, ignore_errors=True)
    return f.done(text)


if __name__ == "__main__":
    sys.exit(main())
