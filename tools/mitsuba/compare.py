"""Compares a raygraph render with a Mitsuba 3 reference of the same scene.

Exports the scene with `raygraph scene export SCENE OUT/scene.xml` (meshes, textures, sky and
the `raygraph` BSDF: tools/mitsuba/raygraph_bsdf.py), renders it with Mitsuba's path tracer,
writes OUT/mitsuba.exr, reads the test image (raygraph's `render --out x.exr`: linear radiance,
RGB float, the same size) and prints

    relMSE = mean over pixels and channels of (test - ref)^2 / (ref^2 + 0.01)
             (epsilon 0.01 keeps black reference pixels from dominating)
    HDR-FLIP (NVIDIA's flip_evaluator, "HDR" mode: it tone-maps over a range of exposures
             itself; the mean of the error map)

and writes OUT/flip.png (the FLIP error map, magma), OUT/relmse.exr (per pixel, the mean over
channels), OUT/mitsuba.png and OUT/test.png (Reinhard tone-mapped previews).

Without a raygraph image, `--against-mitsuba SPP` compares the reference with a second
Mitsuba render at SPP samples and another seed: a check of the pipeline (its error falls
towards 0 as both sample counts grow).

Examples:
    python tools/mitsuba/compare.py default --spp 256 --test raygraph.exr
    python tools/mitsuba/compare.py default --spp 1024 --against-mitsuba 64

The default variant, llvm_ad_rgb, needs LLVM >= 16 (set DRJIT_LIBLLVM_PATH to its libLLVM.so);
scalar_rgb runs the Python BSDF once per ray (about 100x slower); cuda_ad_rgb on a GPU.
"""

import argparse
import os
import subprocess
import sys
import time

import numpy as np

RELMSE_EPSILON = 0.01


def parse_args():
    p = argparse.ArgumentParser(description="Compare a raygraph render with a Mitsuba 3 reference.")
    p.add_argument("scene", help="a raygraph scene: built-in name or .gltf/.glb file")
    p.add_argument("--width", type=int, default=256)
    p.add_argument("--height", type=int, default=256)
    p.add_argument("--spp", type=int, default=256, help="the reference's samples per pixel")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--max-depth", type=int, default=-1,
                   help="Mitsuba's path length (-1: unlimited, Russian roulette; 2: direct light only)")
    p.add_argument("--variant", default="llvm_ad_rgb", help="Mitsuba variant: llvm_ad_rgb, scalar_rgb, cuda_ad_rgb")
    p.add_argument("--raygraph", default="target/release/raygraph", help="the raygraph binary")
    p.add_argument("--out", default="mitsuba_compare", help="folder of the export, the reference and the error images")
    test = p.add_mutually_exclusive_group(required=True)
    test.add_argument("--test", help="raygraph's image: linear RGB EXR of the same size")
    test.add_argument("--against-mitsuba", type=int, metavar="SPP",
                      help="compare with a second Mitsuba render at SPP samples and seed + 1")
    return p.parse_args()


def export(args):
    xml = os.path.join(args.out, "scene.xml")
    if not os.path.exists(args.raygraph):
        sys.exit(f"compare.py: raygraph binary {args.raygraph} not found (build it, or give --raygraph PATH)")
    r = subprocess.run([args.raygraph, "scene", "export", args.scene, xml], capture_output=True, text=True)
    sys.stderr.write(r.stderr)
    if r.returncode != 0:
        sys.exit(f"compare.py: `{args.raygraph} scene export {args.scene} {xml}` failed ({r.returncode})")
    print(r.stdout.strip())
    return xml


def render(mi, xml, args, spp, seed):
    scene = mi.load_file(xml, width=args.width, height=args.height, spp=spp, seed=seed, max_depth=args.max_depth)
    start = time.time()
    image = np.array(mi.render(scene, seed=seed), dtype=np.float32)[..., :3]
    print(f"Mitsuba {args.variant}: {args.width}x{args.height} at {spp} spp, seed {seed}: {time.time() - start:.1f} s")
    return image


def read_test(mi, path, shape):
    if not os.path.exists(path):
        sys.exit(f"compare.py: {path}: no such file")
    try:
        image = np.array(mi.Bitmap(path), dtype=np.float32)
    except Exception as e:  # Mitsuba raises RuntimeError with the reader's message
        sys.exit(f"compare.py: {path}: cannot read it as an image: {e}")
    if image.ndim == 2:
        image = np.repeat(image[..., None], 3, axis=2)
    # raygraph's EXR is premultiplied: alpha is the share of the pixel's paths that met
    # geometry (0 where the camera sees only the backdrop, which is the tone map's, not the sky).
    alpha = image[..., 3] if image.shape[2] == 4 else np.ones(image.shape[:2], dtype=np.float32)
    image = image[..., :3]
    if image.shape != shape:
        sys.exit(f"compare.py: {path}: {image.shape[1]}x{image.shape[0]} pixels, the reference has {shape[1]}x{shape[0]} "
                 f"(give --width {image.shape[1]} --height {image.shape[0]})")
    if not np.all(np.isfinite(image)):
        print(f"warning: {path}: {np.count_nonzero(~np.isfinite(image))} values are NaN or infinite (counted as 0)")
        image = np.nan_to_num(image, nan=0.0, posinf=0.0, neginf=0.0)
    return image, alpha


def preview(mi, image, path):
    ldr = np.clip(image / (1.0 + image), 0.0, 1.0) ** (1.0 / 2.2)
    mi.Bitmap((ldr * 255.0 + 0.5).astype(np.uint8)).write(path)


def compare(mi, reference, test, out, covered=None):
    """relMSE over the `covered` pixels (all where None), HDR-FLIP over the whole image."""
    import flip_evaluator
    relmse_map = ((test - reference) ** 2 / (reference ** 2 + RELMSE_EPSILON)).mean(axis=2)
    judged = relmse_map[covered] if covered is not None else relmse_map.ravel()
    flip_map, flip_mean, _ = flip_evaluator.evaluate(np.maximum(reference, 0.0), np.maximum(test, 0.0), "HDR")
    mi.Bitmap((np.clip(flip_map, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)).write(os.path.join(out, "flip.png"))
    mi.Bitmap(relmse_map.astype(np.float32), mi.Bitmap.PixelFormat.Y).write(os.path.join(out, "relmse.exr"))
    preview(mi, test, os.path.join(out, "test.png"))
    quantiles = np.percentile(judged, [50, 90, 99])
    print(f"relMSE (epsilon {RELMSE_EPSILON}) over {judged.size} pixels: {judged.mean():.6f} (per pixel: median {quantiles[0]:.2e}, "
          f"90% {quantiles[1]:.2e}, 99% {quantiles[2]:.2e}, max {judged.max():.2e})")
    # The pixels the trimmed figures keep: all but the 0.1% of largest relMSE (fireflies of either image).
    kept = np.argsort(judged, kind="stable")[: int(judged.size * 0.999)]
    trimmed = judged[kept].mean()
    print(f"relMSE without the 0.1% largest pixels (fireflies): {trimmed:.6f}")
    print(f"HDR-FLIP mean: {flip_mean:.6f}")
    print(f"mean radiance: reference {reference.mean(axis=(0, 1))}, test {test.mean(axis=(0, 1))}")
    ref_px = reference[covered] if covered is not None else reference.reshape(-1, 3)
    test_px = test[covered] if covered is not None else test.reshape(-1, 3)
    ratio = test_px[kept].sum(axis=0) / np.maximum(ref_px[kept].sum(axis=0), 1e-30)
    print(f"mean radiance ratio test / reference without the 0.1% largest pixels: {ratio}")
    return judged.mean(), flip_mean


def main():
    args = parse_args()
    os.makedirs(args.out, exist_ok=True)
    import mitsuba as mi
    mi.set_variant(args.variant)
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import raygraph_bsdf  # noqa: F401 (registers the plugin)
    xml = export(args)
    reference = render(mi, xml, args, args.spp, args.seed)
    mi.Bitmap(reference).write(os.path.join(args.out, "mitsuba.exr"))
    preview(mi, reference, os.path.join(args.out, "mitsuba.png"))
    if args.test:
        test, alpha = read_test(mi, args.test, reference.shape)
        # Only the pixels whose every path met geometry are compared: where camera rays miss,
        # Mitsuba shows the environment and raygraph the tone map's backdrop (alpha < 1).
        covered = alpha >= 0.999
        print(f"compared: the {covered.mean() * 100:.1f}% of pixels fully covered by geometry in raygraph's image")
        reference = np.where(covered[..., None], reference, 0.0)
        test = np.where(covered[..., None], test, 0.0)
    else:
        test, covered = render(mi, xml, args, args.against_mitsuba, args.seed + 1), None
    compare(mi, reference, test, args.out, covered)
    print(f"wrote {args.out}/mitsuba.exr, flip.png, relmse.exr, mitsuba.png, test.png")


if __name__ == "__main__":
    main()
