"""The files vts writes, read by other tools (issue 20): profile EXRs through
OpenImageIO, `vts export`'s CSV through NumPy's text reader and its .npz
through numpy.load and zipfile.

Run by CTest (tests/python/CMakeLists.txt) with the interpreter CMake found,
VTS_BIN naming bin/vts and VTS_SOURCE_DIR the source tree. The truths: the
scan's own path (profile i at START + i * STEP along DIRECTION, time i / rate),
vts export's CSV for the per-point channels, and the EXR read by
OpenImageIO for the .npz.
"""

import json
import os
import subprocess
import zipfile

import numpy as np
import OpenImageIO as oiio
import pytest

VTS = os.environ["VTS_BIN"]
SOURCE = os.environ["VTS_SOURCE_DIR"]

PROFILES, POINTS = 24, 64
START, STEP = np.array([5.0, 70.0, 70.0]), 0.25  # direction +x

# name: extra `vts scan` options, error model channels?, reference channels?
VARIANTS = {
    "model": ([], True, False),
    "model-reference": (["--reference"], True, True),
    "ideal": (["--ideal", "--source", "reference"], False, False),
    "ideal-reference": (["--ideal", "--reference"], False, True),
}
POINT_CHANNELS = ["range", "y", "z", "valid"]
MODEL_CHANNELS = ["intensity", "true.y", "true.z", "true.valid"]
REF_CHANNELS = ["ref.range", "ref.y", "ref.z", "ref.valid"]
ROW_NAMES = ["pose.tx", "pose.ty", "pose.tz", "pose.qw", "pose.qx", "pose.qy", "pose.qz", "time"]


def vts(*args, cwd):
    return subprocess.run([VTS, *args], cwd=cwd, check=True, capture_output=True, text=True)


def scan(tmp_path, variant):
    extra, _, _ = VARIANTS[variant]
    vts("scan", "--cell", "fillet", "--start=5,70,70", "--direction", "1,0,0", "--step", str(STEP),
        "--profiles", str(PROFILES), "--points", str(POINTS), "--seed", "3", *extra, "--out", "s.exr",
        cwd=tmp_path)
    return tmp_path / "s.exr"


def read_exr(path):
    """Every channel of both subimages as numpy arrays, and part 0's attributes."""
    inp = oiio.ImageInput.open(str(path))
    assert inp, oiio.geterror()
    parts = []
    for sub in range(2):
        assert inp.seek_subimage(sub, 0), f"no subimage {sub}"
        spec = inp.spec()
        channels = {}
        for c, name in enumerate(spec.channelnames):
            fmt = spec.channelformat(c)
            kind = "uint" if fmt == oiio.TypeDesc("uint") else "float"
            assert kind == "float" or name.startswith("f64"), (name, fmt)
            a = inp.read_image(sub, 0, c, c + 1, kind)
            assert a is not None, oiio.geterror()
            channels[name] = a[:, :, 0]
        attributes = {a.name: a.value for a in spec.extra_attribs if a.name.startswith("vts.")}
        parts.append((spec, channels, attributes))
    assert not inp.seek_subimage(2, 0), "more than two subimages"
    inp.close()
    return parts


def exact(rows, name):
    hi = rows["f64hi." + name].ravel().astype(np.uint64)
    lo = rows["f64lo." + name].ravel().astype(np.uint64)
    return (hi << np.uint64(32) | lo).view(np.float64)


@pytest.mark.parametrize("variant", list(VARIANTS))
def test_openimageio_reads_every_channel(tmp_path, variant):
    _, model, reference = VARIANTS[variant]
    (spec, points, attrs), (row_spec, rows, row_attrs) = read_exr(scan(tmp_path, variant))

    assert spec.getattribute("oiio:subimagename") == "profiles"
    assert row_spec.getattribute("oiio:subimagename") == "rows"
    assert attrs["vts.format"] == "vts-profiles 2" and row_attrs["vts.format"] == "vts-profiles 2"
    assert (spec.width, spec.height) == (POINTS, PROFILES)
    assert (row_spec.width, row_spec.height) == (1, PROFILES)
    want = POINT_CHANNELS + (MODEL_CHANNELS if model else []) + (REF_CHANNELS if reference else [])
    assert sorted(points) == sorted(want)
    assert sorted(rows) == sorted(ROW_NAMES + ["f64hi." + n for n in ROW_NAMES] + ["f64lo." + n for n in ROW_NAMES])
    assert attrs["vts.error_model"] == ("triangulation" if model else "ideal")
    assert attrs["vts.reference"] == ("embree3-robust" if reference else "none")

    # Per point: what vts export writes as CSV (9 significant digits read
    # back to the same floats); invalid points are 0 in both.
    vts("export", "s.exr", "--out", "s.csv", cwd=tmp_path)
    csv = np.loadtxt(tmp_path / "s.csv", delimiter=",", skiprows=1)
    assert csv.shape == (PROFILES * POINTS, 4)
    np.testing.assert_array_equal(csv[:, 0].reshape(PROFILES, POINTS), np.repeat(np.arange(PROFILES), POINTS).reshape(PROFILES, POINTS))
    np.testing.assert_array_equal(points["y"], csv[:, 1].astype(np.float32).reshape(PROFILES, POINTS))
    np.testing.assert_array_equal(points["z"], csv[:, 2].astype(np.float32).reshape(PROFILES, POINTS))
    np.testing.assert_array_equal(points["valid"], csv[:, 3].reshape(PROFILES, POINTS))
    assert points["valid"].sum() > PROFILES * POINTS // 2
    for v in ("valid", "true.valid", "ref.valid"):
        if v in points:
            assert set(np.unique(points[v])) <= {0.0, 1.0}
    valid = points["valid"] == 1.0
    # A measured or ideal point lies on its column's ray: range = |(y, z)|.
    np.testing.assert_allclose(np.hypot(points["y"], points["z"])[valid], points["range"][valid], rtol=1e-6)

    # Per row: the scan's path and clock, exactly, and the FLOAT channels
    # are those doubles rounded.
    rate = float(attrs["vts.scanner.rate_hz"])
    i = np.arange(PROFILES)
    np.testing.assert_array_equal(exact(rows, "time"), i / rate)
    np.testing.assert_array_equal(exact(rows, "pose.tx"), START[0] + i * STEP)
    np.testing.assert_array_equal(exact(rows, "pose.ty"), np.full(PROFILES, START[1]))
    np.testing.assert_array_equal(exact(rows, "pose.tz"), np.full(PROFILES, START[2]))
    q = np.stack([exact(rows, n) for n in ("pose.qw", "pose.qx", "pose.qy", "pose.qz")], axis=1)
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-12)
    assert (q[:, 0] >= 0).all()
    assert (q == q[0]).all()  # the orientation is kept along the path
    for n in ROW_NAMES:
        np.testing.assert_array_equal(rows[n].ravel(), exact(rows, n).astype(np.float32))


@pytest.mark.parametrize("variant", list(VARIANTS))
def test_npz_holds_what_the_exr_holds(tmp_path, variant):
    _, model, reference = VARIANTS[variant]
    (_, points, attrs), (_, rows, _) = read_exr(scan(tmp_path, variant))
    vts("export", "s.exr", "--out", "s.npz", cwd=tmp_path)
    with zipfile.ZipFile(tmp_path / "s.npz") as z:
        assert z.testzip() is None  # every member's CRC-32
        assert all(i.compress_type == zipfile.ZIP_STORED for i in z.infolist())
    d = np.load(tmp_path / "s.npz", allow_pickle=False)
    want = ["y", "z", "range", "valid"]
    if model:
        want += ["intensity", "true_y", "true_z", "true_valid"]
    if reference:
        want += ["ref_y", "ref_z", "ref_range", "ref_valid"]
    assert d.files == want + ["pose", "time", "header"]
    for key in want:
        channel = key.replace("_", ".", 1) if key.startswith(("true_", "ref_")) else key
        a = d[key]
        assert a.shape == (PROFILES, POINTS), key
        if key.endswith("valid"):
            assert a.dtype == np.bool_
            np.testing.assert_array_equal(a, points[channel] == 1.0)
        else:
            assert a.dtype == np.float32
            np.testing.assert_array_equal(a.view(np.uint32), points[channel].view(np.uint32))
    pose = np.stack([exact(rows, n) for n in ROW_NAMES[:7]], axis=1)
    assert d["pose"].dtype == np.float64 and d["time"].dtype == np.float64
    np.testing.assert_array_equal(d["pose"].view(np.uint64), pose.view(np.uint64))
    np.testing.assert_array_equal(d["time"].view(np.uint64), exact(rows, "time").view(np.uint64))
    header = json.loads(str(d["header"]))
    assert header == {k: v for k, v in attrs.items() if k != "vts.format"}


@pytest.mark.parametrize("compression", ["zips", "piz", "rle", "none"])
def test_openimageio_reads_every_compression(tmp_path, compression):
    # vts scan --compression: OpenImageIO reads the same channels, bit for
    # bit, as from the default (zip) file, and sees the method asked for.
    (_, points, attrs), (_, rows, _) = read_exr(scan(tmp_path, "model-reference"))
    (tmp_path / "s.exr").rename(tmp_path / "zip.exr")
    extra, _, _ = VARIANTS["model-reference"]
    vts("scan", "--cell", "fillet", "--start=5,70,70", "--direction", "1,0,0", "--step", str(STEP),
        "--profiles", str(PROFILES), "--points", str(POINTS), "--seed", "3", *extra,
        "--compression", compression, "--out", "c.exr", cwd=tmp_path)
    (spec, c_points, c_attrs), (row_spec, c_rows, _) = read_exr(tmp_path / "c.exr")
    assert spec.getattribute("compression") == compression
    assert row_spec.getattribute("compression") == compression
    assert c_attrs == attrs
    for want, got in ((points, c_points), (rows, c_rows)):
        assert sorted(want) == sorted(got)
        for name in want:
            np.testing.assert_array_equal(got[name].view(np.uint32), want[name].view(np.uint32), err_msg=name)


def test_version_1_file_exports(tmp_path):
    # tests/data/profiles-v1.exr: OpenImageIO refuses its subsampled channels,
    # vts reads it and exports it.
    v1 = os.path.join(SOURCE, "tests", "data", "profiles-v1.exr")
    inp = oiio.ImageInput.open(v1)
    assert inp is None and "Subsampled channels are not supported" in oiio.geterror()
    vts("export", v1, "--out", "v1.npz", cwd=tmp_path)
    d = np.load(tmp_path / "v1.npz", allow_pickle=False)
    assert d["y"].shape == (40, 32) and d["ref_valid"].shape == (40, 32) and d["true_y"].shape == (40, 32)
    # tests/sensor/exr_fixture.h: time = 12345 + row / 299.999 + 1e-9 * row
    r = np.arange(40)
    np.testing.assert_array_equal(d["time"], 12345.0 + r / 299.999 + 1e-9 * r)
    np.testing.assert_array_equal(d["pose"][:, 0], 100.0 + r * 1.1)
    assert json.loads(str(d["header"]))["vts.scanner.name"] == "fixture scanner"
