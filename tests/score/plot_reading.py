#!/usr/bin/env python3
"""Plots a profile dumped by `vts-score-corpus --dump JOINT SEED LEVEL PREFIX`:
points (kept colours per segment), the truth's and the reading's track and
break points. Usage: plot_reading.py PREFIX [--zoom MM] [--out PNG]"""
import argparse, csv
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

ap = argparse.ArgumentParser()
ap.add_argument("prefix")
ap.add_argument("--zoom", type=float, default=0.0, help="half width of a view around the truth (mm)")
ap.add_argument("--out", default=None)
a = ap.parse_args()
rows = list(csv.DictReader(open(a.prefix + ".csv")))
info = {}
bps, tbps, segs = [], [], []
for line in open(a.prefix + ".txt"):
    k, _, v = line.rstrip("\n").partition(" ")
    if k == "bp": n, y, z = v.split(); bps.append((n, float(y), float(z)))
    elif k == "truth_bp": n, y, z = v.split(); tbps.append((n, float(y), float(z)))
    elif k == "segment": segs.append([float(x) for x in v.split()])
    else: info[k] = v
fig, ax = plt.subplots(figsize=(11, 6))
ys = [float(r["y"]) for r in rows]; zs = [float(r["z"]) for r in rows]; ok = [r["valid"] == "1" for r in rows]
col_seg = {}
for si, s in enumerate(segs):
    for c in range(int(s[0]), int(s[1]) + 1): col_seg[c] = si
for i in range(len(rows)):
    if not ok[i]: continue
    si = col_seg.get(i)
    ax.plot(ys[i], zs[i], ".", ms=3, color=("k" if si is None else plt.cm.tab10(si % 10)))
ty, tz = map(float, info["truth"].split())
ax.plot(ty, tz, "g+", ms=18, mew=2, label="truth")
for n, y, z in tbps: ax.plot(y, z, "gx", ms=8); ax.annotate(n, (y, z), color="g", fontsize=8)
if "track" in info:
    y, z = map(float, info["track"].split()); ax.plot(y, z, "r+", ms=18, mew=2, label="reading")
if "rival" in info:
    y, z, _ = map(float, info["rival"].split()); ax.plot(y, z, "m+", ms=14, mew=2, label="rival")
for n, y, z in bps: ax.plot(y, z, "rx", ms=7); ax.annotate(n, (y, z), color="r", fontsize=8)
ax.invert_yaxis(); ax.set_aspect("equal"); ax.set_xlabel("y (mm)"); ax.set_ylabel("z (mm)")
if a.zoom > 0: ax.set_xlim(ty - a.zoom, ty + a.zoom); ax.set_ylim(tz + a.zoom * 0.6, tz - a.zoom * 0.6)
ax.set_title(f"{a.prefix}: {info.get('status')} {info.get('reason', '')}\n{info.get('tags', '')}", fontsize=8)
ax.legend(fontsize=8)
fig.savefig(a.out or a.prefix + ".png", dpi=110, bbox_inches="tight")
