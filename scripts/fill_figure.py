#!/usr/bin/env python3
"""docs/img/sim_adaptive_fill.png: vgroove-thick welded bead by bead with the
adaptive fill, the sensor biased 1 mm along its laser line, against the
model's centred fill (docs/SIM.md "Multi-pass").

    python3 scripts/fill_figure.py build/bin/vts docs/img/sim_adaptive_fill.png

Runs `vts sim --cell vgroove-thick --passes 6 --source reference --json`
twice (--fill model, and --fill-bias 1) and draws, from the JSON, the groove's
walls and each pass's fill chord (its true toes B2-B4; the cap's 0.8 mm
crown is left out) with the place each bead was laid and the model's centre.
"""
import json
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def run(vts, *extra):
    args = [vts, "sim", "--cell", "vgroove-thick", "--passes", "6", "--source", "reference",
            "--profiles", "5", "--json", *extra]
    out = subprocess.run(args, check=False, capture_output=True, text=True)
    if out.returncode not in (0, 1):
        sys.exit(f"{' '.join(args)}: exit {out.returncode}: {out.stderr}")
    return json.loads(out.stdout)


def draw(ax, run_json, title):
    passes = run_json["passes"]
    first = passes[0]
    for side in "ab":
        root, top = first[f"toe_{side}_yz_true"], first[f"top_{side}_yz_true"]
        ax.plot([root[0], top[0]], [root[1], top[1]], "k-", lw=2)
    ax.plot([first["toe_a_yz_true"][0], first["toe_b_yz_true"][0]], [0, 0], "k-", lw=2)
    for p in passes[1:]:
        a, b = p["toe_a_yz_true"], p["toe_b_yz_true"]
        ax.plot([a[0], b[0]], [a[1], b[1]], "b-", lw=1.2)
        ax.text(b[0] + 0.4, b[1], f"{p['laid']}", color="b", fontsize=8, va="center")
    for p in passes:
        if not p["next_bead_laid"]:
            continue
        a, b = p["toe_a_yz_true"], p["toe_b_yz_true"]
        z = 0.5 * (a[1] + b[1]) if p["laid"] > 0 else 0.0
        ax.plot([p["next_bead_model_y_mm"]], [z], "k+", ms=9)
        ax.plot([p["next_bead_laid_y_mm"]], [z], "rv", ms=6)
    ax.plot([], [], "b-", label="fill chord after N beads (true toes)")
    ax.plot([], [], "k+", label="model's centre for the next bead")
    ax.plot([], [], "rv", label="where the next bead was laid")
    ax.set_title(title, fontsize=10)
    ax.set_aspect("equal")
    ax.set_xlim(-16, 16)
    ax.set_ylim(-1, 27)
    ax.set_xlabel("y across the seam (mm, part frame)")
    ax.set_ylabel("z above the root (mm)")
    ax.legend(loc="upper left", fontsize=8)
    ax.grid(alpha=0.3)


def main(vts, out_png):
    model = run(vts, "--fill", "model")
    biased = run(vts, "--fill-bias", "1")
    fig, axs = plt.subplots(1, 2, figsize=(13, 6))
    draw(axs[0], model, "--fill model: beads centred, whatever the sensor said")
    draw(axs[1], biased, "adaptive fill, sensor biased 1 mm along its laser line")
    fig.suptitle("vgroove-thick, 6 beads of 4 mm (Embree reference, error model on, seed 1)")
    fig.tight_layout()
    fig.savefig(out_png, dpi=80)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
