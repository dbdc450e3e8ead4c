#!/usr/bin/env python3
"""Writes examples/assets/rocket.obj and rocket.mtl: a small low-poly rocket
(body, nose, three fins and a nozzle as groups with their own materials,
cylindrical texture coordinates on the body, no normals: the importer
computes them), the model the OLED firmware shows and the README's OBJ
walk-through renders. Deterministic: run it again to get the same files."""
import math, os

SIDES = 12
out = os.path.join(os.path.dirname(__file__), "..", "examples", "assets")
v, vt, faces = [], [], []  # faces: (group, [(vi, ti or None), ...])

def vert(x, y, z):
    v.append((x, y, z)); return len(v)

def tex(s, t):
    vt.append((s, t)); return len(vt)

# Body: a cylinder from y = -1 to y = 1, radius 0.35, with its own seam
# column so the texture wraps once.
rings = [(-1.0, 0.35), (-0.3, 0.38), (0.6, 0.36), (1.0, 0.3)]
body = []
for ri, (y, r) in enumerate(rings):
    row = []
    for k in range(SIDES + 1):
        a = 2 * math.pi * k / SIDES
        vi = vert(r * math.cos(a), y, -r * math.sin(a)) if k < SIDES else row[0][0]
        ti = tex(k / SIDES, 1 - ri / (len(rings) - 1))
        row.append((vi, ti))
    body.append(row)
for ri in range(len(rings) - 1):
    for k in range(SIDES):
        a, b = body[ri][k], body[ri][k + 1]
        c, d = body[ri + 1][k + 1], body[ri + 1][k]
        faces.append(("body", [a, b, c, d]))
# Nose: a cone from the top ring to the tip.
tip = vert(0.0, 1.8, 0.0)
tt = tex(0.5, 0.0)
for k in range(SIDES):
    a, b = body[-1][k], body[-1][k + 1]
    faces.append(("nose", [(a[0], None), (b[0], None), (tip, None)]))
# Nozzle: a short flared ring under the body, closed by a fan.
noz = []
for k in range(SIDES):
    a = 2 * math.pi * k / SIDES
    noz.append(vert(0.28 * math.cos(a), -1.25, -0.28 * math.sin(a)))
for k in range(SIDES):
    k1 = (k + 1) % SIDES
    faces.append(("nozzle", [(noz[k], None), (body[0][k][0], None), (body[0][k1][0], None), (noz[k1], None)]))
centre = vert(0.0, -1.25, 0.0)
for k in range(SIDES):
    faces.append(("nozzle", [(noz[(k + 1) % SIDES], None), (noz[k], None), (centre, None)]))
# Three fins: thin quads (both faces) at 0, 120 and 240 degrees.
for f in range(3):
    a = 2 * math.pi * f / 3 + math.pi / 6
    c, s = math.cos(a), -math.sin(a)
    p = lambda rr, y: vert(rr * c, y, rr * s)
    q = [p(0.34, -0.2), p(0.34, -1.0), p(0.95, -1.3), p(0.9, -0.7)]
    faces.append(("fins", [(i, None) for i in q]))
    faces.append(("fins", [(i, None) for i in reversed(q)]))

with open(os.path.join(out, "rocket.mtl"), "w", newline="\n") as m:
    m.write("# Materials of rocket.obj (scripts/make_rocket_obj.py).\n")
    for name, kd in [("hull", (0.85, 0.86, 0.9)), ("nose", (0.9, 0.25, 0.2)),
                     ("nozzle", (0.35, 0.35, 0.4)), ("fins", (0.2, 0.4, 0.9))]:
        m.write(f"newmtl {name}\nKd {kd[0]:.3f} {kd[1]:.3f} {kd[2]:.3f}\n")
with open(os.path.join(out, "rocket.obj"), "w", newline="\n") as o:
    o.write("# A low-poly rocket, written by scripts/make_rocket_obj.py.\n")
    o.write("mtllib rocket.mtl\n")
    for x, y, z in v:
        o.write(f"v {x:.5f} {y:.5f} {z:.5f}\n")
    for s_, t_ in vt:
        o.write(f"vt {s_:.5f} {t_:.5f}\n")
    group = None
    mat = {"body": "hull", "nose": "nose", "nozzle": "nozzle", "fins": "fins"}
    for g, f in faces:
        if g != group:
            o.write(f"g {g}\nusemtl {mat[g]}\n")
            group = g
        o.write("f " + " ".join(f"{vi}/{ti}" if ti else f"{vi}" for vi, ti in f) + "\n")
