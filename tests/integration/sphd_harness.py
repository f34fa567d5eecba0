"""A real sphd on a temporary ipc endpoint and state dir, and a small independent client written
with pyzmq (Debian's python3-zmq): the integration tests talk to sphd the way other programs do."""
import json
import os
import shutil
import signal
import subprocess
import tempfile
import time

import zmq


class Failures:
    """Counts checks; prints each failure; the test exits 1 if any failed."""

    def __init__(self, name):
        self.name, self.passed, self.failed = name, 0, 0

    def check(self, cond, what, detail=None):
        if cond:
            self.passed += 1
        else:
            self.failed += 1
            print(f"FAIL: {what}" + (f": {detail}" if detail is not None else ""), flush=True)
        return cond

    def done(self, log=None):
        """log: the daemon's stderr, shown (its tail) when a check failed."""
        print(f"{self.name}: {self.passed} passed, {self.failed} failed", flush=True)
        if self.failed and log:
            print("--- sphd log (tail):")
            print("\n".join(log.splitlines()[-40:]))
        return 1 if self.failed else 0


class Daemon:
    def __init__(self, sphd, *opts):
        self.tmp = tempfile.mkdtemp(prefix="sphd-it-")
        self.control = f"ipc://{self.tmp}/run/control"
        self.stream = f"ipc://{self.tmp}/run/stream"
        self.state = os.path.join(self.tmp, "state")
        self.logpath = os.path.join(self.tmp, "sphd.log")
        self.ctx = zmq.Context()
        self.proc = subprocess.Popen(
            [sphd, "--listen", self.control, "--publish", self.stream, "--state-dir", self.state,
             *opts], stderr=open(self.logpath, "w"))
        self.req = None
        deadline = time.time() + 10
        while time.time() < deadline:
            if self.proc.poll() is not None:
                raise RuntimeError("sphd exited at start:\n" + self.log())
            try:
                if self.request("ping", timeout=0.5)["ok"]:
                    return
            except TimeoutError:
                pass
            time.sleep(0.05)
        raise RuntimeError("sphd did not answer ping:\n" + self.log())

    def log(self):
        with open(self.logpath) as f:
            return f.read()

    def socket(self, kind=zmq.DEALER):
        s = self.ctx.socket(kind)
        s.setsockopt(zmq.LINGER, 0)
        s.connect(self.control)
        return s

    def request(self, op, args=None, timeout=10.0, raw=None, sock=None):
        """One request on a fresh DEALER (or `sock`); the reply as a dict. raw: bytes to send."""
        own = sock is None
        s = sock or self.socket(zmq.DEALER)
        try:
            body = raw if raw is not None else json.dumps(
                {"v": 1, "id": f"t-{op}", "op": op, "args": args or {}}).encode()
            if s.socket_type == zmq.DEALER:
                s.send(body)
            else:
                s.send(body)
            if not s.poll(int(timeout * 1000)):
                raise TimeoutError(f"no reply to {op!r} within {timeout} s")
            return json.loads(s.recv())
        finally:
            if own:
                s.close()

    def ok(self, op, args=None, **kw):
        r = self.request(op, args, **kw)
        if not r.get("ok"):
            raise AssertionError(f"{op} {args}: {r}")
        return r["result"]

    def subscribe(self, topic=b""):
        s = self.ctx.socket(zmq.SUB)
        s.setsockopt(zmq.LINGER, 0)
        s.setsockopt(zmq.SUBSCRIBE, topic)
        s.connect(self.stream)
        return s

    def wait_state(self, job, states, timeout=60.0):
        deadline = time.time() + timeout
        while time.time() < deadline:
            st = self.ok("query", {"job": job})
            if st["state"] in states:
                return st
            time.sleep(0.02)
        raise AssertionError(f"{job} not in {states} within {timeout} s: {st}")

    def shutdown(self):
        """sphd's `shutdown`; returns the exit code."""
        try:
            self.request("shutdown", timeout=10)
        except TimeoutError:
            pass
        try:
            return self.proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            return self.proc.wait()

    def close(self):
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGKILL)
            self.proc.wait()
        self.ctx.destroy(linger=0)
        shutil.rmtree(self.tmp, ignore_errors=True)


def big_study(src, particles=600000, name="big"):
    """A kernel study that keeps a worker busy for a while (about 0.1 s per 200k particles)."""
    with open(os.path.join(src, "cases", "kernel_study.json")) as f:
        c = json.load(f)
    c.update(name=name, particles=particles, functions=["exp", "sin"],
             kernels=[{"type": "cubic_spline"}, {"type": "wendland_c2"}])
    return c
