"""Labelled profile datasets, as `vts dataset` makes them, from Python and on a
Dask cluster (docs/DATASETS.md).

A dataset is `shard_count(spec)` shards. Shard k is a pure function of
(spec, k): any process on any machine running the same vts build writes the
same bytes for it, so shards can be made in any order, by any number of
workers, and made again. A shard is complete when its record
(`shard-KKKKK.json`, written last) lists every file with the size and SHA-256
found on disk; `generate` skips complete shards (resume) and writes
`manifest.json` once every shard is complete.

    >>> import vts.dataset as ds
    >>> ds.generate("examples/dataset.yaml", "data")                 # this process
    >>> from dask.distributed import Client, LocalCluster
    >>> with Client(LocalCluster(n_workers=2, threads_per_worker=1)) as c:
    ...     ds.generate("examples/dataset.yaml", "data", client=c)   # on the cluster
"""
from __future__ import annotations

import json
import os
from typing import Any, Callable, Iterable, Mapping, Optional, Union

from . import _vts

Spec = Union[str, os.PathLike, Mapping[str, Any]]

__all__ = ["load_spec", "shard_count", "write_shard", "verified_shard", "generate"]


def load_spec(spec: Spec) -> str:
    """The spec in canonical YAML (what the manifest stores). spec: a file
    path, YAML text, or a dict with the keys of the spec file. Errors raise
    ValueError naming the file (or "<spec>"), the field and the value."""
    if isinstance(spec, Mapping):
        return _vts.dataset_canonical(json.dumps(dict(spec)), "<spec dict>")
    text = os.fspath(spec)
    if "\n" not in text and os.path.exists(text):
        with open(text, encoding="utf-8") as f:
            return _vts.dataset_canonical(f.read(), text)
    return _vts.dataset_canonical(text, "<spec>")


def shard_count(spec: Spec) -> int:
    """How many shards the spec makes."""
    return _vts.dataset_shard_count(load_spec(spec))


def write_shard(spec: Spec, k: int, out_dir: Union[str, os.PathLike]) -> dict:
    """Make shard k in out_dir (created if missing) and return its record:
    {"shard", "scenes", "profiles", "files": [{"name", "bytes", "sha256"}]}.
    The GIL is released while it scans."""
    return _vts.dataset_write_shard(load_spec(spec), int(k), os.fspath(out_dir))


def verified_shard(spec: Spec, k: int, out_dir: Union[str, os.PathLike]) -> Optional[dict]:
    """Shard k's record if the shard is complete in out_dir (every file there
    with the recorded size and SHA-256, made by this vts version from this
    spec), else None."""
    return _vts.dataset_verified_shard(load_spec(spec), int(k), os.fspath(out_dir))


def _make_shard(k: int, spec_text: str, out_dir: str) -> dict:
    # A task on a Dask worker: vts's thread pool gets the worker's threads
    # (fixed at the first scan in the process), so workers x threads = cores.
    try:
        from distributed import get_worker
        w = get_worker()
        n = w.state.nthreads if hasattr(w, "state") else w.nthreads
    except (ImportError, ValueError, AttributeError):
        n = 0
    if n:
        try:
            _vts.set_threads(int(n))
        except RuntimeError:
            pass  # already fixed by an earlier task in this process
    return _vts.dataset_write_shard(spec_text, k, out_dir)


def _files_there(record: dict, out_dir: str) -> bool:
    """Every file of a shard's record is in out_dir with the recorded size."""
    for f in record["files"]:
        try:
            if os.path.getsize(os.path.join(out_dir, f["name"])) != f["bytes"]:
                return False
        except OSError:
            return False
    return True


def generate(spec: Spec, out_dir: Union[str, os.PathLike], client: Any = None, *,
             resume: bool = True, shards: Optional[Iterable[int]] = None,
             progress: Optional[Callable[[int, int], None]] = None) -> Optional[dict]:
    """Make the dataset in out_dir and return its manifest (a dict).

    client: a dask.distributed Client: each missing shard becomes one task
      (`_make_shard`), run by whichever worker is free; without one, the
      shards are made here, one after the other. Every worker must import
      this same vts build and see out_dir (a shared directory), or write
      per-worker directories that are gathered after (docs/DATASETS.md).
    resume: skip shards already complete in out_dir (else make every one).
    shards: make only these shard numbers (e.g. one machine's share); the
      manifest is then written only if every shard is complete, and None is
      returned otherwise.
    progress: called as progress(done, total) after each shard.
    """
    text = load_spec(spec)
    out = os.fspath(out_dir)
    n = _vts.dataset_shard_count(text)
    wanted = list(range(n)) if shards is None else sorted(set(int(k) for k in shards))
    for k in wanted:
        if not 0 <= k < n:
            raise ValueError(f"shards: {k} is not a shard of this spec (0 .. {n - 1})")
    # Each shard's record, hashed once: by the check below for a shard found
    # complete, by the process that wrote it for a shard made here (its
    # files' SHA-256 read back from disk after writing), by a final check
    # for a shard neither found nor made here (another machine's share).
    records: dict = {}
    todo = []
    for k in wanted:
        r = _vts.dataset_verified_shard(text, k, out) if resume else None
        if r is None:
            todo.append(k)
        else:
            records[k] = r
    made = set(todo)
    done = len(wanted) - len(todo)
    if progress:
        progress(done, len(wanted))
    if client is None:
        for k in todo:
            records[k] = _vts.dataset_write_shard(text, k, out)
            done += 1
            if progress:
                progress(done, len(wanted))
    else:
        from distributed import as_completed

        futures = client.map(_make_shard, todo, spec_text=text, out_dir=out, pure=False)
        for f in as_completed(futures):
            r = f.result()  # a worker's exception is raised here
            records[int(r["shard"])] = r
            done += 1
            if progress:
                progress(done, len(wanted))
    for k in range(n):
        if k not in records:
            records[k] = _vts.dataset_verified_shard(text, k, out)
        elif k in made and not _files_there(records[k], out):
            records[k] = None  # written where this process cannot see it
    if any(records[k] is None for k in range(n)):
        if shards is None:
            missing = [k for k in range(n) if records[k] is None]
            raise RuntimeError(f"{out}: shards {missing} are not complete after the run")
        return None
    records = [records[k] for k in range(n)]
    _vts.dataset_write_manifest(text, records, out)
    with open(os.path.join(out, "manifest.json"), encoding="utf-8") as f:
        return json.load(f)
