"""Checks the `raygraph` Mitsuba BSDF (raygraph_bsdf.py) against closed forms and quadrature.

1. Energy of single lobes: for a few roughness values and viewing angles, the directional
   albedo E(v) = integral of f(v, l) cos over the hemisphere by midpoint quadrature on a fine
   (theta, phi) grid, against the mean sample weight f cos / pdf of `sample` (they must agree
   within a few standard errors), and the integral of `pdf` over the upper hemisphere against
   the share of samples `sample` returns above it (the pdf is then the density it samples).
2. White furnace: a unit sphere inside a uniform environment of radiance 1, rendered with
   Mitsuba's path tracer. A convex object never sees itself, so each pixel shows E(v) x 1:
   pure Lambert (f0 = f90 = 0) renders exactly 1; with raygraph's f90 = 1 and f0 = 0 the
   (1 - F) factor takes Schlick's grazing reflectance from the diffuse part and the GGX lobe
   (roughness 1) gives most of it back: E = 0.99995 at normal view, 0.992 at cos 0.05
   (quadrature), so the sphere is a little darker than 1 towards its rim.

Exits non-zero when a check fails. Usage (llvm_ad_rgb needs LLVM >= 16: set
DRJIT_LIBLLVM_PATH, e.g. /usr/lib/x86_64-linux-gnu/libLLVM.so.19.1):
    python tools/mitsuba/check_bsdf.py [--variant llvm_ad_rgb]
"""

import argparse
import math
import os
import sys

import drjit as dr
import mitsuba as mi
import numpy as np


def bsdf_of(roughness, metallic, base_color=1.0, f0=0.04, f90=1.0):
    return mi.load_dict({"type": "raygraph", "base_color": mi.ScalarColor3f(base_color), "metallic": metallic,
                         "roughness": roughness, "f0": mi.ScalarColor3f(f0), "f90": f90})


def interaction(cos_v, n):
    si = dr.zeros(mi.SurfaceInteraction3f, n)
    sin_v = math.sqrt(max(0.0, 1.0 - cos_v * cos_v))
    si.wi = mi.Vector3f(sin_v, 0.0, cos_v)
    return si


def quadrature(bsdf, cos_v, n_theta=2048, n_phi=4096):
    """The integrals of f cos and of pdf over the upper hemisphere (midpoint rule)."""
    t = (np.arange(n_theta) + 0.5) * (0.5 * math.pi / n_theta)
    p = (np.arange(n_phi) + 0.5) * (2.0 * math.pi / n_phi)
    tt, pp = np.meshgrid(t, p, indexing="ij")
    tt, pp = tt.ravel(), pp.ravel()
    wo = mi.Vector3f(np.sin(tt) * np.cos(pp), np.sin(tt) * np.sin(pp), np.cos(tt))
    si = interaction(cos_v, tt.size)
    value, pdf = bsdf.eval_pdf(mi.BSDFContext(), si, wo)
    d_omega = np.sin(tt) * (0.5 * math.pi / n_theta) * (2.0 * math.pi / n_phi)
    e = np.array(value)[:, 0] if np.array(value).shape[0] == tt.size else np.array(value)[0]
    return float(np.sum(e * d_omega)), float(np.sum(np.array(pdf) * d_omega))


def sampled(bsdf, cos_v, n=1 << 22, seed=1):
    """The mean sample weight, its standard error, and the share of valid samples."""
    sampler = mi.load_dict({"type": "independent"})
    sampler.seed(seed, n)
    si = interaction(cos_v, n)
    bs, weight = bsdf.sample(mi.BSDFContext(), si, sampler.next_1d(), sampler.next_2d())
    w = np.array(weight)
    w = w[:, 0] if w.shape[0] == n else w[0]
    valid = float(np.mean(np.array(bs.pdf) > 0.0))
    return float(np.mean(w)), float(np.std(w) / math.sqrt(n)), valid


def lobe_checks():
    ok = True
    print("lobe                 cos_v  quadrature E  sampled E (+- 1 s.e.)   integral pdf  valid share")
    cases = [("GGX metal", r, 1.0) for r in (1.0, 0.6, 0.3, 0.2)] + [("dielectric", r, 0.0) for r in (1.0, 0.3)]
    for name, roughness, metallic in cases:
        bsdf = bsdf_of(roughness, metallic)
        for cos_v in (1.0, 0.7, 0.3):
            e, pdf_integral = quadrature(bsdf, cos_v)
            mean, se, valid = sampled(bsdf, cos_v)
            # 5 standard errors, plus the quadrature's own error (measured: below 2e-4 for
            # roughness >= 0.2 when the grid is halved).
            good = abs(mean - e) <= 5.0 * se + 1e-3 and abs(pdf_integral - valid) <= 2e-3
            ok &= good
            print(f"{name:10} r={roughness:<4}  {cos_v:5.2f}  {e:12.5f}  {mean:9.5f} +- {se:.5f}   {pdf_integral:12.5f}  {valid:11.5f}  {'ok' if good else 'FAIL'}")
    return ok


def furnace(f0, f90, size=64, spp=256):
    """The white furnace: the mean radiance of the 8x8 centre pixels (the view within 3 degrees
    of the normal) and of the sphere (80% of its radius), each with its standard error (pixels
    are independent estimates)."""
    scene = mi.load_dict({
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 64, "rr_depth": 64},
        "sensor": {"type": "perspective", "fov": 20.0,
                   "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0, 8], target=[0, 0, 0], up=[0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": size, "height": size, "rfilter": {"type": "box"}},
                   "sampler": {"type": "independent", "sample_count": spp}},
        "env": {"type": "constant", "radiance": {"type": "rgb", "value": 1.0}},
        "sphere": {"type": "sphere", "radius": 1.0,
                   "bsdf": {"type": "raygraph", "base_color": mi.ScalarColor3f(1.0), "metallic": 0.0, "roughness": 1.0,
                            "f0": mi.ScalarColor3f(f0), "f90": f90}},
    })
    img = np.array(mi.render(scene))[..., 0]
    c = size // 2
    y, x = np.mgrid[0:size, 0:size]
    inside = (x + 0.5 - c) ** 2 + (y + 0.5 - c) ** 2 < (0.8 * size * 1.0 / (8 * math.tan(math.radians(10)) * 2)) ** 2
    centre = img[c - 4:c + 4, c - 4:c + 4].ravel()
    return [(float(v.mean()), float(v.std() / math.sqrt(v.size))) for v in (centre, img[inside])]


def furnace_checks():
    (centre, centre_se), (mean, mean_se) = furnace(0.0, 0.0)
    lambert_ok = abs(centre - 1.0) <= 5.0 * centre_se and abs(mean - 1.0) <= 5.0 * mean_se
    print(f"furnace, Lambert (f0 = f90 = 0): centre {centre:.5f} +- {centre_se:.5f}, sphere {mean:.5f} +- {mean_se:.5f} "
          f"(expected 1)  {'ok' if lambert_ok else 'FAIL'}")
    (centre, centre_se), (mean, mean_se) = furnace(0.0, 1.0)
    e_normal, _ = quadrature(bsdf_of(1.0, 0.0, f0=0.0, f90=1.0), 1.0)
    raygraph_ok = abs(centre - e_normal) <= 5.0 * centre_se + 1e-3
    print(f"furnace, raygraph f0 = 0, f90 = 1: centre {centre:.5f} +- {centre_se:.5f} (quadrature E at normal view "
          f"{e_normal:.5f}), sphere {mean:.5f} +- {mean_se:.5f}  {'ok' if raygraph_ok else 'FAIL'}")
    return lambert_ok and raygraph_ok


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--variant", default="llvm_ad_rgb")
    args = parser.parse_args()
    mi.set_variant(args.variant)
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import raygraph_bsdf  # noqa: F401 (registers the plugin)
    ok = lobe_checks()
    ok &= furnace_checks()
    print("all checks passed" if ok else "SOME CHECKS FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
