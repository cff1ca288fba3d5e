#!/usr/bin/env python3
"""Diagnostic variants of the raster graph's shade pass (forward/shade.wgsl), to find what the
conformance work costs it on scenes that use none of the new features. Each variant patches the
working tree's shaders, is built (cargo build --release: the shaders are built in) and copied to
.gpu/raygraph-VARIANT.gz; the working tree is restored after each. Not a feature: a measurement
aid for docs/experiments/gltf_conformance/shade_variants.sh (BENCHMARKS.md says what it found).

  no_ortho   the camera functions without the orthographic branch (perspective only)
  no_extras  surface_at_cone without the shadow-terminator offset and the lobes' assignment
"""
import gzip, shutil, subprocess, sys

PATCHES = {
    "no_ortho": [("shaders/common/camera.wgsl", "fn camera_is_orthographic() -> bool {\n    return frame.camera_pos.w == 0.0;", "fn camera_is_orthographic() -> bool {\n    return false;")],
    "no_extras": [
        ("shaders/common/surface.wgsl", "    s.shadow_offset = max(dot(lift, geo), 0.0);", "    s.shadow_offset = 0.0 * dot(lift, vec3<f32>(0.0));"),
        ("shaders/common/surface.wgsl", "    if material_has_lobes(inst.material) {\n        s.lobes = hit_lobes(", "    if false {\n        s.lobes = hit_lobes("),
    ],
}

for name in sys.argv[1:] or PATCHES:
    saved = {}
    try:
        for path, old, new in PATCHES[name]:
            text = saved.setdefault(path, open(path).read()) if path not in saved else open(path).read()
            assert text.count(old) == 1, (name, path, old)
            open(path, "w").write(text.replace(old, new))
        subprocess.run(["cargo", "build", "--release", "-q"], check=True)
        with open("target/release/raygraph", "rb") as src, gzip.open(f".gpu/raygraph-{name}.gz", "wb") as dst:
            shutil.copyfileobj(src, dst)
    finally:
        for path, text in saved.items():
            open(path, "w").write(text)
subprocess.run(["cargo", "build", "--release", "-q"], check=True)
