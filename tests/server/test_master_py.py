"""vts serve from Python: the client (python/vts_client.py) against the
server, and examples/master.py in lockstep against `vts sim --json`.

Environment: VTS_BIN (the vts binary, required), VTS_SOURCE_DIR (the source
tree; default: two directories up from this file).
"""

import json
import os
import subprocess
import sys

import pytest

SOURCE_DIR = os.environ.get("VTS_SOURCE_DIR") or os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
VTS_BIN = os.environ.get("VTS_BIN", "")
sys.path.insert(0, os.path.join(SOURCE_DIR, "python"))
import vts_client  # noqa: E402

MASTER_PY = os.path.join(SOURCE_DIR, "examples", "master.py")

pytestmark = pytest.mark.skipif(not VTS_BIN or not os.access(VTS_BIN, os.X_OK), reason="VTS_BIN not set")


class Server:
    """`vts serve --port 0 ARGS...`: its port from the first stdout line."""

    def __init__(self, *args):
        self.proc = subprocess.Popen([VTS_BIN, "serve", "--port", "0", *args], stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, text=True)
        line = self.proc.stdout.readline()
        if not line.startswith("listening "):
            self.stop()
            raise RuntimeError("vts serve did not start: %r %s" % (line, self.proc.stderr.read()))
        self.host, port = line.split()[1].rsplit(":", 1)
        self.port = int(port)

    def client(self, role="control", **kw):
        return vts_client.Client(self.host, self.port, role=role, name="pytest", **kw)

    def stop(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        self.proc.stdout.close()
        self.proc.stderr.close()


@pytest.fixture
def server():
    s = Server()
    yield s
    s.stop()


def test_hello(server):
    with server.client() as c:
        assert c.server["ok"] is True
        assert c.server["protocol"] == vts_client.PROTOCOL
        assert c.server["role"] == "control"
        assert c.server["mode"] == "lockstep"
        t = c.time()
        assert t["time_s"] == 0.0 and t["mode"] == "lockstep"


def test_version_mismatch_then_hello_again(server):
    with server.client(hello=False) as c:
        with pytest.raises(vts_client.VtsError) as e:
            c.hello(protocol=vts_client.PROTOCOL + 98)
        assert e.value.code == "version"
        assert e.value.answer.get("server_protocol") == vts_client.PROTOCOL
        # The connection stays open for a new hello.
        assert c.hello()["protocol"] == vts_client.PROTOCOL


def test_no_hello(server):
    with server.client(hello=False) as c:
        with pytest.raises(vts_client.VtsError) as e:
            c.time()
        assert e.value.code == "no_hello"


def test_observer_is_not_controller(server):
    with server.client() as ctl, server.client(role="observe") as obs:
        assert obs.server["role"] == "observe"
        for call in (obs.laser_on, lambda: obs.step(dt_s=0.05), lambda: obs.servo(vts_client.identity_pose())):
            with pytest.raises(vts_client.VtsError) as e:
                call()
            assert e.value.code == "not_controller"
        # Observers read.
        assert obs.sensor_state()["state"] == "idle"
        assert ctl.time()["time_s"] == 0.0


def test_second_controller_is_busy(server):
    with server.client() as ctl:
        with pytest.raises(vts_client.VtsError) as e:
            server.client()
        assert e.value.code == "busy"
        assert ctl.time()["mode"] == "lockstep"


def test_bad_json_keeps_the_connection(server):
    with server.client() as c:
        for line in ("{not json", "[1, 2]", "42", '"cmd"', b"\xff\xfe{}"):
            answer = c.send_line(line)
            assert answer["ok"] is False and answer["error"] == "bad_json", (line, answer)
        assert c.time()["time_s"] == 0.0


def test_unknown_command_and_bad_argument(server):
    with server.client() as c:
        with pytest.raises(vts_client.VtsError) as e:
            c.request("no.such.command")
        assert e.value.code == "unknown_command"
        with pytest.raises(vts_client.VtsError) as e:
            c.servo({"t": [0, 0, 0], "R": [[2, 0, 0], [0, 1, 0], [0, 0, 1]]})
        assert e.value.code == "bad_argument"
        with pytest.raises(vts_client.VtsError) as e:
            c.step(to_s=0.0)  # not after the current time
        assert e.value.code == "bad_argument"


def test_step_events_and_queue(server):
    """A laser that comes on, a step with the answer's events, and the
    pushed events (subscribe) queued between answers."""
    with server.client() as c:
        job = c.sim_job()
        assert job["sensor"]["rate_hz"] > 0
        c.subscribe(events=True)
        c.servo(vts_client.identity_pose())
        assert c.laser_on()["confirmed"] in (True, False)
        answer = c.step(dt_s=0.5)
        assert answer["time_s"] == 0.5
        assert isinstance(answer["events"], list)
        assert isinstance(c.events(), list)
        assert c.sensor_state()["counters"]["profiles"] >= 0


def _vts_sim(seed, tmp_path):
    out = subprocess.run([VTS_BIN, "sim", "--json", "--seed", str(seed), "--out-dir", str(tmp_path / "sim")],
                         capture_output=True, text=True, timeout=600)
    assert out.returncode in (0, 1), out.stderr
    return json.loads(out.stdout)


def _master_py(port, *args):
    out = subprocess.run([sys.executable, MASTER_PY, "--port", str(port), *args], capture_output=True, text=True,
                         timeout=600)
    assert out.returncode in (0, 1), out.stderr
    return out.stdout


def _differences(a, b, path=""):
    """The fields where a and b differ, with both values."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = []
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                out.append((path + k, a.get(k, "<missing>"), b.get(k, "<missing>")))
            else:
                out += _differences(a[k], b[k], path + k + ".")
        return out
    if isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        out = []
        for i, (x, y) in enumerate(zip(a, b)):
            out += _differences(x, y, path + str(i) + ".")
        return out
    if type(a) != type(b) or a != b:
        return [(path.rstrip("."), a, b)]
    return []


@pytest.mark.parametrize("seed", [1, 5])
def test_master_py_matches_vts_sim(seed, tmp_path):
    """examples/master.py --json against `vts serve --seed S` prints the
    summary of `vts sim --json --seed S`, every number to the last digit."""
    s = Server("--seed", str(seed))
    try:
        py = json.loads(_master_py(s.port, "--json"))
    finally:
        s.stop()
    cpp = _vts_sim(seed, tmp_path)
    # What vts sim reports beyond the experiment master.py runs: the robot
    # (perfect here), the open-loop run, its own timing.
    for k in ("robot", "robot_seed", "robot_fault", "weave", "sim_wall_time_s"):
        cpp.pop(k, None)
    for seam in cpp["seams"]:
        seam.pop("open_loop", None)
    assert list(py) == [k for k in cpp if k != "out_dir"]  # same keys, same order
    for k in ("wall_time_s", "out_dir"):
        py.pop(k, None)
        cpp.pop(k, None)
    assert py["completed"] is True
    diffs = _differences(py, cpp)
    assert not diffs, "master.py and vts sim differ (field, master.py, vts sim):\n" + "\n".join(
        "  %s: %r %r" % d for d in diffs)


def test_master_py_text_output():
    s = Server("--seed", "1")
    try:
        text = _master_py(s.port)
    finally:
        s.stop()
    lines = text.splitlines()
    assert lines[0].startswith("master.py: box cell, workpiece displaced")
    assert lines[2].startswith("seam 1: search") and lines[3].startswith("seam 2: search")
    assert "failed" not in text and "profiles," in lines[4]


@pytest.mark.skipif(os.environ.get("VTS_REALTIME_TESTS") != "1",
                    reason="takes a minute of wall-clock time: set VTS_REALTIME_TESTS=1")
def test_master_py_realtime():
    """examples/master.py --realtime against `vts serve --realtime`: both
    seams welded with the joint data polled every 2 s, the sensor at its
    rate (20 Hz for mspot) while the laser is on."""
    s = Server("--realtime", "--seed", "1")
    try:
        summ = json.loads(_master_py(s.port, "--realtime", "--json"))
    finally:
        s.stop()
    assert summ["completed"] is True, summ
    for m in summ["seams"]:
        assert m["end_found"] and not m["failure"] and m["welded_mm"] > 140.0
        assert m["max_error_mm"] < 0.3
    rt = summ["realtime"]
    assert abs(rt["laser_rate_hz"] - summ["rate_hz"]) < 0.05 * summ["rate_hz"]
    assert rt["polls"] >= 10
