"""vts.Tracker on hand-made profiles, vts.track against `vts track`, EXR
read/write round trips."""
import json

import numpy as np
import pytest

import vts


def fillet_profile(n=400, root=(1.5, 120.0), half=25.0):
    """A 90-degree fillet seen along its bisector: two lines meeting at root
    at +-45 degrees, sampled evenly in y (closed form)."""
    y = np.linspace(-half, half, n) + root[0]
    z = root[1] - np.abs(y - root[0])
    return y.astype(np.float32), z.astype(np.float32)


def test_tracker_finds_the_root_of_a_hand_made_fillet():
    y, z = fillet_profile()
    r = vts.Tracker("fillet").track(y, z, np.ones_like(y, dtype=bool))
    assert r["status"] == "ok"
    assert abs(r["track_point"]["y"] - 1.5) < 0.05 and abs(r["track_point"]["z"] - 120.0) < 0.05
    assert abs(r["angle_deg"] - 90.0) < 0.2


def test_tracker_params_and_nan_points():
    y, z = fillet_profile()
    y[:50] = np.nan  # no valid flag given: non-finite points do not count
    r = vts.Tracker("fillet", params={"surface_tol_mm": 0.05}).track(y, z)
    assert r["valid_points"] == len(y) - 50
    # The accept range excludes 90 degrees: the reading is rejected, not bent.
    r = vts.Tracker("fillet", params={"fillet": {"angle_deg": [100, 170]}}).track(y, z)
    assert r["status"] != "ok"
    with pytest.raises(ValueError, match="surface_tol_mm"):
        vts.Tracker("fillet", params={"surface_tol_mm": -1})
    with pytest.raises(ValueError, match="joint = 'x'"):
        vts.Tracker("x")
    with pytest.raises(ValueError, match="1-D"):
        vts.Tracker().track(np.zeros((2, 3)), np.zeros((2, 3)), np.zeros((2, 3), bool))


def test_track_equals_vts_track(vts_cli, tmp_path):
    out = tmp_path / "butt.exr"
    vts_cli("scan", "--cell", "butt", "--profiles", 25, "--seed", 4, "--out", out)
    for independent in (False, True):
        args = ["track", out] + (["--independent"] if independent else [])
        cli = [json.loads(line) for line in vts_cli(*args).splitlines()]
        py = vts.track(vts.read_exr(out), independent=independent)
        assert py == cli


def test_exr_round_trip(tmp_path):
    s = vts.scan("vgroove", profiles=6, seed=2, reference=True)
    p = tmp_path / "a.exr"
    vts.write_exr(p, s)
    t = vts.read_exr(p)
    for k in ("y", "z", "range", "valid", "intensity", "true_y", "true_z", "true_valid",
              "ref_y", "ref_z", "ref_range", "ref_valid", "pose", "time"):
        np.testing.assert_array_equal(getattr(s, k), getattr(t, k), err_msg=k)
    assert t.scene_text == s.scene_text and t.seed == 2
    np.testing.assert_array_equal(s.track_point, t.track_point)


@pytest.mark.parametrize("compression", ["zip", "zips", "piz", "rle", "none"])
def test_exr_round_trip_every_compression(tmp_path, compression):
    s = vts.scan("vgroove", profiles=40, seed=3, reference=True)
    p = tmp_path / f"{compression}.exr"
    vts.write_exr(p, s, compression=compression)
    t = vts.read_exr(p)
    for k in ("y", "z", "range", "valid", "intensity", "true_y", "true_z", "true_valid",
              "ref_y", "ref_z", "ref_range", "ref_valid", "pose", "time"):
        np.testing.assert_array_equal(getattr(s, k), getattr(t, k), err_msg=k)
    with pytest.raises(ValueError, match="compression 'lzw'"):
        vts.write_exr(tmp_path / "x.exr", s, compression="lzw")


def test_exr_errors_name_the_file(tmp_path):
    with pytest.raises(ValueError, match="missing.exr"):
        vts.read_exr(tmp_path / "missing.exr")
    bad = tmp_path / "bad.exr"
    bad.write_text("not an exr")
    with pytest.raises(ValueError, match="bad.exr"):
        vts.read_exr(bad)
    s = vts.scan("fillet", profiles=2)
    s.y = s.y[:, :10]
    with pytest.raises(ValueError, match="columns|shape"):
        vts.write_exr(tmp_path / "c.exr", s)
    assert not (tmp_path / "c.exr").exists()
