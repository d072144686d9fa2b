#!/usr/bin/env python3
"""Draws docs/images/camera.svg, the camera diagram of docs/guide.md (standard library only):

    python3 docs/images/camera_svg.py > docs/images/camera.svg

Eye space as VoRANG defines it (docs/camera.md, src/scene/camera.rs): the eye at the origin, x right,
y up, looking along −z; depth d = −z. `look_at` places the eye E, the reference point R on the
viewing axis and the up vector U. `ortho_camera l r b t front back` keeps x in [l, r], y in
[b, t] and depth in [front, back]; `persp_camera fovy aspect near far` keeps the frustum of
vertical angle fovy and width/height = aspect between the depths near and far. Pixel (i, j)
counts i to the right and j downwards from the top-left corner of the image, which covers
[l, r] × [b, t] (orthographic) or the frustum's cross-section (perspective).

Three panels: the two cameras seen from the side (depth to the right, y up), and the image as
the eye sees it.
"""

import math

W, H = 940, 350
out = []


def line(a, b, cls, arrow=False):
    m = f' marker-end="url(#arrow-{cls})"' if arrow else ""
    out.append(
        f'<line class="{cls}" x1="{a[0]:.1f}" y1="{a[1]:.1f}" x2="{b[0]:.1f}" y2="{b[1]:.1f}"{m}/>'
    )


def rect(x0, y0, x1, y1, cls):
    out.append(
        f'<rect class="{cls}" x="{min(x0, x1):.1f}" y="{min(y0, y1):.1f}" width="{abs(x1 - x0):.1f}" height="{abs(y1 - y0):.1f}"/>'
    )


def text(p, s, cls, dx=0, dy=0, anchor="middle"):
    out.append(
        f'<text class="{cls}" x="{p[0] + dx:.1f}" y="{p[1] + dy:.1f}" text-anchor="{anchor}">{s}</text>'
    )


def circle(p, cls):
    out.append(f'<circle class="{cls}" cx="{p[0]:.1f}" cy="{p[1]:.1f}" r="4.5"/>')


def side_view(ox, oy, title):
    """Eye E at (ox, oy); depth to the right, y up. Returns a function (d, y) → screen."""
    S = 42.0

    def at(d, y):
        return (ox + d * S, oy - y * S)

    text((ox + 120, 34), title, "title")
    line(at(0, 0), at(6.3, 0), "axis", arrow=True)
    text(at(6.3, 0), "depth d = −z", "small", dx=0, dy=-10, anchor="end")
    line(at(0, 0), at(0, 1.3), "up", arrow=True)
    text(at(0, 1.3), "up U (y)", "up-label", dx=6, dy=4, anchor="start")
    circle(at(0, 0), "eye")
    text(at(0, 0), "eye E", "eye-label", dx=-8, dy=5, anchor="end")
    circle(at(5.2, 0), "ref")
    text(at(5.2, 0), "reference R", "ref-label", dx=0, dy=20)
    return at


def depth_tick(at, d, name):
    p = at(d, -2.05)
    line((p[0], p[1] - 5), (p[0], p[1] + 5), "tick")
    line(at(d, -2.05), at(d, -1.75), "guide")
    text(p, name, "param", dy=20)


# Panel 1: orthographic, seen from the side.
at = side_view(70, 165, "ortho_camera l r b t front back")
front, back, b, t = 1.3, 4.4, -1.3, 1.1
rect(*at(front, b), *at(back, t), "volume")
for y in (-0.9, -0.3, 0.3, 0.9):
    line(at(0.15, y), at(6.0, y), "ray")
line(at(0, -2.05), at(6.0, -2.05), "tick")
depth_tick(at, front, "front")
depth_tick(at, back, "back")
text(at(back, t), "t", "param", dx=12, dy=5)
text(at(back, b), "b", "param", dx=12, dy=5)
text(at(3.6, 1.75), "rays parallel to the axis", "small")

# Panel 2: perspective, seen from the side.
at = side_view(380, 165, "persp_camera fovy aspect near far")
fovy, near, far = 44.0, 1.5, 4.6
h = math.tan(math.radians(fovy / 2))
out.append(
    '<polygon class="volume" points="'
    + " ".join(f"{p[0]:.1f},{p[1]:.1f}" for p in [at(near, -h * near), at(far, -h * far), at(far, h * far), at(near, h * near)])
    + '"/>'
)
line(at(0, 0), at(5.4, h * 5.4), "edge")
line(at(0, 0), at(5.4, -h * 5.4), "edge")
for y in (-0.5, 0.5):
    line(at(0.15, y * 0.15 / 3), at(6.0, y * 2.0), "ray")
r = 1.05
a0, a1 = at(r * math.cos(math.radians(fovy / 2)), r * math.sin(math.radians(fovy / 2))), at(
    r * math.cos(math.radians(fovy / 2)), -r * math.sin(math.radians(fovy / 2))
)
out.append(
    f'<path class="fov" d="M {a0[0]:.1f},{a0[1]:.1f} A {r * 42:.1f} {r * 42:.1f} 0 0 1 {a1[0]:.1f},{a1[1]:.1f}"/>'
)
text(at(r, 0), "fovy", "fov-label", dx=6, dy=-8, anchor="start")
line(at(0, -2.05), at(6.0, -2.05), "tick")
depth_tick(at, near, "near")
depth_tick(at, far, "far")
text(at(2.2, -1.55), "rays from the eye", "small")

# Panel 3: the image, as the eye sees it.
x0, y0, cw, ch, ni, nj = 700.0, 92.0, 24.0, 24.0, 8, 5
text((x0 + ni * cw / 2, 34), "the image: imagesize W H", "title")
rect(x0, y0, x0 + ni * cw, y0 + nj * ch, "volume")
for i in range(1, ni):
    line((x0 + i * cw, y0), (x0 + i * cw, y0 + nj * ch), "grid")
for j in range(1, nj):
    line((x0, y0 + j * ch), (x0 + ni * cw, y0 + j * ch), "grid")
rect(x0, y0, x0 + cw, y0 + ch, "pixel0")
text((x0 + cw / 2, y0 + ch / 2), "0,0", "tiny", dy=4)
line((x0, y0 - 12), (x0 + 4 * cw, y0 - 12), "pixel", arrow=True)
text((x0 + 4 * cw, y0 - 12), "i", "pixel-label", dx=10, dy=5)
line((x0 - 34, y0), (x0 - 34, y0 + 3.2 * ch), "pixel", arrow=True)
text((x0 - 34, y0 + 3.2 * ch), "j", "pixel-label", dy=18)
text((x0, y0 + nj * ch / 2), "l", "param", dx=-12, dy=5)
text((x0 + ni * cw, y0 + nj * ch / 2), "r", "param", dx=12, dy=5)
text((x0 + ni * cw / 2, y0), "t", "param", dx=40, dy=-6)
text((x0 + ni * cw / 2, y0 + nj * ch), "b", "param", dy=18)
text((x0 + ni * cw / 2, y0 + nj * ch + 44), "x_eye from l to r, y_eye from t down to b;", "small")
text((x0 + ni * cw / 2, y0 + nj * ch + 60), "perspective: width / height = aspect", "small")
text((x0 + ni * cw / 2, y0 + nj * ch + 76), "pixel (i, j) has its centre at (i + ½, j + ½)", "small")

text(
    (W / 2, H - 16),
    "look_at ex ey ez  rx ry rz  ux uy uz: eye E, reference point R (the viewing direction), up U (made orthogonal to it)",
    "small",
)

style = """
text { font-family: DejaVu Sans, Helvetica, Arial, sans-serif; }
.title { font-size: 15px; font-weight: bold; fill: #222; }
.small { font-size: 12px; fill: #333; }
.tiny { font-size: 9px; fill: #333; }
.param { font-size: 15px; font-style: italic; fill: #1f4e9c; }
.volume { fill: #1f4e9c; fill-opacity: 0.12; stroke: #1f4e9c; stroke-width: 1.5; }
.edge { stroke: #1f4e9c; stroke-width: 1.2; }
.axis { stroke: #444; stroke-width: 1.3; }
.up { stroke: #2a8a3a; stroke-width: 2; }
.up-label { font-size: 12px; fill: #2a8a3a; }
.ray { stroke: #888; stroke-width: 1; stroke-dasharray: 3 3; }
.grid { stroke: #1f4e9c; stroke-width: 0.5; stroke-opacity: 0.5; }
.guide { stroke: #999; stroke-width: 0.8; stroke-dasharray: 2 2; }
.fov { stroke: #c05000; stroke-width: 1.5; fill: none; }
.fov-label { font-size: 14px; font-style: italic; fill: #c05000; }
.pixel { stroke: #b0007a; stroke-width: 2; }
.pixel0 { fill: #b0007a; fill-opacity: 0.25; stroke: none; }
.pixel-label { font-size: 15px; font-weight: bold; fill: #b0007a; }
.tick { stroke: #777; stroke-width: 1; }
.eye { fill: #222; }
.eye-label { font-size: 13px; fill: #222; }
.ref { fill: #fff; stroke: #c05000; stroke-width: 2; }
.ref-label { font-size: 12px; fill: #c05000; }
"""

print(f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" viewBox="0 0 {W} {H}">')
print("<defs>")
for cls, colour in [("axis", "#444"), ("up", "#2a8a3a"), ("pixel", "#b0007a")]:
    print(
        f'<marker id="arrow-{cls}" viewBox="0 0 10 10" refX="9" refY="5" markerWidth="7" markerHeight="7" orient="auto"><path d="M 0 0 L 10 5 L 0 10 z" fill="{colour}"/></marker>'
    )
print("</defs>")
print(f"<style>{style}</style>")
print(f'<rect width="{W}" height="{H}" fill="#fff"/>')
for o in out:
    print(o)
print("</svg>")
