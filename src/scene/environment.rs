//! An environment map: an equirectangular HDR image of the radiance arriving from every
//! direction (Radiance `.hdr` or OpenEXR), with an intensity scale and a rotation about the up
//! axis. It owns loading (clear errors naming the file), the radiance towards a direction, the
//! irradiance at every normal ([`IrradianceMap`]: a small grid of normals, what a diffuse term
//! reads; nine spherical harmonics too, which lose a sun or a studio's lamps:
//! tests/environment.rs), and an importance sampler over its texels ([`EnvironmentSampler`]:
//! Vose's alias table by luminance times solid angle, what next-event estimation draws from),
//! and the levels prefiltered for glossy reflections (`Environment::specular_chain`). The GPU
//! form is `runtime::environment_upload`'s.
//!
//! Directions: +Y is up; the image's top row looks up, its bottom row down; its horizontal
//! centre looks along -Z (glTF's forward) and u grows towards +X:
//! u = 1/2 + atan2(x, -z) / 2π, v = acos(y) / π.

use crate::util::luminance;
use glam::{Mat3, Vec3};
use std::f32::consts::PI;
use std::path::{Path, PathBuf};

/// What is wrong with an environment map, naming the file.
#[derive(Debug, thiserror::Error)]
pub enum EnvironmentError {
    /// The file could not be read, is not an HDR image, or holds an image no environment map
    /// can be (not 2:1, a texel not finite or negative).
    #[error("environment map {path}: {message}")]
    Invalid {
        /// The file (or what the texels came from).
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

fn invalid(path: &Path, message: impl Into<String>) -> EnvironmentError {
    EnvironmentError::Invalid { path: path.to_path_buf(), message: message.into() }
}

/// An equirectangular environment map in linear RGB radiance.
#[derive(Debug, Clone)]
pub struct Environment {
    width: usize,
    height: usize,
    /// Row-major, top row first.
    texels: Vec<[f32; 3]>,
    /// Scales every texel's radiance.
    pub intensity: f32,
    /// Turns the map about +Y by this many radians (counter-clockwise seen from above).
    pub rotation: f32,
}

/// Nine spherical-harmonic coefficients per colour channel, in the order
/// (0,0), (1,-1), (1,0), (1,1), (2,-2), (2,-1), (2,0), (2,1), (2,2).
pub type Sh9 = [[f32; 3]; 9];

impl Environment {
    /// An environment map from `width` x `height` linear RGB texels, top row first: a 2:1
    /// image of finite, non-negative radiance.
    pub fn from_texels(width: usize, height: usize, texels: Vec<[f32; 3]>, what: &Path) -> Result<Self, EnvironmentError> {
        if width == 0 || height == 0 || texels.len() != width * height {
            return Err(invalid(what, format!("{width}x{height} with {} texels", texels.len())));
        }
        if width != 2 * height {
            return Err(invalid(what, format!("{width}x{height} is not an equirectangular image (width twice the height)")));
        }
        if let Some(i) = texels.iter().position(|t| t.iter().any(|c| !c.is_finite() || *c < 0.0)) {
            let t = texels[i];
            return Err(invalid(what, format!("texel ({}, {}) is {t:?}: radiance must be finite and not negative", i % width, i / width)));
        }
        Ok(Self { width, height, texels, intensity: 1.0, rotation: 0.0 })
    }

    /// Loads a Radiance HDR or OpenEXR file.
    pub fn load(path: &Path) -> Result<Self, EnvironmentError> {
        let reader = image::ImageReader::open(path).map_err(|e| invalid(path, e.to_string()))?;
        let reader = reader.with_guessed_format().map_err(|e| invalid(path, e.to_string()))?;
        match reader.format() {
            Some(image::ImageFormat::Hdr) | Some(image::ImageFormat::OpenExr) => {}
            Some(other) => return Err(invalid(path, format!("a {other:?} image, not HDR: give a Radiance .hdr or an OpenEXR .exr file"))),
            None => return Err(invalid(path, "not an image format raygraph reads: give a Radiance .hdr or an OpenEXR .exr file")),
        }
        let image = reader.decode().map_err(|e| invalid(path, e.to_string()))?.into_rgb32f();
        let (width, height) = (image.width() as usize, image.height() as usize);
        let texels = image.pixels().map(|p| p.0).collect();
        Self::from_texels(width, height, texels, path)
    }

    /// The image's size in texels.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// The texels (linear RGB, without the intensity), row-major, top row first.
    pub fn texels(&self) -> &[[f32; 3]] {
        &self.texels
    }

    /// The map prefiltered for glossy reflections by the split-sum approximation (Karis 2013):
    /// level k of `levels` (at most the mip chain's length) holds, at mip k's size, the GGX
    /// lobe of roughness k / (levels - 1) around each texel's direction (normal = view =
    /// reflection) averaged over the map with the cosine weight; level 0 is the map. Each
    /// texel takes 64 lobe directions (Hammersley points), each read from the mip level whose
    /// texels match its share of the lobe's solid angle (filtered importance sampling), so the
    /// result has no sampling noise to speak of.
    pub fn specular_chain(&self, levels: usize) -> Vec<Environment> {
        use rayon::prelude::*;
        let chain = self.mip_chain();
        let levels = levels.clamp(1, chain.len());
        let mut out = vec![self.clone()];
        for k in 1..levels {
            let roughness = k as f32 / (levels - 1).max(1) as f32;
            let (width, height) = chain[k].size();
            let texels = (0..width * height)
                .into_par_iter()
                .map(|i| {
                    let n = uv_direction(((i % width) as f32 + 0.5) / width as f32, ((i / width) as f32 + 0.5) / height as f32);
                    prefiltered_texel(&chain, n, roughness).to_array()
                })
                .collect();
            out.push(Environment { width, height, texels, intensity: self.intensity, rotation: self.rotation });
        }
        out
    }

    /// The map's mip chain: the map, then each level the 2x2 blocks of the one before
    /// averaged, while the height halves evenly (a 1024 x 512 map: down to 2 x 1).
    pub fn mip_chain(&self) -> Vec<Environment> {
        let mut levels = vec![self.clone()];
        let mut factor = 2;
        while self.height.is_multiple_of(factor) {
            levels.push(self.downsampled(factor));
            factor *= 2;
        }
        levels
    }

    /// The radiance arriving from world direction `dir` (nearest texel), times the intensity.
    pub fn radiance(&self, dir: Vec3) -> Vec3 {
        let (texel, _) = texel_of(dir, self.rotation, self.width, self.height);
        Vec3::from(self.texels[texel]) * self.intensity
    }

    /// Every texel's world direction (its centre), radiance (times the intensity) and solid
    /// angle.
    fn texels_with_directions(&self) -> impl Iterator<Item = (Vec3, Vec3, f32)> + '_ {
        let d_theta = PI / self.height as f32;
        let d_phi = 2.0 * PI / self.width as f32;
        self.texels.iter().enumerate().map(move |(i, t)| {
            let (x, y) = (i % self.width, i / self.width);
            let u = (x as f32 + 0.5) / self.width as f32;
            let v = (y as f32 + 0.5) / self.height as f32;
            let solid_angle = d_phi * d_theta * (v * PI).sin();
            (rotate_about_y(uv_direction(u, v), self.rotation), Vec3::from(*t) * self.intensity, solid_angle)
        })
    }

    /// The radiance projected on the first nine real spherical harmonics (world directions).
    pub fn radiance_sh(&self) -> Sh9 {
        let mut sh = [[0.0f64; 3]; 9];
        for (dir, radiance, solid_angle) in self.texels_with_directions() {
            for (k, y) in sh_basis(dir).into_iter().enumerate() {
                for c in 0..3 {
                    sh[k][c] += (radiance[c] * y * solid_angle) as f64;
                }
            }
        }
        sh.map(|k| k.map(|c| c as f32))
    }

    /// The irradiance's spherical-harmonic coefficients: the radiance's convolved with the
    /// clamped cosine (band 0 by π, band 1 by 2π/3, band 2 by π/4), so that
    /// [`sh_evaluate`] of them at a normal is the irradiance there.
    pub fn irradiance_sh(&self) -> Sh9 {
        const BAND: [f32; 9] = [PI, 2.0 * PI / 3.0, 2.0 * PI / 3.0, 2.0 * PI / 3.0, PI / 4.0, PI / 4.0, PI / 4.0, PI / 4.0, PI / 4.0];
        let mut sh = self.radiance_sh();
        for (k, coefficient) in sh.iter_mut().enumerate() {
            *coefficient = coefficient.map(|c| c * BAND[k]);
        }
        sh
    }

    /// The irradiance at a surface of normal `n`, summed over every texel (the reference the
    /// spherical harmonics approximate).
    pub fn irradiance_exact(&self, n: Vec3) -> Vec3 {
        let n = n.normalize_or(Vec3::Y);
        let mut sum = [0.0f64; 3];
        for (dir, radiance, solid_angle) in self.texels_with_directions() {
            let w = (n.dot(dir).max(0.0) * solid_angle) as f64;
            for c in 0..3 {
                sum[c] += radiance[c] as f64 * w;
            }
        }
        Vec3::new(sum[0] as f32, sum[1] as f32, sum[2] as f32)
    }
}

/// `d` turned by `angle` radians about +Y (counter-clockwise seen from above).
fn rotate_about_y(d: Vec3, angle: f32) -> Vec3 {
    Mat3::from_rotation_y(angle) * d
}

/// The texel of a `width` x `height` map turned by `rotation` that world direction `dir` (any
/// length) falls in, row-major, and the direction's v.
fn texel_of(dir: Vec3, rotation: f32, width: usize, height: usize) -> (usize, f32) {
    let (u, v) = direction_uv(rotate_about_y(dir.normalize_or(Vec3::Y), -rotation));
    let x = ((u * width as f32) as usize).min(width - 1);
    let y = ((v * height as f32) as usize).min(height - 1);
    (y * width + x, v)
}

/// The irradiance at every normal, tabulated at the centres of a `width` x `width / 2`
/// equirectangular grid of normals (world directions, this module's (u, v) convention) and
/// read bilinearly: what the clamped cosine makes of the map is smooth, so a small grid holds
/// it (tests/environment.rs measures the error), where nine spherical harmonics lose a sun or
/// a studio's lamps.
#[derive(Debug, Clone)]
pub struct IrradianceMap {
    width: usize,
    height: usize,
    texels: Vec<Vec3>,
}

impl IrradianceMap {
    /// The grid's size (columns, rows).
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// The irradiance at the grid's normals, row-major, top row (looking up) first.
    pub fn texels(&self) -> &[Vec3] {
        &self.texels
    }

    /// The irradiance at a surface of normal `n` (any length), interpolated.
    pub fn irradiance(&self, n: Vec3) -> Vec3 {
        let (u, v) = direction_uv(n.normalize_or(Vec3::Y));
        let x = u * self.width as f32 - 0.5;
        let y = (v * self.height as f32 - 0.5).clamp(0.0, (self.height - 1) as f32);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let at = |i: f32, j: f32| {
            let column = (i as i64).rem_euclid(self.width as i64) as usize;
            let row = (j as usize).min(self.height - 1);
            self.texels[row * self.width + column]
        };
        let top = at(x0, y0).lerp(at(x0 + 1.0, y0), fx);
        let bottom = at(x0, y0 + 1.0).lerp(at(x0 + 1.0, y0 + 1.0), fx);
        top.lerp(bottom, fy)
    }
}

impl Environment {
    /// A copy with each `factor` x `factor` block of texels averaged into one (`factor` a
    /// divisor of the height).
    fn downsampled(&self, factor: usize) -> Environment {
        let (width, height) = (self.width / factor, self.height / factor);
        let mut texels = vec![[0.0f32; 3]; width * height];
        for (i, t) in self.texels.iter().enumerate() {
            let (x, y) = (i % self.width / factor, i / self.width / factor);
            for c in 0..3 {
                texels[y * width + x][c] += t[c] / (factor * factor) as f32;
            }
        }
        Environment { width, height, texels, intensity: self.intensity, rotation: self.rotation }
    }

    /// The irradiance tabulated on a `width` x `width / 2` grid of normals, each summed over
    /// the map averaged down to at most 256 x 128 texels.
    pub fn irradiance_map(&self, width: usize) -> IrradianceMap {
        let height = (width / 2).max(1);
        let mut factor = 1;
        while self.height / factor > 128 && self.height.is_multiple_of(2 * factor) {
            factor *= 2;
        }
        let source: Vec<(Vec3, Vec3, f32)> = self.downsampled(factor).texels_with_directions().collect();
        let texels = (0..width * height)
            .map(|i| {
                let n = uv_direction(((i % width) as f32 + 0.5) / width as f32, ((i / width) as f32 + 0.5) / height as f32);
                source.iter().map(|(dir, radiance, solid_angle)| *radiance * (n.dot(*dir).max(0.0) * solid_angle)).sum()
            })
            .collect();
        IrradianceMap { width, height, texels }
    }
}

/// Lobe directions per prefiltered texel ([`Environment::specular_chain`]).
const PREFILTER_SAMPLES: u32 = 64;

/// The GGX lobe of `roughness` about unit direction `n` (the map's frame; normal = view) over
/// `chain` (a mip chain), cosine-weighted, without the intensity.
fn prefiltered_texel(chain: &[Environment], n: Vec3, roughness: f32) -> Vec3 {
    let a2 = (roughness * roughness).powi(2).max(1e-8);
    let (t, b) = n.any_orthonormal_pair();
    let base_texel_solid_angle = 4.0 * PI / (chain[0].width * chain[0].height) as f32;
    let mut sum = Vec3::ZERO;
    let mut weight = 0.0;
    for i in 0..PREFILTER_SAMPLES {
        let (u1, u2) = ((i as f32 + 0.5) / PREFILTER_SAMPLES as f32, i.reverse_bits() as f32 / 4_294_967_296.0);
        let cos_h = ((1.0 - u2) / (1.0 + (a2 - 1.0) * u2)).sqrt();
        let sin_h = (1.0 - cos_h * cos_h).max(0.0).sqrt();
        let phi = 2.0 * PI * u1;
        let h = t * (sin_h * phi.cos()) + b * (sin_h * phi.sin()) + n * cos_h;
        let l = 2.0 * n.dot(h) * h - n;
        let n_l = n.dot(l);
        if n_l <= 0.0 {
            continue;
        }
        // The lobe's density of l (D / 4 where view = normal) and the solid angle it stands for.
        let d = a2 / (PI * (cos_h * cos_h * (a2 - 1.0) + 1.0).powi(2));
        let sample_solid_angle = 1.0 / (PREFILTER_SAMPLES as f32 * d / 4.0);
        let level = (0.5 * (sample_solid_angle / base_texel_solid_angle).log2()).clamp(0.0, (chain.len() - 1) as f32);
        let source = &chain[level.round() as usize];
        let (texel, _) = texel_of(l, 0.0, source.width, source.height);
        sum += Vec3::from(source.texels[texel]) * n_l;
        weight += n_l;
    }
    if weight > 0.0 {
        sum / weight
    } else {
        Vec3::ZERO
    }
}

/// (u, v) in [0, 1] of a unit direction in the map's frame.
fn direction_uv(d: Vec3) -> (f32, f32) {
    let u = 0.5 + d.x.atan2(-d.z) / (2.0 * PI);
    // atan2 rather than acos: exact near the poles too.
    let v = Vec3::new(d.x, 0.0, d.z).length().atan2(d.y) / PI;
    (u.rem_euclid(1.0), v)
}

/// The unit direction in the map's frame of (u, v).
fn uv_direction(u: f32, v: f32) -> Vec3 {
    let (phi, theta) = ((u - 0.5) * 2.0 * PI, v * PI);
    Vec3::new(theta.sin() * phi.sin(), theta.cos(), -theta.sin() * phi.cos())
}

/// The first nine real spherical harmonics at unit direction `d`.
pub fn sh_basis(d: Vec3) -> [f32; 9] {
    let (x, y, z) = (d.x, d.y, d.z);
    [
        0.282_095,
        0.488_603 * y,
        0.488_603 * z,
        0.488_603 * x,
        1.092_548 * x * y,
        1.092_548 * y * z,
        0.315_392 * (3.0 * z * z - 1.0),
        1.092_548 * x * z,
        0.546_274 * (x * x - y * y),
    ]
}

/// The function of coefficients `sh` at unit direction `d`.
pub fn sh_evaluate(sh: &Sh9, d: Vec3) -> Vec3 {
    let basis = sh_basis(d.normalize_or(Vec3::Y));
    let mut sum = Vec3::ZERO;
    for (k, y) in basis.into_iter().enumerate() {
        sum += Vec3::from(sh[k]) * y;
    }
    sum
}

/// Draws directions from an environment map in proportion to its radiance (luminance) times
/// each texel's solid angle: Vose's alias table picks a texel, a uniform point of it in (u, v)
/// gives the direction. Texels of zero radiance are never drawn.
#[derive(Debug, Clone)]
pub struct EnvironmentSampler {
    /// Per texel: the probability of keeping it in its alias slot, and its alias.
    slots: Vec<(f32, u32)>,
    /// Per texel: its probability of being drawn.
    probability: Vec<f32>,
    width: usize,
    height: usize,
    rotation: f32,
}

impl EnvironmentSampler {
    /// The sampler of `env`; `None` where the map is black.
    pub fn new(env: &Environment) -> Option<Self> {
        let weights: Vec<f64> = env.texels_with_directions().map(|(_, radiance, solid_angle)| (luminance(radiance.into()) * solid_angle) as f64).collect();
        let total: f64 = weights.iter().sum();
        if total.is_nan() || total <= 0.0 {
            return None;
        }
        let probability: Vec<f32> = weights.iter().map(|w| (w / total) as f32).collect();
        Some(Self { slots: alias_table(&weights, total), probability, width: env.width, height: env.height, rotation: env.rotation })
    }

    /// A world direction drawn from three uniform numbers in [0, 1), and its probability
    /// density per steradian.
    pub fn sample(&self, u: [f32; 3]) -> (Vec3, f32) {
        let n = self.slots.len();
        let slot = ((u[0] * n as f32) as usize).min(n - 1);
        // The slot or its alias by the second number, which is then stretched back over [0, 1)
        // for the point's u (the first keeps too few bits under a slot of half a million).
        let (keep, alias) = self.slots[slot];
        let (texel, along) = if u[1] < keep { (slot, u[1] / keep) } else { (alias as usize, (u[1] - keep) / (1.0 - keep)) };
        let (x, y) = (texel % self.width, texel / self.width);
        let uv_u = (x as f32 + along.min(1.0 - f32::EPSILON)) / self.width as f32;
        let uv_v = ((y as f32 + u[2]) / self.height as f32).min(1.0);
        (rotate_about_y(uv_direction(uv_u, uv_v), self.rotation), self.density(texel, uv_v))
    }

    /// The table as the GPU reads it (`scene_environment_table`, common/environment_sampling.wgsl):
    /// per texel, the probability of keeping its slot (f32 bits), its alias, and its own
    /// probability of being drawn (f32 bits).
    pub fn gpu_slots(&self) -> Vec<[u32; 4]> {
        self.slots.iter().zip(&self.probability).map(|((keep, alias), p)| [keep.to_bits(), *alias, p.to_bits(), 0]).collect()
    }

    /// The probability density per steradian of drawing world direction `dir`.
    pub fn pdf(&self, dir: Vec3) -> f32 {
        let (texel, v) = texel_of(dir, self.rotation, self.width, self.height);
        self.density(texel, v)
    }

    /// Texel `texel`'s probability spread uniformly over its (u, v) rectangle, per steradian
    /// at polar position `v` (the rectangle's solid angle per unit of u and v is 2π² sin θ).
    fn density(&self, texel: usize, v: f32) -> f32 {
        let sin_theta = (v * PI).sin();
        if sin_theta <= 0.0 {
            return 0.0;
        }
        self.probability[texel] * (self.width * self.height) as f32 / (2.0 * PI * PI * sin_theta)
    }
}

/// Vose's alias table of `weights` (summing to `total`): per slot, the probability of keeping
/// it and the slot taken otherwise.
fn alias_table(weights: &[f64], total: f64) -> Vec<(f32, u32)> {
    let n = weights.len();
    let mut scaled: Vec<f64> = weights.iter().map(|w| w * n as f64 / total).collect();
    let mut slots = vec![(1.0f32, 0u32); n];
    let (mut small, mut large): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| scaled[i] < 1.0);
    while let (Some(s), Some(&l)) = (small.pop(), large.last()) {
        slots[s] = (scaled[s] as f32, l as u32);
        scaled[l] -= 1.0 - scaled[s];
        if scaled[l] < 1.0 {
            large.pop();
            small.push(l);
        }
    }
    // What is left (rounding) keeps its own slot.
    for i in small.into_iter().chain(large) {
        slots[i] = (1.0, i as u32);
    }
    slots
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `width` x `width / 2` map whose texel looking along `dir` has `radiance(dir)`.
    fn map(width: usize, radiance: impl Fn(Vec3) -> [f32; 3]) -> Environment {
        let height = width / 2;
        let texels = (0..width * height)
            .map(|i| radiance(uv_direction(((i % width) as f32 + 0.5) / width as f32, ((i / width) as f32 + 0.5) / height as f32)))
            .collect();
        Environment::from_texels(width, height, texels, Path::new("test")).unwrap()
    }

    const NORMALS: [Vec3; 7] = [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z, Vec3::new(0.48, 0.6, 0.64)];

    #[test]
    fn directions_and_texels_agree() {
        for (u, v) in [(0.5, 0.5), (0.75, 0.25), (0.1, 0.9), (0.3, 0.01)] {
            let (u2, v2) = direction_uv(uv_direction(u, v));
            assert!((u - u2).abs() < 1e-5 && (v - v2).abs() < 1e-5, "({u}, {v}) -> ({u2}, {v2})");
        }
        // The centre looks along -Z, a quarter to the right along +X, the top row up.
        assert!(uv_direction(0.5, 0.5).distance(Vec3::NEG_Z) < 1e-5);
        assert!(uv_direction(0.75, 0.5).distance(Vec3::X) < 1e-5);
        assert!(uv_direction(0.5, 0.0).distance(Vec3::Y) < 1e-5);
    }

    #[test]
    fn a_constant_sky_gives_pi_times_its_radiance_at_every_normal() {
        // Within 1e-3 of it: the texels sum the sphere by the midpoint rule over 64 rows
        // (measured: 4e-4 for the irradiance along +Y).
        let env = map(128, |_| [0.5, 1.0, 2.0]);
        let sh = env.irradiance_sh();
        let expected = Vec3::new(0.5, 1.0, 2.0) * PI;
        for n in NORMALS {
            let (e, exact) = (sh_evaluate(&sh, n), env.irradiance_exact(n));
            assert!(e.distance(expected) < 1e-3 * expected.length() && exact.distance(expected) < 1e-3 * expected.length(), "{n}: SH {e}, sum {exact}");
        }
    }

    #[test]
    fn a_bright_upper_hemisphere_gives_the_closed_form_irradiance() {
        // Radiance 1 from above the horizon, 0 below: E(n) = π (1 + n.y) / 2. Its projection
        // has no band-2 part, so nine coefficients hold it up to the texels' discretisation.
        let env = map(256, |d| if d.y > 0.0 { [1.0; 3] } else { [0.0; 3] });
        let sh = env.irradiance_sh();
        for n in NORMALS {
            let closed = PI * (1.0 + n.normalize().y) / 2.0;
            let (e, exact) = (sh_evaluate(&sh, n).x, env.irradiance_exact(n).x);
            assert!((e - closed).abs() < 5e-3 && (exact - closed).abs() < 5e-3, "{n}: SH {e}, sum {exact}, closed form {closed}");
        }
    }

    #[test]
    fn the_rotation_turns_the_map_about_up() {
        // A bright patch along -Z turned by 90 degrees counter-clockwise seen from above lies
        // along -X.
        let mut env = map(64, |d| if d.dot(Vec3::NEG_Z) > 0.95 { [10.0; 3] } else { [0.0; 3] });
        env.rotation = 0.5 * PI;
        assert_eq!(env.radiance(Vec3::NEG_X), Vec3::splat(10.0));
        assert_eq!(env.radiance(Vec3::NEG_Z), Vec3::ZERO);
        assert!(env.irradiance_exact(Vec3::NEG_X).x > 0.1 && env.irradiance_exact(Vec3::X).x == 0.0);
        env.intensity = 2.0;
        assert_eq!(env.radiance(Vec3::NEG_X), Vec3::splat(20.0));
    }

    #[test]
    fn the_sampler_draws_by_radiance_and_its_density_integrates_to_one() {
        let mut env = map(64, |d| if d.dot(Vec3::new(0.6, 0.8, 0.0)) > 0.9 { [50.0; 3] } else { [0.2, 0.3, 0.4] });
        env.rotation = 0.7;
        let sampler = EnvironmentSampler::new(&env).unwrap();
        let integral: f32 = env.texels_with_directions().map(|(d, _, solid_angle)| sampler.pdf(d) * solid_angle).sum();
        assert!((integral - 1.0).abs() < 1e-3, "the density integrates to {integral}");
        // Irradiance at a few normals, estimated from the sampler's directions, against the
        // sum over the texels: within 4 standard errors.
        let mut state = 0x1234_5678u32;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            (state >> 8) as f32 / (1u32 << 24) as f32
        };
        for n in [Vec3::Y, Vec3::X, Vec3::new(0.48, 0.6, 0.64)] {
            let samples: Vec<f32> = (0..20_000)
                .map(|_| {
                    let (d, pdf) = sampler.sample([next(), next(), next()]);
                    assert!((sampler.pdf(d) - pdf).abs() <= 1e-3 * pdf, "the density of {d}: drawn {pdf}, looked up {}", sampler.pdf(d));
                    env.radiance(d).x * n.dot(d).max(0.0) / pdf
                })
                .collect();
            let mean = samples.iter().sum::<f32>() / samples.len() as f32;
            let var = samples.iter().map(|s| (s - mean).powi(2)).sum::<f32>() / (samples.len() - 1) as f32;
            let exact = env.irradiance_exact(n).x;
            assert!((mean - exact).abs() <= 4.0 * (var / samples.len() as f32).sqrt() + 1e-4, "{n}: {mean} against {exact}");
        }
    }

    #[test]
    fn the_specular_chain_of_a_constant_sky_is_that_sky_at_every_roughness() {
        let env = map(64, |_| [0.5, 1.0, 2.0]);
        let chain = env.specular_chain(6);
        assert_eq!(chain.len(), 6);
        for (k, level) in chain.iter().enumerate() {
            assert_eq!(level.size(), (64 >> k, 32 >> k));
            for t in level.texels() {
                assert!((t[0] - 0.5).abs() < 1e-5 && (t[1] - 1.0).abs() < 1e-5 && (t[2] - 2.0).abs() < 1e-5, "level {k}: {t:?}");
            }
        }
        // A sky bright above the horizon only: rough levels blur the horizon's step, smooth
        // ones keep it, and straight up stays bright at every roughness.
        let step = map(256, |d| if d.y > 0.0 { [1.0; 3] } else { [0.0; 3] }).specular_chain(6);
        let at = |level: &Environment, d: Vec3| Vec3::from(level.texels()[texel_of(d, 0.0, level.width, level.height).0]);
        let near_horizon = Vec3::new(0.0, 0.1, -1.0).normalize();
        assert!(at(&step[1], near_horizon).x > at(&step[5], near_horizon).x, "rougher lobes reach further below the horizon");
        for (k, level) in step.iter().enumerate() {
            println!("level {k}: straight up {}, near the horizon {}", at(level, Vec3::Y).x, at(level, near_horizon).x);
        }
        // Straight up every lobe direction lies above the horizon: 1, but for the coarsest
        // levels' texels (8 x 4 at roughness 1: the top row's centre is 22.5 degrees from up,
        // measured 0.951; 0.996 at 16 x 8).
        for (k, level) in step.iter().enumerate() {
            let bound = if k == step.len() - 1 { 0.95 } else { 0.99 };
            assert!(at(level, Vec3::Y).x > bound, "level {k}, straight up: {}", at(level, Vec3::Y).x);
        }
    }

    #[test]
    fn a_black_map_has_no_sampler_and_bad_texels_are_refused() {
        assert!(EnvironmentSampler::new(&map(16, |_| [0.0; 3])).is_none());
        let e = Environment::from_texels(
            4,
            2,
            vec![[0.0; 3], [f32::NAN, 0.0, 0.0], [0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3]],
            Path::new("x.hdr"),
        );
        let message = e.unwrap_err().to_string();
        assert!(message.contains("x.hdr") && message.contains("texel (1, 0)"), "{message}");
        let e = Environment::from_texels(4, 4, vec![[0.0; 3]; 16], Path::new("square.hdr")).unwrap_err().to_string();
        assert!(e.contains("square.hdr") && e.contains("equirectangular"), "{e}");
    }
}
