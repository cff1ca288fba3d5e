//! "atrium-lights": the atrium at night, the many-lights scene. The sun is off and the sky
//! faint; [`LIGHT_COUNT`] coloured point lights hang in a grid over the courtyard and the
//! aisles at heights drawn from the seed, each with a glTF `range`, and the brass of the twenty
//! lanterns under the gallery glows (an emissive factor: its triangles are lights in the
//! ray-traced modes). Shading every light at every pixel does not scale to this; sampling
//! them does.

use super::common::Rng;
use crate::scene::{LightKind, PunctualLight, Scene};
use glam::Vec3;

/// Point lights in the scene: a grid of 64 along the courtyard by 16 across it.
pub const LIGHT_COUNT: usize = 1024;
/// Each light's glTF `range` (metres): its light ends there.
const LIGHT_RANGE: f32 = 4.0;
/// Each light's intensity (candela, times its colour, whose brightest channel is 1).
const LIGHT_INTENSITY: f32 = 0.5;
/// The lanterns' brass glows this warm white (linear radiance).
const LANTERN_EMISSION: [f32; 3] = [4.0, 2.6, 1.1];

/// A saturated colour of hue `h` (0..1), its brightest channel 1.
fn hue(h: f32) -> Vec3 {
    let k = |n: f32| {
        let t = (n + h * 6.0) % 6.0;
        1.0 - (t.min(4.0 - t).clamp(0.0, 1.0))
    };
    Vec3::new(k(5.0), k(3.0), k(1.0)).max(Vec3::splat(0.15))
}

/// The atrium of `seed` at night with [`LIGHT_COUNT`] point lights and glowing lanterns.
pub(super) fn build(seed: u64) -> Scene {
    let mut s = super::atrium(seed);
    s.set_name("atrium-lights");
    s.light_mut().intensity = 0.0;
    s.light_mut().ambient = 0.02;
    for m in s.materials_mut().iter_mut().filter(|m| m.name.starts_with("atrium_brass")) {
        m.emissive = LANTERN_EMISSION;
    }
    let mut rng = Rng::new(seed ^ 0x6c69_6768_7473);
    let (columns, rows) = (64, LIGHT_COUNT / 64);
    *s.lights_mut() = (0..LIGHT_COUNT)
        .map(|i| {
            let (cx, cz) = ((i % columns) as f32 + 0.5, (i / columns) as f32 + 0.5);
            let position = Vec3::new(-14.5 + 29.0 * cx / columns as f32, rng.range(0.4, 10.5), -6.6 + 13.2 * cz / rows as f32);
            PunctualLight {
                name: format!("light {i}"),
                kind: LightKind::Point { range: Some(LIGHT_RANGE) },
                position,
                direction: Vec3::NEG_Y,
                color: hue(rng.range(0.0, 1.0)),
                intensity: LIGHT_INTENSITY,
            }
        })
        .collect();
    s
}
