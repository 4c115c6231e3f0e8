#!/usr/bin/env python3
"""Draws docs/img/joint_grooves.svg: the groove model's break points on a
filled v-groove, a single bevel, a U and a J groove (docs/JOINTS.md "Grooves
and fill"). Plain SVG, standard library only:

    python3 scripts/groove_figure.py docs/img/joint_grooves.svg
"""
import math
import sys

W, H = 320, 300  # one panel
S = 5.0          # px per mm
GREY, EDGE, BLUE, FILL = "#c8ccd4", "#555", "#1f5fbf", "#e9b949"


def arc(cx, cz, r, a0, a1, n=40):
    return [(cx + r * math.cos(a0 + (a1 - a0) * k / n), cz + r * math.sin(a0 + (a1 - a0) * k / n)) for k in range(n + 1)]


def wall(side, kind, beta, depth, gap, radius):
    """Root edge to top edge (joint frame, mm), and where the straight part starts."""
    x0 = side * gap / 2
    pts = [(x0, 0.0)]
    if kind == "square":
        return pts + [(x0, depth)], (x0, 0.0)
    t = (x0, 0.0)
    if kind == "curved":
        phi_end = math.pi / 2 - beta
        pts += [(x0 + side * radius * math.sin(p), radius - radius * math.cos(p))
                for p in (phi_end * k / 30 for k in range(1, 31))]
        t = pts[-1]
    return pts + [(t[0] + side * (depth - t[1]) * math.tan(beta), depth)], t


def level(pts, h):
    for (x0, z0), (x1, z1) in zip(pts, pts[1:]):
        if z0 <= h <= z1:
            u = (h - z0) / (z1 - z0) if z1 != z0 else 0.0
            return (x0 + u * (x1 - x0), h)
    return pts[-1]


def panel(title, a, b, depth, gap=0.0, radius=5.0, fill=None):
    """a, b: (kind, beta_deg). fill: (level, crown) or None."""
    wa, ta = wall(-1, a[0], math.radians(a[1]), depth, gap, radius)
    wb, tb = wall(+1, b[0], math.radians(b[1]), depth, gap, radius)
    if fill:
        h, crown = fill
        b2, b4 = level(wa, h), level(wb, h)
        half, xm = (b4[0] - b2[0]) / 2, (b4[0] + b2[0]) / 2
        r = (half * half + crown * crown) / (2 * crown)
        bottom = [(xm + x, h + math.sqrt(r * r - x * x) - (r - crown))
                  for x in (-half + 2 * half * k / 40 for k in range(41))]
    else:
        b2, b4 = ta, tb
        bottom = [p for p in reversed(wa) if p[1] <= ta[1]] + [p for p in wb if p[1] <= tb[1]]
    b1, b5 = wa[-1], wb[-1]
    b3 = min(bottom, key=lambda p: abs(p[0] - (b2[0] + b4[0]) / 2))
    low = min(bottom, key=lambda p: p[1])
    cx, top_y = W / 2, 70

    def px(p):
        return (cx + S * p[0], top_y + S * (depth - p[1]))

    out = []
    poly = lambda pts, **kw: out.append(
        '<polygon points="%s" %s/>' % (" ".join("%.1f,%.1f" % px(p) for p in pts),
                                       " ".join('%s="%s"' % (k.replace("_", "-"), v) for k, v in kw.items())))
    # Each plate: its top, its wall down to the root edge, the land below it.
    plate_a = [(-30, depth)] + list(reversed(wa)) + [(-gap / 2, -2.0), (-30, -2.0)]
    plate_b = [(30, depth)] + list(reversed(wb)) + [(gap / 2, -2.0), (30, -2.0)]
    poly(plate_a, fill=GREY, stroke=EDGE, stroke_width=1.2)
    poly(plate_b, fill=GREY, stroke=EDGE, stroke_width=1.2)
    if fill:
        body = [b2] + bottom[1:-1] + [b4] + [p for p in reversed(wb) if p[1] < fill[0]] + [(gap / 2, -2.0), (-gap / 2, -2.0)] + [p for p in wa if p[1] < fill[0]]
        poly(body, fill=FILL, stroke=EDGE, stroke_width=1.0)
    # The open cross-section still to fill.
    poly([b1] + [b2] + bottom[1:-1] + [b4] + [b5], fill="none", stroke="#2a8", stroke_width=1.5,
         stroke_dasharray="5,3")
    for name, p, dx, dy in (("B1", b1, -26, -8), ("B5", b5, 8, -8), ("B2", b2, -26, 4), ("B4", b4, 8, 4),
                            ("B3", b3, -8, -10)):
        x, y = px(p)
        out.append('<circle cx="%.1f" cy="%.1f" r="3.5" fill="%s"/>' % (x, y, BLUE))
        out.append('<text x="%.1f" y="%.1f" fill="%s" font-weight="bold">%s</text>' % (x + dx, y + dy, BLUE, name))
    x, y = px(low)
    out.append('<circle cx="%.1f" cy="%.1f" r="3" fill="none" stroke="#c33" stroke-width="1.5"/>' % (x, y))
    out.append('<text x="%.1f" y="%.1f" font-weight="bold">%s</text>' % (10, 22, title))
    return out


def main(path):
    panels = [
        ("v-groove, 3 beads laid", ("bevel", 30), ("bevel", 30), 28.0, 2.0, 5.0, (12.0, 0.8)),
        ("single bevel", ("square", 0), ("bevel", 40), 28.0, 1.0, 5.0, None),
        ("U groove", ("curved", 8), ("curved", 8), 28.0, 0.0, 5.0, None),
        ("J groove, 1 bead", ("square", 0), ("curved", 20), 28.0, 0.0, 6.0, (7.0, 0.5)),
    ]
    body = []
    for k, (title, a, b, depth, gap, radius, fill) in enumerate(panels):
        body.append('<g transform="translate(%d,%d)">' % ((k % 2) * W, (k // 2) * H))
        body += panel(title, a, b, depth, gap, radius, fill)
        body.append("</g>")
    legend = ('<text x="10" y="%d" font-size="12">dashed: the open cross-section (area_mm2), red ring: '
              'fill_lowest (depth_mm from the line B1-B5); yellow: beads</text>' % (2 * H + 16))
    svg = ('<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" viewBox="0 0 %d %d" '
           'font-family="sans-serif" font-size="13">\n<rect width="100%%" height="100%%" fill="white"/>\n%s\n%s\n</svg>\n'
           % (2 * W, 2 * H + 26, 2 * W, 2 * H + 26, "\n".join(body), legend))
    with open(path, "w") as f:
        f.write(svg)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/img/joint_grooves.svg")
