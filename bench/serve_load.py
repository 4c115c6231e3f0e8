#!/usr/bin/env python3
"""Load test of `vts serve --realtime` on loopback (docs/RELIABILITY.md,
"vts serve"): one controller lights the laser and moves the robot along the
box's first seam; N observers subscribe to every profile for D seconds. Each
observer checks that the profile indices it receives are consecutive (no
message lost) and counts them; the server's resident memory is sampled every
second (growth = last sample minus the one at 10 s).

    /usr/bin/python3 bench/serve_load.py [--vts build/bin/vts] [--observers 50] [--seconds 60]

Standard library only. Exit status 1 if a profile was lost or an observer
was dropped.
"""
import argparse
import json
import os
import re
import selectors
import socket
import subprocess
import sys
import time

INDEX = re.compile(rb'"index":(\d+)')


def rss_kb(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return 0


def cpu_s(pid):
    with open(f"/proc/{pid}/stat") as f:
        parts = f.read().rsplit(")", 1)[1].split()
    return (int(parts[11]) + int(parts[12])) / os.sysconf("SC_CLK_TCK")


class Conn:
    def __init__(self, port):
        self.sock = socket.create_connection(("127.0.0.1", port))
        self.buf = b""

    def send(self, obj):
        self.sock.sendall((json.dumps(obj) + "\n").encode())

    def answer(self):
        while b"\n" not in self.buf:
            chunk = self.sock.recv(65536)
            if not chunk:
                raise RuntimeError("server closed the connection")
            self.buf += chunk
        line, self.buf = self.buf.split(b"\n", 1)
        return json.loads(line)

    def request(self, **fields):
        self.send(fields)
        while True:
            a = self.answer()
            if "event" not in a:
                if not a.get("ok"):
                    raise RuntimeError(f"{fields['cmd']}: {a}")
                return a


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--vts", default="build/bin/vts")
    ap.add_argument("--observers", type=int, default=50)
    ap.add_argument("--seconds", type=float, default=60.0)
    a = ap.parse_args()

    srv = subprocess.Popen([a.vts, "serve", "--realtime", "--port", "0"], stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True)
    try:
        port = int(srv.stdout.readline().strip().rsplit(":", 1)[1])
        ctl = Conn(port)
        ctl.request(cmd="hello", role="control", client="load-controller")
        job = ctl.request(cmd="sim.job")
        observers = []
        for i in range(a.observers):
            c = Conn(port)
            c.request(cmd="hello", role="observe", client=f"observer-{i}")
            c.request(cmd="subscribe", events=True, profiles=True)
            c.sock.setblocking(False)
            c.last = None
            c.count = 0
            c.gaps = 0
            observers.append(c)
        # The torch over the first seam's start, then along it at 10 mm/s.
        wp = job["world_from_workpiece"]
        seam = job["seams"][0]

        def to_world(p):
            R, t = wp["R"], wp["t"]
            return [sum(R[i][k] * p[k] for k in range(3)) + t[i] for i in range(3)]

        s, e = to_world(seam["start_mm"]), to_world(seam["end_mm"])
        rot = [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]
        start = {"t": [s[0], s[1], s[2] + 5.0], "R": rot}
        end = {"t": [e[0], e[1], e[2] + 5.0], "R": rot}
        ctl.request(cmd="robot.move", world_from_tool=start, speed_mm_s=500.0)
        ctl.request(cmd="sensor.laser_on")
        ctl.request(cmd="sensor.search_start")
        ctl.request(cmd="robot.move", world_from_tool=end, speed_mm_s=10.0, queue=True)

        sel = selectors.DefaultSelector()
        for c in observers:
            sel.register(c.sock, selectors.EVENT_READ, c)
        t0 = time.monotonic()
        cpu0 = cpu_s(srv.pid)
        samples = []
        next_sample = t0
        closed = 0
        while time.monotonic() - t0 < a.seconds:
            now = time.monotonic()
            if now >= next_sample:
                samples.append((now - t0, rss_kb(srv.pid)))
                next_sample += 1.0
            for key, _ in sel.select(timeout=0.2):
                c = key.data
                try:
                    chunk = c.sock.recv(1 << 20)
                except BlockingIOError:
                    continue
                if not chunk:
                    sel.unregister(c.sock)
                    closed += 1
                    continue
                c.buf += chunk
                *lines, c.buf = c.buf.split(b"\n")
                for line in lines:
                    if not line.startswith(b'{"event":"profile"'):
                        continue
                    m = INDEX.search(line, 0, 200)
                    k = int(m.group(1))
                    if c.last is not None and k != c.last + 1:
                        c.gaps += 1
                    c.last = k
                    c.count += 1
        elapsed = time.monotonic() - t0
        cpu = cpu_s(srv.pid) - cpu0
        state = ctl.request(cmd="sensor.state")
        counts = [c.count for c in observers]
        gaps = sum(c.gaps for c in observers)
        base = next((r for t, r in samples if t >= 10.0), samples[0][1])
        print(f"{a.observers} observers, {elapsed:.1f} s, profiles per observer: min {min(counts)}, "
              f"max {max(counts)} ({min(counts) / elapsed:.2f} Hz at the least)")
        print(f"lost (index gaps): {gaps}; observers closed by the server: {closed}")
        print(f"server: {cpu / elapsed * 100:.0f} % of a core; RSS {samples[0][1] / 1024:.1f} MB at start, "
              f"{base / 1024:.1f} MB at 10 s, {samples[-1][1] / 1024:.1f} MB at the end "
              f"(growth after 10 s: {(samples[-1][1] - base) / 1024:+.1f} MB)")
        print(f"sensor: {state['state']}, {state['counters']['profiles']} profiles read in the task")
        return 1 if gaps or closed else 0
    finally:
        srv.terminate()
        try:
            _, err = srv.communicate(timeout=10)
            sys.stderr.write(err)
        except subprocess.TimeoutExpired:
            srv.kill()


if __name__ == "__main__":
    sys.exit(main())
