#!/usr/bin/env python3
"""docs/img/sim_thermal_gap_profiles.png: the profiles of the thermal-gap
scenario against the same run without the lift (docs/SIM.md).

    build/bin/vts sim --scenario thermal-gap --out-dir /tmp/tg
    sed 's/distortion_lift_deg_per_100mm: 1.0/distortion_lift_deg_per_100mm: 0/' \\
        examples/scenarios/thermal-gap.yaml > /tmp/rigid.yaml
    build/bin/vts sim --scenario /tmp/rigid.yaml --out-dir /tmp/rigid
    build/bin/vts export /tmp/tg/profiles.exr --out /tmp/tg/p.npz
    build/bin/vts export /tmp/rigid/profiles.exr --out /tmp/rigid/p.npz
    python3 scripts/thermal_gap_figure.py /tmp/tg/p.npz /tmp/rigid/p.npz docs/img/sim_thermal_gap_profiles.png
"""
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(lifted_npz, rigid_npz, out_png):
    lifted, rigid = np.load(lifted_npz), np.load(rigid_npz)
    t = lifted["time"]
    fig, axs = plt.subplots(1, 3, figsize=(15, 5))
    for ax, when in zip(axs, [6.0, 10.0, 14.0]):
        i = int(np.argmin(abs(t - when)))
        for d, label, style, key in [(rigid, "no lift (ideal)", "k.-", "true_"),
                                     (lifted, "lift 1 deg / 100 mm (ideal)", "r.-", "true_"),
                                     (lifted, "lift, measured", "b.", "")]:
            v = d[key + "valid"][i].astype(bool)
            ax.plot(d[key + "y"][i][v], d[key + "z"][i][v], style, ms=3, label=label)
        ax.set_title(f"seam 1, profile {i} at t = {t[i]:.1f} s")
        ax.set_xlim(-2.5, 2.5)
        ax.set_ylim(102.0, 97.5)
        ax.set_xlabel("y (mm, sensor frame)")
        ax.set_ylabel("z (mm)")
        ax.legend(loc="lower left")
    fig.suptitle("thermal-gap: the wall lifting off the plate 50 mm ahead of the arc")
    fig.tight_layout()
    fig.savefig(out_png, dpi=80)


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(*sys.argv[1:])
