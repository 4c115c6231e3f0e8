"""vts.dataset: shards from Python, from a Dask cluster of 2 worker processes
and from `vts dataset` are the same bytes; resume; bad specs."""
import filecmp
import json
import os

import pytest

import vts
import vts.dataset as ds

SPEC = {
    "seed": 11,
    "shards": 3,
    "scenes_per_shard": 2,
    "profiles_per_scene": 4,
    "joints": {"fillet": {"gap_mm": [0, 1.5]}, "butt": {"gap_mm": [0, 2]}, "vgroove": {"angle_deg": [50, 70]}},
    "sensors": {"mspot": {"standoff_mm": [90, 120]}},
}


def same_tree(a, b):
    names = sorted(os.listdir(a))
    assert names == sorted(os.listdir(b))
    _, mismatch, errors = filecmp.cmpfiles(a, b, names, shallow=False)
    assert not mismatch and not errors, (mismatch, errors)
    return names


@pytest.fixture(scope="module")
def local(tmp_path_factory):
    out = tmp_path_factory.mktemp("local")
    manifest = ds.generate(SPEC, out)
    return out, manifest


def test_local_run_makes_every_shard_and_a_manifest(local):
    out, manifest = local
    assert ds.shard_count(SPEC) == 3
    assert len(manifest["shards"]) == 3
    lines = [json.loads(l) for k in range(3) for l in open(out / f"shard-{k:05d}.jsonl")]
    assert len(lines) == 3 * 2 * 4
    assert {l["joint"] for l in lines} <= {"fillet", "butt", "vgroove"}
    # A label against the recording it names: the EXR row's pose is the line's.
    first = lines[0]
    scan = vts.read_exr(out / first["exr"])
    tp = first["track_point"]
    assert list(scan.track_point[first["profile"]]) == pytest.approx([tp["y"], tp["z"]], abs=1e-9)
    # ... and the same labels from the cell in the recording, through vts.Cell.profile_truth.
    truth = scan.cell.profile_truth(scan.world_from_sensor()[first["profile"]])
    assert truth["track_point"] == pytest.approx(tp, abs=1e-9)
    assert [b["name"] for b in truth["break_points"]] == [b["name"] for b in first["break_points"]]


def test_cli_writes_the_same_bytes(local, vts_cli, tmp_path):
    out, _ = local
    spec = tmp_path / "spec.yaml"
    spec.write_text(ds.load_spec(SPEC))
    vts_cli("dataset", "--spec", spec, "--out", tmp_path / "cli")
    same_tree(out, tmp_path / "cli")


def test_dask_cluster_of_two_processes_writes_the_same_bytes(local, tmp_path):
    distributed = pytest.importorskip("distributed")
    out, _ = local
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None, silence_logs=40) as cluster, \
            distributed.Client(cluster) as client:
        manifest = ds.generate(SPEC, tmp_path / "dask", client=client)
        workers = client.run(os.getpid)
    assert len(set(workers.values())) == 2
    assert len(manifest["shards"]) == 3
    same_tree(out, tmp_path / "dask")


def test_resume_remakes_only_the_damaged_shard(local, tmp_path):
    out, _ = local
    d = tmp_path / "resume"
    ds.generate(SPEC, d)
    victim = next(n for n in sorted(os.listdir(d)) if n.startswith("shard-00001-") and n.endswith(".exr"))
    with open(d / victim, "r+b") as f:
        f.seek(100)
        f.write(b"\xff")
    assert ds.verified_shard(SPEC, 1, d) is None
    keep = {n: os.stat(d / n).st_mtime_ns for n in os.listdir(d) if n.startswith(("shard-00000", "shard-00002"))}
    made = []
    ds.generate(SPEC, d, progress=lambda done, total: made.append(done))
    assert made == [2, 3]  # two found complete, one made
    assert {n: os.stat(d / n).st_mtime_ns for n in keep} == keep
    same_tree(out, d)


def test_one_machines_share(tmp_path):
    assert ds.generate(SPEC, tmp_path, shards=[0, 2]) is None  # shard 1 missing: no manifest
    assert not (tmp_path / "manifest.json").exists()
    assert ds.generate(SPEC, tmp_path, shards=[1])["shards"][1]["shard"] == 1


def test_shards_written_where_the_caller_cannot_see_them_are_not_complete(tmp_path, monkeypatch):
    # The records the writers return are taken without hashing the files again,
    # but only for files the caller finds with the recorded sizes: a worker
    # that wrote to its own disk leaves the run incomplete, and no manifest.
    elsewhere = tmp_path / "worker-disk"
    real = ds._vts.dataset_write_shard
    monkeypatch.setattr(ds._vts, "dataset_write_shard", lambda text, k, out: real(text, k, str(elsewhere)))
    with pytest.raises(RuntimeError, match=r"shards \[0, 1, 2\] are not complete"):
        ds.generate(SPEC, tmp_path / "shared")
    assert not (tmp_path / "shared" / "manifest.json").exists()


def test_bad_specs_name_the_field():
    with pytest.raises(ValueError, match=r"joints\.butt\.gap_mm.*min must not exceed max"):
        ds.load_spec({**SPEC, "joints": {"butt": {"gap_mm": [2, 0.5]}}})
    with pytest.raises(ValueError, match="shards"):
        ds.load_spec({**SPEC, "shards": 0})
    with pytest.raises(ValueError, match="not a shard"):
        ds.generate(SPEC, "unused", shards=[7])
