"""vts.scan: the same profiles as `vts scan`, geometry against closed forms and
the Embree reference, determinism."""
import numpy as np
import pytest

import vts


def test_scan_equals_the_cli_recording(vts_cli, tmp_path):
    # The package and the CLI run one pipeline: the same cell, profiles and
    # seed give the same arrays, bit for bit.
    out = tmp_path / "fillet.exr"
    vts_cli("scan", "--cell", "fillet", "--profiles", 30, "--seed", 7, "--out", out)
    cli = vts.read_exr(out)
    py = vts.scan("fillet", profiles=30, seed=7)
    for k in ("y", "z", "range", "valid", "intensity", "true_y", "true_z", "true_valid", "pose", "time"):
        np.testing.assert_array_equal(getattr(py, k), getattr(cli, k), err_msg=k)
    assert py.scanner.points == cli.scanner.points == 512
    assert py.seed == cli.seed == 7


def test_plate_seen_from_above_is_flat_at_the_standoff():
    # The built-in plate is scanned straight down its z at the path's
    # standoff: every ideal point lies on the plate's top face, one world z,
    # and the sensor-frame z equals the standoff (closed form, no tracker).
    c = vts.cell("plate")
    s = vts.scan(c, profiles=5, scanner=vts.Scanner(ideal=True))
    assert s.true_y is None  # ideal: no error model, no truth channels
    w = s.points_world()
    assert len(w) > 0.9 * 5 * 512
    assert np.ptp(w[:, 2]) < 1e-3
    z0 = s.z[s.valid]
    assert np.ptp(z0) < 1e-3
    # Column i looks along (0, t_i, 1), t_i = tan(fan/2) (2 (i + 0.5) / N - 1):
    # y = z t_i (docs/EXR_FORMAT.md).
    n = s.scanner.points
    t = np.tan(np.radians(s.scanner.fan_deg / 2)) * (2 * (np.arange(n) + 0.5) / n - 1)
    ok = s.valid[0]
    np.testing.assert_allclose(s.y[0][ok], s.z[0][ok] * t[ok], atol=2e-4)


def test_raster_agrees_with_the_embree_reference():
    s = vts.scan("vgroove", profiles=10, reference=True, scanner=vts.Scanner(ideal=True))
    both = s.valid & s.ref_valid
    assert both.sum() > 0.8 * s.valid.size
    assert np.abs(s.range[both] - s.ref_range[both]).max() < 0.01


def test_track_point_truth_against_the_tracker_on_ideal_profiles():
    # The per-profile truth (the scene's analytic joint) and the tracker
    # on ideal points agree to the tracker's ideal tolerance.
    s = vts.scan("fillet", profiles=8, seed=1)
    t = vts.Tracker("fillet")
    for r in range(len(s)):
        res = t.track(s.true_y[r], s.true_z[r], s.true_valid[r])
        assert res["status"] == "ok"
        tp = res["track_point"]
        assert np.hypot(tp["y"] - s.track_point[r, 0], tp["z"] - s.track_point[r, 1]) < 0.1


def test_seed_and_options():
    a = vts.scan("butt", profiles=4, seed=1)
    b = vts.scan("butt", profiles=4, seed=1)
    c = vts.scan("butt", profiles=4, seed=2)
    np.testing.assert_array_equal(a.z, b.z)
    assert not np.array_equal(a.z, c.z)
    wide = vts.scan("butt", profiles=2, scanner=vts.Scanner("lps-2048-short"), standoff_mm=90)
    assert wide.y.shape == (2, 2048)
    cell = vts.cell("butt")
    before = cell.path.profiles
    vts.scan(cell, profiles=3)
    assert cell.path.profiles == before  # the caller's cell is not changed


def test_bad_arguments_are_clear():
    with pytest.raises(ValueError, match="cell 'nope': unknown"):
        vts.cell("nope")
    with pytest.raises(ValueError, match="sensor 'x': unknown"):
        vts.Scanner("x")
    sc = vts.Scanner()
    sc.points = 3
    with pytest.raises(ValueError, match="points = 3"):
        vts.scan("fillet", profiles=1, scanner=sc)
    with pytest.raises(ValueError, match="source = 'gpu'"):
        vts.scan("fillet", profiles=1, source="gpu")
    with pytest.raises(ValueError, match="path.profiles = 0"):
        vts.scan("fillet", profiles=0)


def test_scene_text_round_trip():
    c = vts.cell("static-B")
    d = vts.parse_scene(c.to_yaml(), "copy")
    assert d.to_yaml() == c.to_yaml()
    assert d.joint == "fillet"
    assert abs(d.truth()["angle_deg"] - 90) < 1e-9
