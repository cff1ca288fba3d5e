"""raygraph's BSDF as a Mitsuba 3 plugin (`<bsdf type="raygraph">`).

It evaluates exactly `brdf_light` of shaders/common/lighting.wgsl:

    f(v, l) = (1 - F) (1 - metallic) albedo / pi  +  D G F / (4 n.l n.v)

    D = a^2 / (pi ((n.h)^2 (a^2 - 1) + 1)^2),  a = roughness^2         (GGX)
    G = n.l / (n.l (1 - k) + k) * n.v / (n.v (1 - k) + k),  k = (roughness + 1)^2 / 8
                                                                        (Schlick-Smith)
    F = f0' + (f90' - f0') (1 - max(h.v, 0))^5                          (Schlick)
    f0' = mix(f0, albedo, metallic),  f90' = mix(f90, 1, metallic),  n.v clamped to 1e-4

and samples it: with probability p_spec a GGX half vector (pdf D (n.h) / (4 v.h)), otherwise
a cosine-weighted direction (pdf n.l / pi); the pdf is the mixture of both, so the sample
weight f cos / pdf is unbiased whatever p_spec. p_spec = clamp(lum(F(n.v)) / (lum(F(n.v)) +
lum(diffuse albedo)), 0.1, 0.9), a function of the viewing direction only.

Parameters (what `raygraph scene export` writes): `base_color` (rgb, linear),
`base_color_texture` (bitmap, sRGB: multiplies it), `metallic`, `roughness` (floats),
`metallic_roughness_texture` (bitmap, raw: blue multiplies metallic, green roughness),
`f0` (rgb: the dielectric reflectance at normal incidence, 0.04 for glTF's core material),
`f90` (float, 1), `normal_texture` (bitmap, raw) and `normal_scale` (float, 1).

Normal maps are applied here, as apply_normal_map of shaders/common/material_inputs.wgsl does:
tangent t = dp/du made orthogonal to the shading normal n, bitangent = +-(n x t) on the side of
decreasing v (glTF's convention, mirrored uvs included), perturbed normal
normalize(t m.x s + b m.y s + n m.z) with m = 2 texel - 1 and s = `normal_scale`; the shading
normal itself where the uvs are degenerate. Mitsuba's own `normalmap` builds its bitangent as
n x t on every triangle, which reads one axis flipped where uvs are mirrored.

The surface is one-sided like raygraph's lighting (n.l <= 0 or n.v <= 0: no reflection);
the export wraps double-sided materials in `twosided`. Roughness is clamped to [0.02, 1] as
raygraph clamps it (shaders/common/surface.wgsl): below that, a^2 is lost in float precision in
D's n.h^2 (a^2 - 1) + 1, and the clamp is part of raygraph's surfaces anyway.

Written with Dr.Jit operations only, so it runs in every variant (scalar_rgb, llvm_ad_rgb,
cuda_ad_rgb). Import this module (after mi.set_variant) before loading an exported scene.
"""

import drjit as dr
import mitsuba as mi

ROUGHNESS_MIN = 0.02
N_V_MIN = 1e-4


def _luminance(c):
    return c[0] * 0.2126 + c[1] * 0.7152 + c[2] * 0.0722


class RaygraphBSDF(mi.BSDF):
    def __init__(self, props):
        mi.BSDF.__init__(self, props)

        def colour(name, default):
            return mi.Color3f(props[name]) if props.has_property(name) else mi.Color3f(default)

        def scalar(name, default):
            return mi.Float(props[name]) if props.has_property(name) else mi.Float(default)

        def texture(name):
            return props[name] if props.has_property(name) else None

        self.base_color = colour("base_color", 1.0)
        self.f0 = colour("f0", 0.04)
        self.metallic = scalar("metallic", 0.0)
        self.roughness = scalar("roughness", 1.0)
        self.f90 = scalar("f90", 1.0)
        self.base_color_texture = texture("base_color_texture")
        self.metallic_roughness_texture = texture("metallic_roughness_texture")
        self.normal_texture = texture("normal_texture")
        self.normal_scale = scalar("normal_scale", 1.0)
        flags = mi.BSDFFlags.DiffuseReflection | mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
        self.m_components = [mi.BSDFFlags.DiffuseReflection | mi.BSDFFlags.FrontSide,
                             mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide]
        self.m_flags = flags

    # The material at a surface point: albedo, metallic, roughness, f0', f90'.
    def _point(self, si, active):
        albedo = mi.Color3f(self.base_color)
        if self.base_color_texture is not None:
            albedo *= self.base_color_texture.eval(si, active)
        metallic = mi.Float(self.metallic)
        roughness = mi.Float(self.roughness)
        if self.metallic_roughness_texture is not None:
            mr = self.metallic_roughness_texture.eval(si, active)
            metallic *= mr[2]
            roughness *= mr[1]
        # raygraph's surfaces clamp roughness (shaders/common/surface.wgsl, Surface.roughness).
        roughness = dr.clip(roughness, ROUGHNESS_MIN, 1.0)
        f0 = dr.lerp(self.f0, albedo, metallic)
        f90 = dr.lerp(self.f90, 1.0, metallic)
        return albedo, metallic, roughness, f0, f90

    @staticmethod
    def _alpha(roughness):
        return roughness * roughness

    @staticmethod
    def _ggx_d(n_h, a):
        a2 = a * a
        t = n_h * n_h * (a2 - 1.0) + 1.0
        return a2 / (dr.pi * t * t)

    @staticmethod
    def _schlick(cos_theta, f0, f90):
        return f0 + (f90 - f0) * dr.power(1.0 - dr.clip(cos_theta, 0.0, 1.0), 5.0)

    def _spec_probability(self, n_v, albedo, metallic, f0, f90):
        f = self._schlick(n_v, f0, f90)
        ws = _luminance(f)
        wd = _luminance((1.0 - f) * (1.0 - metallic) * albedo)
        return dr.clip(ws / dr.maximum(ws + wd, 1e-8), 0.1, 0.9)

    # The normal-mapped shading frame (world space); None without a normal map (si.sh_frame).
    def _frame(self, si, active):
        if self.normal_texture is None:
            return None
        n = si.sh_frame.n
        texel = self.normal_texture.eval(si, active)
        m = mi.Vector3f(texel[0], texel[1], texel[2]) * 2.0 - 1.0
        dpdu, dpdv = si.dp_du, si.dp_dv
        t_raw = dpdu - n * dr.dot(n, dpdu)
        usable = (dr.squared_norm(t_raw) > 1e-12 * dr.squared_norm(dpdu)) & (dr.squared_norm(dpdu) > 0.0)
        t = dr.normalize(t_raw)
        c = dr.cross(n, t)
        b = dr.select(dr.dot(c, dpdv) > 0.0, -c, c)
        p = t * (m.x * self.normal_scale) + b * (m.y * self.normal_scale) + n * m.z
        usable &= dr.squared_norm(p) > 0.0
        n_mapped = dr.select(usable, dr.normalize(p), n)
        return mi.Frame3f(n_mapped)

    # Direction w (local to si.sh_frame) local to `frame` (si.sh_frame itself where None).
    @staticmethod
    def _to_frame(si, frame, w):
        return w if frame is None else frame.to_local(si.sh_frame.to_world(w))

    # Whether wo (local to si.sh_frame) leaves above the geometric surface: raygraph's path
    # tracer ends a path, and lights nothing, below the triangle's plane (shaders/rt/path.wgsl),
    # where a normal map or an interpolated normal would let the BSDF reflect into the surface.
    # The geometric normal is taken on the shading normal's side; a query without one (a zero
    # si.n: check_bsdf.py's, outside any shape) is above.
    @staticmethod
    def _above_geometry(si, wo):
        g = si.sh_frame.to_local(si.n)
        g = dr.select(g.z < 0.0, -g, g)
        return (dr.dot(wo, g) > 0.0) | (dr.squared_norm(si.n) == 0.0)

    # f(v, l) n.l, and the pdf of sampling l, for wo local to si.sh_frame.
    def _eval_pdf(self, si, wo, active):
        frame = self._frame(si, active)
        active = active & self._above_geometry(si, wo)
        point = self._point(si, active)
        return self._eval_pdf_local(point, self._to_frame(si, frame, si.wi), self._to_frame(si, frame, wo), active)

    # f(v, l) n.l, and the pdf of sampling l, for v and l (= wo) local to the shading frame, at
    # the material point `point` (_point); 0 for both where not `active`.
    def _eval_pdf_local(self, point, v, wo, active):
        albedo, metallic, roughness, f0, f90 = point
        n_l = mi.Frame3f.cos_theta(wo)
        cos_v = mi.Frame3f.cos_theta(v)
        valid = active & (n_l > 0.0) & (cos_v > 0.0)
        n_v = dr.maximum(cos_v, N_V_MIN)
        h = dr.normalize(wo + v)
        n_h = dr.maximum(mi.Frame3f.cos_theta(h), 0.0)
        v_h = dr.maximum(dr.dot(h, v), 0.0)
        a = self._alpha(roughness)
        d = self._ggx_d(n_h, a)
        k = (roughness + 1.0) * (roughness + 1.0) / 8.0
        g = (n_l / (n_l * (1.0 - k) + k)) * (n_v / (n_v * (1.0 - k) + k))
        f = self._schlick(v_h, f0, f90)
        specular = d * g * f / (4.0 * n_l * n_v)
        diffuse = (1.0 - f) * (1.0 - metallic) * albedo / dr.pi
        value = dr.select(valid, (diffuse + specular) * n_l, 0.0)
        p_spec = self._spec_probability(n_v, albedo, metallic, f0, f90)
        pdf_spec = d * n_h / (4.0 * dr.maximum(v_h, 1e-8))
        pdf_diff = n_l / dr.pi
        pdf = dr.select(valid, p_spec * pdf_spec + (1.0 - p_spec) * pdf_diff, 0.0)
        return mi.Color3f(value), pdf

    def eval(self, ctx, si, wo, active=True):
        return self._eval_pdf(si, wo, active)[0]

    def pdf(self, ctx, si, wo, active=True):
        return self._eval_pdf(si, wo, active)[1]

    def eval_pdf(self, ctx, si, wo, active=True):
        return self._eval_pdf(si, wo, active)

    def sample(self, ctx, si, sample1, sample2, active=True):
        point = self._point(si, active)
        albedo, metallic, roughness, f0, f90 = point
        frame = self._frame(si, active)
        v = self._to_frame(si, frame, si.wi)
        cos_v = mi.Frame3f.cos_theta(v)
        p_spec = self._spec_probability(dr.maximum(cos_v, N_V_MIN), albedo, metallic, f0, f90)
        pick_spec = sample1 < p_spec
        # GGX half vector: cos^2 theta_h = (1 - u) / (1 + (a^2 - 1) u).
        a = self._alpha(roughness)
        a2 = a * a
        u = sample2[0]
        cos2 = (1.0 - u) / (1.0 + (a2 - 1.0) * u)
        cos_h = dr.sqrt(dr.maximum(cos2, 0.0))
        sin_h = dr.sqrt(dr.maximum(1.0 - cos2, 0.0))
        phi = 2.0 * dr.pi * sample2[1]
        h = mi.Vector3f(sin_h * dr.cos(phi), sin_h * dr.sin(phi), cos_h)
        reflected = 2.0 * dr.dot(v, h) * h - v
        cosine = mi.warp.square_to_cosine_hemisphere(sample2)
        wo = dr.select(pick_spec, reflected, cosine)
        value, pdf = self._eval_pdf_local(point, v, wo, active)
        ok = active & (cos_v > 0.0) & (mi.Frame3f.cos_theta(wo) > 0.0) & (pdf > 0.0)
        bs = dr.zeros(mi.BSDFSample3f)
        bs.wo = wo if frame is None else si.sh_frame.to_local(frame.to_world(wo))
        ok &= self._above_geometry(si, bs.wo)
        bs.pdf = dr.select(ok, pdf, 0.0)
        bs.eta = 1.0
        bs.sampled_type = dr.select(pick_spec, mi.UInt32(+mi.BSDFFlags.GlossyReflection), mi.UInt32(+mi.BSDFFlags.DiffuseReflection))
        bs.sampled_component = dr.select(pick_spec, mi.UInt32(1), mi.UInt32(0))
        weight = dr.select(ok, value / dr.maximum(pdf, 1e-20), 0.0)
        return bs, mi.Color3f(weight)

    def traverse(self, callback):
        pass

    def to_string(self):
        return "RaygraphBSDF[]"


def register():
    """Registers the plugin as `raygraph` for the active variant."""
    mi.register_bsdf("raygraph", lambda props: RaygraphBSDF(props))


register()
