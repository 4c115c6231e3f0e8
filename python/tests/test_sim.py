"""vts.sim: the closed loop of `vts sim` in process, the same numbers as the
CLI, the per-cycle arrays consistent with the summary."""
import json

import numpy as np
import pytest

import vts


def test_scenarios_are_the_clis(vts_cli):
    listed = [line.split()[0] for line in vts_cli("sim", "--scenarios").splitlines() if line.strip()]
    assert vts.scenarios() == listed


def test_a_scenario_gives_the_clis_summary(vts_cli, tmp_path):
    cli = json.loads(vts_cli("sim", "--scenario", "weaving", "--json", "--out-dir", tmp_path / "w"))
    py = vts.sim("weaving")
    for k in ("scenario", "verdict", "reason", "robot", "profiles", "sim_time_s", "completed"):
        assert py[k] == cli[k], k
    for a, b in zip(py["seams"], cli["seams"]):
        for k in ("rms_lateral_mm", "rms_vertical_mm", "max_error_mm", "start_error_mm", "end_error_mm"):
            assert a[k] == b[k], k
        assert a["open_loop"] == b["open_loop"]


def test_arrays_agree_with_the_summary():
    r = vts.sim(robot="kr16", robot_seed=3, seed=3, seam1_bow_mm=4)
    n = len(r["time_s"])
    assert r["tcp_mm"].shape == (n, 3) and r["commanded_mm"].shape == (n, 3) and len(r["phase"]) == n
    weld = np.array([p == "weld" for p in r["phase"]])
    # Errors only while welding.
    assert np.all(np.isnan(r["lateral_error_mm"][~weld]))
    assert not np.any(np.isnan(r["lateral_error_mm"][weld]))
    for k, seam in enumerate(r["seams"]):
        mask = weld & (r["seam_index"] == k)
        rms = float(np.sqrt(np.mean(r["lateral_error_mm"][mask] ** 2)))
        assert rms == pytest.approx(seam["rms_lateral_mm"], rel=1e-9, abs=1e-12)
    # While welding the arm is where it was sent within its absolute error
    # (0.2-1 mm) and a little lag; a perfect robot would be exactly there.
    off = np.linalg.norm(r["tcp_mm"] - r["commanded_mm"], axis=1)[weld]
    assert 0.05 < float(np.min(off)) and float(np.max(off)) < 2.0
    assert r["robot"] == "kr16" and r["verdict"] == "pass"


def test_bad_input_is_a_value_error():
    with pytest.raises(ValueError, match="colour"):
        vts.sim(colour="red")
    with pytest.raises(ValueError, match="no scenario 'nope'"):
        vts.sim("nope")
    with pytest.raises(ValueError, match="robot = 'ur5'"):
        vts.sim(robot="ur5")
    with pytest.raises(ValueError, match="not both"):
        vts.sim("weaving", seed=2)
