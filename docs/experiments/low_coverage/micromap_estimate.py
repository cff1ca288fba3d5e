"""PERF.md step 32: how many of the pine's foliage micro-triangles a texture-only opacity
micromap would resolve. Each foliage triangle (smallpine's BLEND material, its 2048x2048 atlas)
is cut into N x N micro-triangles in barycentric space; a micro-triangle is resolved where every
texel its bilinear reads can touch (the uv box of its corners, one texel more on each side,
wrapped as the sampler repeats) has alpha 0 (texture alpha exactly 0) or 255 (exactly 1), so
the alpha test could skip the texture there with the same result. Needs numpy and pillow; run
from the repository root: `python3 docs/experiments/low_coverage/micromap_estimate.py`."""
import json
import struct

import numpy as np
from PIL import Image

ROOT = "assets/gltf/smallpine/"
g = json.load(open(ROOT + "scene.gltf"))
data = open(ROOT + "scene.bin", "rb").read()


def accessor(i):
    a = g["accessors"][i]
    bv = g["bufferViews"][a["bufferView"]]
    comp = {5126: "f", 5123: "H", 5125: "I", 5121: "B"}[a["componentType"]]
    n = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[a["type"]]
    off = bv.get("byteOffset", 0) + a.get("byteOffset", 0)
    stride = bv.get("byteStride", 0) or n * struct.calcsize(comp)
    return np.array([struct.unpack_from("<" + comp * n, data, off + k * stride) for k in range(a["count"])])


def micro_corners(n):
    for i in range(n):
        for j in range(n - i):
            yield [(i, j), (i + 1, j), (i, j + 1)]
            if i + j < n - 1:
                yield [(i + 1, j), (i, j + 1), (i + 1, j + 1)]


alpha = np.array(Image.open(ROOT + "textures/M_TreeAtlas_baseColor.png").convert("RGBA"))[:, :, 3]
h, w = alpha.shape
prim = g["meshes"][1]["primitives"][0]
tris = accessor(prim["indices"]).reshape(-1, 3).astype(int)
uv = accessor(prim["attributes"]["TEXCOORD_0"])
print(f"atlas {w}x{h}: texels of alpha 0 {(alpha == 0).mean():.3f}, of alpha 255 {(alpha == 255).mean():.3f}; {len(tris)} foliage triangles")
for n in (4, 8, 16):
    counts = np.zeros(3)
    for tri in tris:
        a, b, c = uv[tri[0]], uv[tri[1]], uv[tri[2]]
        for corners in micro_corners(n):
            pts = np.array([a * (1 - (p + q) / n) + b * (p / n) + c * (q / n) for p, q in corners])
            lo, hi = pts.min(0), pts.max(0)
            xs = np.arange(int(np.floor(lo[0] * w - 0.5)) - 1, int(np.floor(hi[0] * w - 0.5)) + 3) % w
            ys = np.arange(int(np.floor(lo[1] * h - 0.5)) - 1, int(np.floor(hi[1] * h - 0.5)) + 3) % h
            block = alpha[np.ix_(ys, xs)]
            counts[0 if (block == 0).all() else 1 if (block == 255).all() else 2] += 1
    share = counts / counts.sum()
    print(f"{n * n} micro-triangles a triangle: alpha 0 {share[0]:.3f}, alpha 1 {share[1]:.3f}, mixed {share[2]:.3f}")
