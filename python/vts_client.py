"""A client for `vts serve` (docs/PROTOCOL.md), standard library only.

    from vts_client import Client, pose
    with Client("127.0.0.1", 5170, role="control", name="my-master") as c:
        job = c.sim_job()
        c.laser_on()
        c.servo(pose([600.0, 200.0, 100.0]))
        answer = c.step(dt_s=0.05)          # lockstep: advance simulated time
        for event in answer["events"]:
            print(event["event"], event["time_s"])
        print(c.joint())                    # the latest joint data, or None

Units as in the protocol: millimetres, seconds, degrees (fields named
`_deg`), world frame unless a field says `_sensor`. A pose is the dict
`{"t": [x, y, z], "R": [[r00, r01, r02], [r10, ...], [r20, ...]]}`
(translation in mm, rotation matrix row by row, mapping the named frame into
the world); `pose()` and `pose_parts()` convert from and to (t, R).

Requests are answered in order; events the server pushes in between (an
`event` field, no `id`) are queued and read with `events()` or
`next_event(timeout)`. A failed request raises VtsError(code, message).
"""

import json
import socket
import time as _time
from collections import deque

PROTOCOL = 1
DEFAULT_HOST = "127.0.0.1"
DEFAULT_PORT = 5170

__all__ = ["Client", "VtsError", "pose", "pose_parts", "identity_pose", "PROTOCOL", "DEFAULT_HOST", "DEFAULT_PORT"]


class VtsError(Exception):
    """A request the server refused: `code` is the protocol's error code
    (`bad_argument`, `not_controller`, `version`, ...), `message` its text,
    `answer` the whole response (e.g. `server_protocol` on `version`)."""

    def __init__(self, code, message="", answer=None):
        super().__init__("%s: %s" % (code, message) if message else str(code))
        self.code = code
        self.message = message
        self.answer = answer if answer is not None else {}


def pose(t, R=None):
    """A protocol pose from a translation t (3 numbers, mm) and a rotation
    matrix R (3x3, row by row; identity if omitted)."""
    if R is None:
        R = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    return {"t": [float(x) for x in t], "R": [[float(x) for x in row] for row in R]}


def pose_parts(p):
    """(t, R) of a protocol pose: t a list of 3 floats (mm), R a 3x3 list of rows."""
    return [float(x) for x in p["t"]], [[float(x) for x in row] for row in p["R"]]


def identity_pose():
    return pose([0.0, 0.0, 0.0])


class Client:
    """One connection to `vts serve`.

    host, port: the server's address (default 127.0.0.1:5170).
    role: "control" (moves the robot, commands the sensor, steps time) or
        "observe" (reads, receives events). Only one client controls.
    name: how the server names this client in its log.
    timeout: seconds to wait for a response (a lockstep `step` over many
        profiles can take a while; None waits for ever).
    hello: send `hello` at once (default). With hello=False call hello().

    The hello answer is kept in `self.server` (keys `server`, `mode`,
    `cell`, `time_s`, ...).
    """

    def __init__(self, host=DEFAULT_HOST, port=DEFAULT_PORT, role="control", name="vts_client.py",
                 timeout=60.0, hello=True, protocol=PROTOCOL):
        self.host, self.port, self.role, self.name = host, int(port), role, name
        self.timeout = timeout
        self._sock = socket.create_connection((host, self.port), timeout=timeout)
        self._sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self._buf = bytearray()
        self._events = deque()
        self._next_id = 1
        self.server = None
        if hello:
            self.hello(role=role, name=name, protocol=protocol)

    # -- connection ---------------------------------------------------------

    def close(self):
        if self._sock is not None:
            try:
                self._sock.close()
            finally:
                self._sock = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def _read_message(self, timeout):
        """The next message (dict) from the server, waiting at most `timeout`
        seconds (None: self.timeout). Raises socket.timeout, ConnectionError."""
        deadline = None if timeout is None else _time.monotonic() + timeout
        while True:
            nl = self._buf.find(b"\n")
            if nl >= 0:
                line = bytes(self._buf[:nl])
                del self._buf[:nl + 1]
                line = line.strip()
                if not line:
                    continue
                return json.loads(line.decode("utf-8"))
            # A timeout of 0 still takes what has already arrived.
            left = None if deadline is None else max(0.0, deadline - _time.monotonic())
            self._sock.settimeout(left)
            try:
                chunk = self._sock.recv(1 << 16)
            except (BlockingIOError, socket.timeout):
                raise socket.timeout("no message from the server within %.3g s" % timeout) from None
            if not chunk:
                raise ConnectionError("the server closed the connection")
            self._buf += chunk

    def send_line(self, line):
        """Sends one raw line (str or bytes; a newline is appended if missing)
        and returns the next response (not an event), without raising on an
        error answer. For testing the server's handling of bad input."""
        data = line.encode("utf-8") if isinstance(line, str) else bytes(line)
        if not data.endswith(b"\n"):
            data += b"\n"
        self._sock.sendall(data)
        return self._await_response(None)

    def _await_response(self, rid):
        while True:
            msg = self._read_message(self.timeout)
            if "event" in msg and "ok" not in msg:
                self._events.append(msg)
                continue
            if rid is not None and "id" in msg and msg["id"] != rid:
                raise VtsError("protocol", "response id %r does not match request id %r" % (msg.get("id"), rid), msg)
            return msg

    def request(self, cmd, **fields):
        """Sends {"cmd": cmd, **fields} and returns the answer (a dict with
        "ok": true). Raises VtsError(code, message) on an error answer."""
        rid = self._next_id
        self._next_id += 1
        msg = {"id": rid, "cmd": cmd}
        msg.update(fields)
        self._sock.sendall(json.dumps(msg, separators=(",", ":")).encode("utf-8") + b"\n")
        answer = self._await_response(rid)
        if not answer.get("ok", False):
            raise VtsError(answer.get("error", "unknown"), answer.get("message", ""), answer)
        return answer

    # -- events -------------------------------------------------------------

    def events(self):
        """The events received so far and not yet taken (oldest first); also
        reads what has already arrived without waiting."""
        try:
            while True:
                msg = self._read_message(0.0)
                if "event" in msg and "ok" not in msg:
                    self._events.append(msg)
                else:  # a response nobody waits for: keep it out of the way
                    self._events.append({"event": "unexpected-response", "response": msg})
        except socket.timeout:
            pass
        out = list(self._events)
        self._events.clear()
        return out

    def next_event(self, timeout=None):
        """The next event, waiting at most `timeout` seconds (None: for
        ever); None if none came."""
        if self._events:
            return self._events.popleft()
        deadline = None if timeout is None else _time.monotonic() + timeout
        while True:
            left = None if deadline is None else max(0.0, deadline - _time.monotonic())
            try:
                msg = self._read_message(left)
            except socket.timeout:
                return None
            if "event" in msg and "ok" not in msg:
                return msg

    # -- session ------------------------------------------------------------

    def hello(self, role="control", name="vts_client.py", protocol=PROTOCOL):
        """Opens the session. Raises VtsError("version") with
        answer["server_protocol"] if the server speaks another version, or
        VtsError("busy") if another client controls."""
        self.server = self.request("hello", protocol=protocol, role=role, client=name)
        self.role = self.server.get("role", role)
        return self.server

    def time(self):
        """Simulated time: {"time_s": s, "mode": "lockstep" | "realtime"}."""
        return self.request("time")

    def step(self, to_s=None, dt_s=None):
        """Lockstep only: advances simulated time to `to_s` (absolute, s) or
        by `dt_s` (s). Returns {"time_s", "events": [...]} with the sensor's
        alerts raised during the step, in order."""
        if (to_s is None) == (dt_s is None):
            raise ValueError("step: give exactly one of to_s and dt_s")
        return self.request("step", to_s=float(to_s)) if to_s is not None else self.request("step", dt_s=float(dt_s))

    def subscribe(self, events=True, profiles=False, joints=False):
        """Pushes from now on: the sensor's events, every profile taken
        ({"event": "profile", "profile": ...}), every joint accepted."""
        return self.request("subscribe", events=bool(events), profiles=bool(profiles), joints=bool(joints))

    # -- sensor interface -----------------------------------------------------

    def laser_on(self):
        """Answer with "confirmed" (bool) and, if not, "message" (why)."""
        return self.request("sensor.laser_on")

    def laser_off(self):
        return self.request("sensor.laser_off")

    def search_start(self):
        """The start is reported by event start-found (or start-behind)."""
        return self.request("sensor.search_start")

    def start_tracking(self):
        return self.request("sensor.start_tracking")

    def look_for_end(self):
        """The end is reported by event end-found."""
        return self.request("sensor.look_for_end")

    def sensor_idle(self):
        return self.request("sensor.idle")

    def sensor_state(self):
        """{"state", "start_point", "end_point" (world mm or None), "counters"}."""
        return self.request("sensor.state")

    def joint(self):
        """The latest joint data (dict, docs/PROTOCOL.md) with age_s, or None."""
        return self.request("sensor.joint").get("joint")

    def joints(self, after_index=-1):
        """{"joints": [joint data with profile_index > after_index, oldest
        first], "dropped": n}."""
        return self.request("sensor.joints", after_index=int(after_index))

    def profile(self):
        """The last profile taken (dict) or None."""
        return self.request("sensor.profile").get("profile")

    # -- robot channel --------------------------------------------------------

    def robot_pose(self):
        """{"time_s", "world_from_tool" (pose), "moving", "queued", "correction_mm"}."""
        return self.request("robot.pose")

    def servo(self, world_from_tool):
        """The TCP is at this pose (protocol pose dict) from now on."""
        return self.request("robot.servo", world_from_tool=world_from_tool)

    def move(self, world_from_tool, speed_mm_s, queue=False):
        """A linear move to the pose at speed_mm_s (mm/s); queue=True appends
        it to the moves not yet done (at most 64), else replaces them. Event
        move-done when the last move ends."""
        return self.request("robot.move", world_from_tool=world_from_tool, speed_mm_s=float(speed_mm_s),
                            queue=bool(queue))

    def stop(self):
        return self.request("robot.stop")

    def correct(self, offset_mm):
        """Path correction: offset_mm [x, y, z] added to the commanded position."""
        return self.request("robot.correct", offset_mm=[float(x) for x in offset_mm])

    # -- simulator ------------------------------------------------------------

    def sim_job(self):
        """The master's knowledge: seams (workpiece frame), world_from_workpiece
        (nominal), master parameters, sensor, source, seed, speed_mm_s."""
        return self.request("sim.job")

    def sim_truth(self):
        """The actual cell: seams (world), world_from_workpiece,
        workpiece_offset_mm, workpiece_rotation_deg."""
        return self.request("sim.truth")
