#!/usr/bin/env python3
"""Writes the hand-made animated glTF files of this folder, their statically posed twins
(tests/fixtures/anim/*_static_*.gltf: the same scenes with every node, morph weight and
skinned vertex posed at one time in closed form, without animation) and the bad-input
fixtures (tests/fixtures/anim/bad_*.gltf).

    python3 assets/gltf/animated/make.py

Standard library only. The poses here are written from the formulas (Hermite, slerp of a
single-axis rotation as a linear angle, linear blend skinning), not from raygraph's code.
"""
import base64
import json
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
FIXTURES = os.path.join(HERE, "..", "..", "..", "tests", "fixtures", "anim")


class Doc:
    def __init__(self):
        self.bin = bytearray()
        self.j = {
            "asset": {"version": "2.0", "generator": "raygraph assets/gltf/animated/make.py"},
            "scene": 0,
            "scenes": [{"nodes": []}],
            "nodes": [],
            "meshes": [],
            "materials": [
                {"name": "ground", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0, "roughnessFactor": 0.9}},
                {"name": "orange", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.45, 0.15, 1], "metallicFactor": 0, "roughnessFactor": 0.6}},
                {"name": "blue", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.35, 0.85, 1], "metallicFactor": 0, "roughnessFactor": 0.5}},
            ],
            "accessors": [],
            "bufferViews": [],
            "buffers": [],
        }

    def accessor(self, fmt, comps, values, acc_type, minmax=False, component=5126):
        while len(self.bin) % 4:
            self.bin.append(0)
        offset = len(self.bin)
        flat = [x for v in values for x in (v if isinstance(v, (list, tuple)) else [v])]
        self.bin += struct.pack("<%d%s" % (len(flat), fmt), *flat)
        self.j["bufferViews"].append({"buffer": 0, "byteOffset": offset, "byteLength": len(self.bin) - offset})
        acc = {"bufferView": len(self.j["bufferViews"]) - 1, "componentType": component, "count": len(values), "type": acc_type}
        if minmax:
            acc["min"] = [min(v[i] for v in values) for i in range(comps)]
            acc["max"] = [max(v[i] for v in values) for i in range(comps)]
        self.j["accessors"].append(acc)
        return len(self.j["accessors"]) - 1

    def mesh(self, name, positions, normals, indices, material, targets=None, weights=None, joints=None, skin_weights=None):
        attrs = {
            "POSITION": self.accessor("f", 3, positions, "VEC3", minmax=True),
            "NORMAL": self.accessor("f", 3, normals, "VEC3"),
        }
        if joints is not None:
            attrs["JOINTS_0"] = self.accessor("H", 4, joints, "VEC4", component=5123)
            attrs["WEIGHTS_0"] = self.accessor("f", 4, skin_weights, "VEC4")
        prim = {"attributes": attrs, "indices": self.accessor("I", 1, indices, "SCALAR", component=5125), "material": material}
        if targets:
            prim["targets"] = [{"POSITION": self.accessor("f", 3, t, "VEC3", minmax=True)} for t in targets]
        m = {"name": name, "primitives": [prim]}
        if weights is not None:
            m["weights"] = weights
        self.j["meshes"].append(m)
        return len(self.j["meshes"]) - 1

    def node(self, root=True, **kw):
        self.j["nodes"].append(kw)
        if root:
            self.j["scenes"][0]["nodes"].append(len(self.j["nodes"]) - 1)
        return len(self.j["nodes"]) - 1

    def channel(self, anim, node, path, times, values, interpolation="LINEAR", acc_type="VEC3"):
        a = self.j.setdefault("animations", [])
        while len(a) <= anim[0]:
            a.append({"name": anim[1], "channels": [], "samplers": []})
        clip = a[anim[0]]
        inp = self.accessor("f", 1, times, "SCALAR", minmax=False)
        self.j["accessors"][inp]["min"] = [min(times)]
        self.j["accessors"][inp]["max"] = [max(times)]
        out = self.accessor("f", 1, values, acc_type)
        clip["samplers"].append({"input": inp, "output": out, "interpolation": interpolation})
        clip["channels"].append({"sampler": len(clip["samplers"]) - 1, "target": {"node": node, "path": path}})

    def write(self, path):
        self.j["buffers"] = [{"byteLength": len(self.bin), "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(self.bin)).decode()}]
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as f:
            json.dump(self.j, f, indent=1)
            f.write("\n")


def look_at(eye, target):
    """The rotation (x, y, z, w) of a glTF camera at `eye` looking at `target` (cameras look
    down their -Z with +Y up)."""
    f = [t - e for t, e in zip(target, eye)]
    n = math.sqrt(sum(c * c for c in f))
    b = [-c / n for c in f]  # the camera's +Z
    r = [b[2], 0.0, -b[0]]  # up x back
    n = math.sqrt(sum(c * c for c in r))
    r = [c / n for c in r]
    u = [b[1] * r[2] - b[2] * r[1], b[2] * r[0] - b[0] * r[2], b[0] * r[1] - b[1] * r[0]]
    m = [[r[0], u[0], b[0]], [r[1], u[1], b[1]], [r[2], u[2], b[2]]]
    w = math.sqrt(max(0.0, 1 + m[0][0] + m[1][1] + m[2][2])) / 2
    return [(m[2][1] - m[1][2]) / (4 * w), (m[0][2] - m[2][0]) / (4 * w), (m[1][0] - m[0][1]) / (4 * w), w]


def camera(doc, eye, target):
    doc.j["cameras"] = [{"type": "perspective", "perspective": {"yfov": math.radians(45), "znear": 0.05, "zfar": 100}}]
    doc.node(name="view", camera=0, translation=eye, rotation=look_at(eye, target))


def ground(doc):
    s = 5.0
    p = [(-s, 0, -s), (s, 0, -s), (s, 0, s), (-s, 0, s)]
    m = doc.mesh("ground", p, [(0, 1, 0)] * 4, [0, 2, 1, 0, 3, 2], 0)
    doc.node(name="ground", mesh=m)


def box(h=0.5):
    """A cube of half-size h with per-face normals: positions, normals, indices."""
    p, n, i = [], [], []
    for axis in range(3):
        for sign in (-1, 1):
            normal = [0, 0, 0]
            normal[axis] = sign
            u, v = [(axis + 1) % 3, (axis + 2) % 3]
            base = len(p)
            for a, b in [(-1, -1), (1, -1), (1, 1), (-1, 1)]:
                q = [0, 0, 0]
                q[axis] = sign * h
                q[u] = a * h
                q[v] = b * h
                p.append(tuple(q))
                n.append(tuple(normal))
            quad = [base, base + 1, base + 2, base, base + 2, base + 3]
            if sign < 0:
                quad = [base, base + 2, base + 1, base, base + 3, base + 2]
            i += quad
    return p, n, i


def hermite(v0, out0, in1, v1, s, dt):
    h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
    h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
    return [h00 * a + h10 * dt * b + h01 * c + h11 * dt * d for a, b, c, d in zip(v0, out0, v1, in1)]


def lerp_keys(times, values, t):
    if t <= times[0]:
        return values[0]
    for k in range(len(times) - 1):
        if times[k] <= t <= times[k + 1]:
            s = (t - times[k]) / (times[k + 1] - times[k])
            return [a + (b - a) * s for a, b in zip(values[k], values[k + 1])]
    return values[-1]


def quat_y(deg):
    r = math.radians(deg) / 2
    return [0.0, math.sin(r), 0.0, math.cos(r)]


def quat_z(deg):
    r = math.radians(deg) / 2
    return [0.0, 0.0, math.sin(r), math.cos(r)]


# --- spinner: a box that turns about Y and moves, with a child whose scale is a cubic spline.
SPIN_TIMES = [0.0, 0.5, 1.0, 1.5, 2.0]
SPIN_DEG = [0, 90, 180, 270, 360]
MOVE_TIMES = [0.0, 1.0, 2.0]
MOVE = [[0, 1, 0], [2, 1.5, 0], [0, 1, 0]]
MOON_SCALE = ([0.3] * 3, [0.2] * 3, [-0.1] * 3, [0.6] * 3)  # v0, out-tangent 0, in-tangent 1, v1 over [0, 2]


def spinner(t=None):
    doc = Doc()
    ground(doc)
    camera(doc, [2.5, 4.0, 7.0], [0.8, 1.0, 0.0])
    p, n, i = box()
    m = doc.mesh("box", p, n, i, 1)
    moon_mesh = doc.mesh("moon", p, n, i, 2)
    if t is None:
        spin = doc.node(name="spinner", mesh=m, translation=MOVE[0], children=[])
        moon = doc.node(root=False, name="moon", mesh=moon_mesh, translation=[1.5, 0, 0], scale=MOON_SCALE[0])
        doc.j["nodes"][spin]["children"].append(moon)
        clip = (0, "spin")
        doc.channel(clip, spin, "rotation", SPIN_TIMES, [quat_y(d) for d in SPIN_DEG], acc_type="VEC4")
        doc.channel(clip, spin, "translation", MOVE_TIMES, MOVE)
        v0, out0, in1, v1 = MOON_SCALE
        doc.channel(clip, moon, "scale", [0.0, 2.0], [[0, 0, 0], v0, out0, in1, v1, [0, 0, 0]], interpolation="CUBICSPLINE")
        # A second clip, to select by name: the box hops (STEP).
        doc.channel((1, "hop"), spin, "translation", [0.0, 0.5, 1.0], [[0, 1, 0], [0, 2, 0], [0, 1, 0]], interpolation="STEP")
    else:
        tl = t % 2.0
        deg = lerp_keys(SPIN_TIMES, [[d] for d in SPIN_DEG], tl)[0]
        v0, out0, in1, v1 = MOON_SCALE
        spin = doc.node(name="spinner", mesh=m, translation=lerp_keys(MOVE_TIMES, MOVE, tl), rotation=quat_y(deg), children=[])
        moon = doc.node(root=False, name="moon", mesh=moon_mesh, translation=[1.5, 0, 0], scale=hermite(v0, out0, in1, v1, tl / 2.0, 2.0))
        doc.j["nodes"][spin]["children"].append(moon)
    return doc


# --- morph: a box on the ground stretched up (target 0) and out along +X (target 1).
MORPH_TIMES = [0.0, 1.0, 2.0]
MORPH_WEIGHTS = [[0.0, 0.0], [1.0, 0.5], [0.0, 1.0]]


def morph(t=None):
    doc = Doc()
    ground(doc)
    camera(doc, [2.0, 2.2, 3.5], [0.2, 0.7, 0.0])
    p, n, i = box()
    up = [(0, 1.0 if q[1] > 0 else 0, 0) for q in p]
    out = [(0.5 if q[0] > 0 else 0, 0, 0) for q in p]
    if t is None:
        m = doc.mesh("morph box", p, n, i, 1, targets=[up, out], weights=[0.0, 0.0])
        node = doc.node(name="morpher", mesh=m, translation=[0, 0.5, 0])
        doc.channel((0, "breathe"), node, "weights", MORPH_TIMES, [w for ws in MORPH_WEIGHTS for w in ws], acc_type="SCALAR")
    else:
        w = lerp_keys(MORPH_TIMES, MORPH_WEIGHTS, t % 2.0)
        posed = [tuple(q[k] + w[0] * a[k] + w[1] * b[k] for k in range(3)) for q, a, b in zip(p, up, out)]
        m = doc.mesh("morph box", posed, n, i, 1)
        doc.node(name="morpher", mesh=m, translation=[0, 0.5, 0])
    return doc


# --- skinned cylinder: two joints, the upper one bending about Z; the root slides along X.
RINGS = [0.0, 0.5, 1.0, 1.5, 2.0]
SEGMENTS = 16
RADIUS = 0.3
BEND_TIMES = [0.0, 1.0, 2.0]
BEND_DEG = [0, 90, 0]
SLIDE = [[0, 0, 0], [1, 0, 0], [0, 0, 0]]


def cylinder():
    p, n, i, joints, weights = [], [], [], [], []

    def influence(y):
        if y < 1.0:
            return (0, 1, 0, 0), (1.0, 0.0, 0.0, 0.0)
        if y > 1.0:
            return (1, 0, 0, 0), (1.0, 0.0, 0.0, 0.0)
        return (0, 1, 0, 0), (0.5, 0.5, 0.0, 0.0)

    for y in RINGS:
        for s in range(SEGMENTS):
            a = 2 * math.pi * s / SEGMENTS
            p.append((RADIUS * math.cos(a), y, RADIUS * math.sin(a)))
            n.append((math.cos(a), 0.0, math.sin(a)))
            j, w = influence(y)
            joints.append(j)
            weights.append(w)
    for r in range(len(RINGS) - 1):
        for s in range(SEGMENTS):
            a, b = r * SEGMENTS + s, r * SEGMENTS + (s + 1) % SEGMENTS
            c, d = a + SEGMENTS, b + SEGMENTS
            i += [a, c, b, b, c, d]
    for y, ny in ((0.0, -1.0), (2.0, 1.0)):
        center = len(p)
        p.append((0.0, y, 0.0))
        n.append((0.0, ny, 0.0))
        j, w = influence(y)
        joints.append(j)
        weights.append(w)
        for s in range(SEGMENTS):
            a = 2 * math.pi * s / SEGMENTS
            p.append((RADIUS * math.cos(a), y, RADIUS * math.sin(a)))
            n.append((0.0, ny, 0.0))
            joints.append(j)
            weights.append(w)
        for s in range(SEGMENTS):
            a, b = center + 1 + s, center + 1 + (s + 1) % SEGMENTS
            i += [center, b, a] if ny > 0 else [center, a, b]
    return p, n, i, joints, weights


def mat_mul(a, b):
    return [[sum(a[r][k] * b[k][c] for k in range(4)) for c in range(4)] for r in range(4)]


def translate(x, y, z):
    return [[1, 0, 0, x], [0, 1, 0, y], [0, 0, 1, z], [0, 0, 0, 1]]


def rot_z(deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return [[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]


def skinned(t=None):
    doc = Doc()
    ground(doc)
    camera(doc, [1.8, 1.8, 3.6], [0.6, 1.0, 0.0])
    p, n, i, joints, weights = cylinder()
    if t is None:
        m = doc.mesh("cylinder", p, n, i, 1, joints=joints, skin_weights=weights)
        j0 = doc.node(name="root joint", translation=SLIDE[0], children=[])
        j1 = doc.node(root=False, name="upper joint", translation=[0, 1, 0])
        doc.j["nodes"][j0]["children"].append(j1)
        inverse_bind = [translate(0, 0, 0), translate(0, -1, 0)]
        # Column-major, as glTF stores matrices.
        ib = doc.accessor("f", 16, [[mm[r][c] for c in range(4) for r in range(4)] for mm in inverse_bind], "MAT4")
        doc.j["skins"] = [{"name": "cylinder skin", "joints": [j0, j1], "inverseBindMatrices": ib}]
        doc.node(name="cylinder", mesh=m, skin=0)
        clip = (0, "bend")
        doc.channel(clip, j1, "rotation", BEND_TIMES, [quat_z(d) for d in BEND_DEG], acc_type="VEC4")
        doc.channel(clip, j0, "translation", BEND_TIMES, SLIDE)
    else:
        tl = t % 2.0
        deg = lerp_keys(BEND_TIMES, [[d] for d in BEND_DEG], tl)[0]
        x = lerp_keys(BEND_TIMES, SLIDE, tl)
        m0 = translate(*x)
        m1 = mat_mul(mat_mul(mat_mul(translate(*x), translate(0, 1, 0)), rot_z(deg)), translate(0, -1, 0))
        mats = [m0, m1]
        posed_p, posed_n = [], []
        for q, nn, j, w in zip(p, n, joints, weights):
            m = [[sum(w[k] * mats[j[k]][r][c] for k in range(4) if w[k] > 0) for c in range(4)] for r in range(4)]
            posed_p.append(tuple(sum(m[r][c] * (list(q) + [1])[c] for c in range(4)) for r in range(3)))
            a = [[m[r][c] for c in range(3)] for r in range(3)]
            cols = [[a[r][c] for r in range(3)] for c in range(3)]

            def cross(u, v):
                return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]

            cof = [cross(cols[1], cols[2]), cross(cols[2], cols[0]), cross(cols[0], cols[1])]  # columns
            nv = [sum(cof[c][r] * nn[c] for c in range(3)) for r in range(3)]
            length = math.sqrt(sum(v * v for v in nv))
            posed_n.append(tuple(v / length for v in nv))
        mesh = doc.mesh("cylinder", posed_p, posed_n, i, 1)
        doc.node(name="cylinder", mesh=mesh)
    return doc


def bad_fixtures():
    """Files that must fail with a clear error (or be repaired and counted)."""
    d = spinner()
    d.j["animations"][0]["channels"][0]["sampler"] = 7
    d.write(os.path.join(FIXTURES, "bad_missing_sampler.gltf"))

    d = skinned()
    prim = d.j["meshes"][1]["primitives"][0]
    acc = d.j["accessors"][prim["attributes"]["JOINTS_0"]]
    view = d.j["bufferViews"][acc["bufferView"]]
    struct.pack_into("<H", d.bin, view["byteOffset"] + 8 * 5, 9)  # vertex 5's first joint: 9 of 2
    d.write(os.path.join(FIXTURES, "bad_joint_index.gltf"))

    d = spinner()
    sampler = d.j["animations"][0]["samplers"][1]
    view = d.j["bufferViews"][d.j["accessors"][sampler["output"]]["bufferView"]]
    struct.pack_into("<f", d.bin, view["byteOffset"] + 4 * 4, float("nan"))  # key 1's y
    d.write(os.path.join(FIXTURES, "bad_nan_keyframe.gltf"))

    d = morph()
    sampler = d.j["animations"][0]["samplers"][0]
    d.j["accessors"][sampler["output"]]["count"] -= 1  # 5 weights for 3 keys of 2 targets
    d.write(os.path.join(FIXTURES, "bad_output_count.gltf"))

    d = skinned()
    prim = d.j["meshes"][1]["primitives"][0]
    acc = d.j["accessors"][prim["attributes"]["WEIGHTS_0"]]
    view = d.j["bufferViews"][acc["bufferView"]]
    struct.pack_into("<ff", d.bin, view["byteOffset"], 2.0, 2.0)  # vertex 0 sums to 4: repaired
    d.write(os.path.join(FIXTURES, "repair_weights.gltf"))


STATIC_TIMES = {"spinner": [0.7, 2.6], "morph": [0.3, 1.6], "skinned_cylinder": [0.5, 1.25]}

if __name__ == "__main__":
    for name, make in [("spinner", spinner), ("morph", morph), ("skinned_cylinder", skinned)]:
        make().write(os.path.join(HERE, name + ".gltf"))
        for t in STATIC_TIMES[name]:
            make(t).write(os.path.join(FIXTURES, "%s_static_%s.gltf" % (name, t)))
    bad_fixtures()
