"""vts: a virtual laser-triangulation seam sensor, from Python.

Scan a built-in cell or a scene file with an emulated laser profile scanner,
get the profiles as numpy arrays with their ground truth, track the seam in
them, and read and write vts profile EXR files. Every call runs the same C++
library as the ``vts`` command line (docs/PYTHON.md).

Units: lengths in mm, angles in degrees, times in s. Profiles are in the
sensor frame: z along the optical axis (range), y along the laser line.

    >>> import vts
    >>> cell = vts.cell("fillet")
    >>> scan = vts.scan(cell, profiles=50, seed=1)
    >>> scan.y.shape
    (50, 512)
    >>> vts.Tracker("fillet").track(scan.y[0], scan.z[0], scan.valid[0])["status"]
    'ok'
"""
from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from typing import Any, Mapping, Optional, Union

import numpy as np

from . import _vts
from ._vts import (  # noqa: F401  (re-exported)
    Cell,
    ExrError,
    ParamsError,
    SceneError,
    ScanPath,
    Scanner,
    TrackInputError,
    cell,
    cell_description,
    cells,
    load_scene,
    material_description,
    scenarios,
    materials,
    parse_scene,
    sensor_description,
    sensors,
    set_threads,
    threads,
)

__version__ = _vts.__version__

__all__ = [
    "Cell", "Scan", "ScanPath", "Scanner", "Tracker", "cell", "cells", "load_scene",
    "parse_scene", "read_exr", "scan", "sensors", "materials", "set_threads", "track",
    "write_exr", "ExrError", "ParamsError", "SceneError", "TrackInputError",
]

_PER_POINT = ("y", "z", "range", "valid", "intensity", "true_y", "true_z", "true_valid",
              "ref_y", "ref_z", "ref_range", "ref_valid")


@dataclass
class Scan:
    """Profiles of one recording: P profiles of N points, as numpy arrays.

    Per point, shape (P, N), sensor frame:
      y, z, range: float32, mm (0 where not valid); valid: bool.
      intensity (0..1), true_y, true_z (mm), true_valid: the error model's
        output and the ideal geometric point of each column (ground truth);
        None when the scan is ideal (no error model).
      ref_y, ref_z, ref_range, ref_valid: the Embree ray-cast reference at the
        same poses; None unless scanned with reference=True.
    Per profile:
      pose: float64 (P, 7): world_from_sensor as tx, ty, tz (mm, world) and a
        unit quaternion qw, qx, qy, qz (qw >= 0).
      time: float64 (P,), s.
      track_point: float64 (P, 2): the joint's true track point (y, z) in each
        profile, mm (NaN when the scene has no joint or the file did not say).
    scanner: the Scanner; scene_name, scene_text (YAML); seed.
    """

    y: np.ndarray
    z: np.ndarray
    range: np.ndarray
    valid: np.ndarray
    pose: np.ndarray
    time: np.ndarray
    scanner: Scanner
    scene_name: str = ""
    scene_text: str = ""
    seed: int = 0
    intensity: Optional[np.ndarray] = None
    true_y: Optional[np.ndarray] = None
    true_z: Optional[np.ndarray] = None
    true_valid: Optional[np.ndarray] = None
    ref_y: Optional[np.ndarray] = None
    ref_z: Optional[np.ndarray] = None
    ref_range: Optional[np.ndarray] = None
    ref_valid: Optional[np.ndarray] = None
    track_point: Optional[np.ndarray] = field(default=None, repr=False)

    def __len__(self) -> int:
        return self.y.shape[0]

    def __repr__(self) -> str:
        p, n = self.y.shape
        extra = []
        if self.true_y is not None:
            extra.append("truth")
        if self.ref_y is not None:
            extra.append("reference")
        return (f"<vts.Scan {p} profiles x {n} points of {self.scene_name!r}"
                f"{', ' + ', '.join(extra) if extra else ''}>")

    @property
    def points(self) -> np.ndarray:
        """(P, N, 2) float32: y, z per point, sensor frame, mm (a new array)."""
        return np.stack([self.y, self.z], axis=-1)

    @property
    def cell(self) -> Cell:
        """The scene the profiles were taken of, parsed from scene_text."""
        return parse_scene(self.scene_text, self.scene_name)

    def world_from_sensor(self) -> np.ndarray:
        """(P, 4, 4) float64: each profile's pose as a homogeneous matrix."""
        return _matrices(self.pose)

    def points_world(self, i: Optional[int] = None) -> np.ndarray:
        """Valid points in the world frame, mm: (M, 3) for profile i, or for
        all profiles (M, 4) with the profile index in the last column."""
        mats = self.world_from_sensor()
        rows = range(len(self)) if i is None else [i]
        out = []
        for r in rows:
            ok = self.valid[r]
            local = np.stack([np.zeros(ok.sum()), self.y[r][ok], self.z[r][ok]], axis=1)
            world = local @ mats[r, :3, :3].T + mats[r, :3, 3]
            if i is None:
                world = np.concatenate([world, np.full((len(world), 1), r)], axis=1)
            out.append(world)
        return out[0] if i is not None else np.concatenate(out, axis=0)

    def arrays(self) -> dict:
        """Every array and the header as one dict (what write_exr stores)."""
        d = {k: getattr(self, k) for k in _PER_POINT if getattr(self, k) is not None}
        d.update(pose=self.pose, time=self.time, scanner=self.scanner,
                 scene_name=self.scene_name, scene_text=self.scene_text, seed=self.seed)
        return d


def _matrices(pose: np.ndarray) -> np.ndarray:
    t, (w, x, y, z) = pose[:, :3], pose[:, 3:].T
    m = np.zeros((len(pose), 4, 4))
    m[:, 0, 0] = 1 - 2 * (y * y + z * z)
    m[:, 0, 1] = 2 * (x * y - z * w)
    m[:, 0, 2] = 2 * (x * z + y * w)
    m[:, 1, 0] = 2 * (x * y + z * w)
    m[:, 1, 1] = 1 - 2 * (x * x + z * z)
    m[:, 1, 2] = 2 * (y * z - x * w)
    m[:, 2, 0] = 2 * (x * z - y * w)
    m[:, 2, 1] = 2 * (y * z + x * w)
    m[:, 2, 2] = 1 - 2 * (x * x + y * y)
    m[:, :3, 3] = t
    m[:, 3, 3] = 1
    return m


def _scan_of(d: dict, cell: Optional[Cell] = None) -> Scan:
    """A Scan of the arrays; its track points from `cell` (the cell scanned),
    else from the recording's scene text."""
    s = Scan(**d)
    c = cell
    if c is None:
        try:
            c = parse_scene(s.scene_text, s.scene_name) if s.scene_text else None
        except (SceneError, ValueError, RuntimeError):
            c = None  # e.g. a mesh file that is not where the recording says
    tp = np.full((len(s), 2), np.nan)
    if c is not None and c.joint is not None:
        for r, m in enumerate(_matrices(s.pose)):
            tp[r] = c.track_point(m)
    s.track_point = tp
    return s


def scan(cell: Union[Cell, str], *, profiles: Optional[int] = None, seed: int = 0,
         scanner: Optional[Scanner] = None, standoff_mm: Optional[float] = None,
         source: str = "raster", reference: bool = False, batch: int = 512) -> Scan:
    """Scan a cell along its path and return the profiles.

    cell: a Cell, or the name of a built-in cell (vts.cells()).
    profiles: number of profiles (default: the cell's path).
    seed: the error model's random draws (same seed, same profiles).
    scanner: replaces the cell's scanner (e.g. vts.Scanner("lps-2048-short")).
    standoff_mm: re-derive the path at this distance from the seam root, mm.
    source: "raster" (the OpenGL emulator) or "reference" (Embree ray caster).
    reference: also scan with the Embree reference beside the raster source.
    batch: profiles per batch (memory of the job, not of the result).

    The GIL is released while scanning; Ctrl-C stops the scan between batches.
    The arrays are filled as the profiles are made (one copy).
    """
    c = _vts.cell(cell) if isinstance(cell, str) else cell.copy()  # the caller's cell stays as it was
    if scanner is not None:
        c.scanner = scanner
    if standoff_mm is not None:
        c.look_from(standoff_mm)
    if profiles is not None:
        c.path.profiles = int(profiles)
    return _scan_of(_vts._scan(c, int(seed), source, bool(reference), int(batch)), c)


def read_exr(path: Union[str, os.PathLike]) -> Scan:
    """Read a vts profile EXR (any format version) into a Scan."""
    return _scan_of(_vts._read_exr(os.fspath(path)))


def write_exr(path: Union[str, os.PathLike], scan: Scan, compression: str = "zip") -> None:
    """Write a Scan to a vts profile EXR (written whole under a temporary name,
    then renamed). The truth channels are written when scan.true_y is set, the
    reference when scan.ref_y is set. compression: "zip" (default), "zips",
    "piz", "rle" or "none", all lossless (docs/EXR_FORMAT.md)."""
    _vts._write_exr(os.fspath(path), scan.arrays(), str(compression))


def _params_text(params: Union[None, str, os.PathLike, Mapping[str, Any]]) -> tuple[str, str]:
    if params is None:
        return "", "<params>"
    if isinstance(params, Mapping):
        return json.dumps(params), "<params dict>"  # JSON is YAML
    text = os.fspath(params)
    if "\n" not in text and os.path.exists(text):
        with open(text, encoding="utf-8") as f:
            return f.read(), text
    return text, "<params>"


class Tracker:
    """The seam tracker (tracker/ in C++), on one profile at a time.

    Tracker(joint="fillet", params=None): joint is fillet, corner, lap, butt,
    vgroove, bevel, ugroove or jgroove; params overrides the defaults as a
    nested dict, YAML text or a YAML file path with the keys of `vts track
    --params` (docs/CLI.md), e.g. {"surface_tol_mm": 0.05,
    "fillet": {"gap_mm": [0, 3]}}.

    track(y, z, valid) returns the result as `vts track` prints it (a dict:
    status, confidence, track_point [y, z] mm, break points, gap_mm,
    angle_deg, ...; docs/JOINTS.md).
    """

    def __init__(self, joint: Optional[str] = None,
                 params: Union[None, str, os.PathLike, Mapping[str, Any]] = None):
        text, name = _params_text(params)
        self._t = _vts._Tracker(joint or "", text, name)

    @property
    def joint(self) -> str:
        return self._t.joint

    def track(self, y, z, valid=None) -> dict:
        """Track one profile: y, z (mm, sensor frame) and valid, 1-D of one length.
        Without valid, the points with finite y and z count."""
        y = np.asarray(y, dtype=np.float32)
        z = np.asarray(z, dtype=np.float32)
        if valid is None:
            valid = np.isfinite(y) & np.isfinite(z)
            y, z = np.where(valid, y, 0), np.where(valid, z, 0)
        return self._t.track(y, z, np.asarray(valid, dtype=bool))


def track(scan: Scan, joint: Optional[str] = None,
          params: Union[None, str, os.PathLike, Mapping[str, Any]] = None,
          independent: bool = False, truth: bool = False) -> list:
    """Track every profile of a Scan as `vts track` does: a list with one dict
    per profile. By default as a sequence along one seam (each profile searched
    near where the last ones predict, docs/JOINTS.md); independent=True tracks
    each profile alone. joint: default the scene's joint, else fillet.
    truth=True tracks the ideal points (true_y, true_z) instead."""
    if joint is None:
        try:
            joint = scan.cell.joint
        except (SceneError, ValueError, RuntimeError):
            joint = None
    d = scan.arrays()
    if truth:
        if scan.true_y is None:
            raise ValueError("truth=True: the scan has no truth (it was scanned ideal)")
        d.update(y=scan.true_y, z=scan.true_z, valid=scan.true_valid)
        d.pop("range", None)
    text, name = _params_text(params)
    return _vts._track_recording(d, joint or "", text, name, bool(independent))


def sim(scenario: Union[None, str, os.PathLike] = None, **spec: Any) -> dict:
    """Run `vts sim`'s closed loop (and the same program open loop) in process.

    scenario: a built-in scenario's name (vts.scenarios()) or a scenario
    file's path (docs/SIM.md "Scenarios"); or None and the scenario's keys
    as keyword arguments, e.g. vts.sim(robot="kr16", robot_seed=3,
    seam1_bow_mm=4, weave_amplitude_mm=2) (the default: the box displaced
    by seed 1, a perfect robot, the Embree reference source).

    Returns the summary of `vts sim --scenario --json` as a dict (per seam:
    errors in mm, the open loop's beside them; the verdict and its reason)
    and per master cycle numpy arrays: time_s, seam_index (0-based, -1 after
    the last), phase (list of str), tcp_mm and commanded_mm (N x 3, world,
    mm: where the TCP really was and where the master sent it),
    lateral_error_mm and vertical_error_mm (of the weld path's centre from
    the true seam; NaN when not welding). Raises ValueError for an unknown
    scenario or a bad key or value. The GIL is released while it runs.
    """
    if scenario is not None and spec:
        raise ValueError("give a scenario or its keys, not both")
    if scenario is not None:
        text = str(scenario)
        if os.sep in text or text.endswith(".yaml"):
            with open(text, encoding="utf-8") as f:
                return _vts._sim("", f.read(), text)
        return _vts._sim(text, "", "")
    yaml = "".join(f"{k}: {json.dumps(v)}\n" for k, v in spec.items())
    return _vts._sim("", yaml or "{}\n", "<vts.sim>")
