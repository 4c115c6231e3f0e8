#!/usr/bin/env python3
"""Plots corpus profiles with their truth, for looking at them.

  vts-corpus --joint butt --count 5 --csv b.csv --truth b.jsonl --scene b.scene.jsonl
  plot_corpus.py b.csv b.jsonl [--scene b.scene.jsonl] [--profiles 0,3] --out DIR

Each PNG: the whole profile (left) and +-zoom mm around the track point
(right); z grows downwards (away from the sensor), as the work is seen.
"""
import argparse
import csv
import json
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_profiles(path):
    profiles = {}
    with open(path) as f:
        for row in csv.DictReader(f):
            k = int(row["profile"])
            p = profiles.setdefault(k, {"y": [], "z": [], "valid": []})
            p["y"].append(float(row["y"]))
            p["z"].append(float(row["z"]))
            p["valid"].append(row["valid"] == "1")
    return profiles


def read_jsonl(path):
    with open(path) as f:
        return {o["profile"]: o for o in map(json.loads, f)}


def draw(ax, prof, truth, scene, zoom):
    ty, tz = truth["track_point"]["y"], truth["track_point"]["z"]
    if scene:
        for y0, z0, y1, z1, face in scene["edges"]:
            ax.plot([y0, y1], [z0, z1], color="0.8", lw=0.8, zorder=1)
    ys = [y for y, v in zip(prof["y"], prof["valid"]) if v]
    zs = [z for z, v in zip(prof["z"], prof["valid"]) if v]
    ax.plot(ys, zs, ".", ms=2.0 if not zoom else 3.5, color="tab:blue", zorder=2)
    for name, p in truth["break_points"].items():
        if p is None:
            continue
        ax.plot(p["y"], p["z"], "x", color="tab:red", ms=8, zorder=3)
        ax.annotate(name, (p["y"], p["z"]), textcoords="offset points", xytext=(4, 4), color="tab:red", fontsize=8)
    ax.plot(ty, tz, "o", mfc="none", mec="tab:green", ms=12, mew=1.5, zorder=4)
    if truth.get("decoy_point"):
        d = truth["decoy_point"]
        ax.plot(d["y"], d["z"], "s", mfc="none", mec="tab:purple", ms=10, zorder=4)
    if zoom:
        ax.set_xlim(ty - zoom, ty + zoom)
        ax.set_ylim(tz + zoom, tz - zoom)
    else:
        if ys:
            ax.set_xlim(min(ys) - 5, max(ys) + 5)
            ax.set_ylim(max(zs) + 5, min(zs) - 5)
    ax.set_aspect("equal")
    ax.set_xlabel("y [mm]")
    ax.set_ylabel("z [mm]")
    ax.grid(True, lw=0.3)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("truth")
    ap.add_argument("--scene")
    ap.add_argument("--profiles", default="")
    ap.add_argument("--zoom", type=float, default=10.0)
    ap.add_argument("--out", default=".")
    a = ap.parse_args()
    profiles = read_profiles(a.csv)
    truths = read_jsonl(a.truth)
    scenes = read_jsonl(a.scene) if a.scene else {}
    ks = [int(k) for k in a.profiles.split(",") if k] or sorted(profiles)
    os.makedirs(a.out, exist_ok=True)
    for k in ks:
        t = truths[k]
        fig, axes = plt.subplots(1, 2, figsize=(15, 6.5))
        draw(axes[0], profiles[k], t, scenes.get(k), 0)
        draw(axes[1], profiles[k], t, scenes.get(k), a.zoom)
        vals = ", ".join(
            f"{n}={t[n]:.3g}" for n in ("gap_mm", "mismatch_mm", "angle_deg", "step_mm", "depth_mm") if t[n] is not None
        )
        fig.suptitle(
            f"{t['joint']} profile {k} seed {t['seed']}: {t['columns']} columns, standoff {t['standoff_mm']:.0f} mm, "
            f"noise {t['noise_mm']} mm; {vals}\n" + " ".join(t["tags"]),
            fontsize=9,
        )
        fig.tight_layout()
        name = os.path.join(a.out, f"{t['joint']}_{k:04d}.png")
        fig.savefig(name, dpi=80)
        plt.close(fig)
        print(name)


if __name__ == "__main__":
    main()
