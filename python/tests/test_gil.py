"""The GIL is released while vts scans (a file of its own: the thread limit
is set once per process, before the first scan)."""
import threading
import time

import vts

vts.set_threads(1)  # leave a core for the main thread's loop


def test_scanning_releases_the_gil():
    # While one thread scans, the main thread keeps running: the longest
    # pause of its loop stays far below the scan's duration (holding the GIL,
    # the pause would be the whole scan).
    cell = vts.cell("fillet")
    cell.path.profiles = 4000
    done = {}

    def work():
        t0 = time.perf_counter()
        vts.scan(cell, seed=3)
        done["s"] = time.perf_counter() - t0

    th = threading.Thread(target=work)
    last, gap = time.perf_counter(), 0.0
    th.start()
    while th.is_alive():
        now = time.perf_counter()
        gap, last = max(gap, now - last), now
    th.join()
    assert vts.threads() == 1
    assert done["s"] > 0.05
    assert gap < 0.5 * done["s"], (gap, done["s"])
