#!/usr/bin/env python3
"""Writes a glTF scene of N quads, each with its own base-colour texture (a plain colour), the
textures' sizes cycling through 64, 128, 256 and 512 texels: a scene with as many textures as
a real one, for measuring what a frame costs per texture (docs/experiments/texture_pool/run.sh).

Usage: many_textures.py N OUT.gltf
"""
import base64, json, struct, sys, zlib

SIZES = [64, 128, 256, 512]


def png(size, rgb):
    row = b"\x00" + bytes(rgb + (255,)) * size
    chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    ihdr = struct.pack(">IIBBBBB", size, size, 8, 6, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(row * size)) + chunk(b"IEND", b"")


def scene(n):
    columns = max(1, int(n ** 0.5))
    pos, uv = [], []
    for i in range(n):
        x, z = (i % columns) * 1.1, (i // columns) * 1.1
        pos += [(x, 0, z), (x + 1, 0, z), (x + 1, 0, z + 1), (x, 0, z + 1)]
        uv += [(0, 0), (1, 0), (1, 1), (0, 1)]
    pb = b"".join(struct.pack("<3f", *p) for p in pos)
    ub = b"".join(struct.pack("<2f", *u) for u in uv)
    ib = struct.pack("<6H", 0, 2, 1, 0, 3, 2)
    data = pb + ub + ib
    g = {
        "asset": {"version": "2.0", "generator": "docs/experiments/texture_pool/many_textures.py"},
        "scene": 0, "scenes": [{"nodes": list(range(n))}], "samplers": [{}],
        "nodes": [], "meshes": [], "materials": [], "textures": [], "images": [], "accessors": [],
        "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(pb)},
            {"buffer": 0, "byteOffset": len(pb), "byteLength": len(ub)},
            {"buffer": 0, "byteOffset": len(pb) + len(ub), "byteLength": len(ib)},
        ],
    }
    for i in range(n):
        lo, hi = pos[4 * i], pos[4 * i + 2]
        g["accessors"] += [
            {"bufferView": 0, "byteOffset": 48 * i, "componentType": 5126, "count": 4, "type": "VEC3", "min": list(map(float, lo)), "max": list(map(float, hi))},
            {"bufferView": 1, "byteOffset": 32 * i, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"},
        ]
        rgb = (i * 37 % 256, i * 91 % 256, i * 13 % 256)
        g["images"].append({"uri": "data:image/png;base64," + base64.b64encode(png(SIZES[i % len(SIZES)], rgb)).decode()})
        g["textures"].append({"source": i, "sampler": 0})
        g["materials"].append({"pbrMetallicRoughness": {"baseColorTexture": {"index": i}}})
        g["meshes"].append({"primitives": [{"attributes": {"POSITION": 3 * i, "TEXCOORD_0": 3 * i + 1}, "indices": 3 * i + 2, "material": i}]})
        g["nodes"].append({"mesh": i})
    return g


if __name__ == "__main__":
    with open(sys.argv[2], "w") as f:
        json.dump(scene(int(sys.argv[1])), f)
