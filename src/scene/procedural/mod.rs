//! Deterministic procedural stand-ins for the three benchmark scenes of "Hybrid Raytracing in
//! DXR" (Table 1): a textured box ([`box_scene`], 12 triangles), a closed organic head-like
//! mesh ([`organic`], 3,920 triangles) and a Sponza-like courtyard ([`atrium`], about
//! 262,500 triangles in 103 meshes with 69 textures).
//!
//! Two animated variants serve `raygraph bench anim` ([`animated`]): `organic-skinned` and
//! `atrium-moving`. The Cornell box ([`cornell`]) is the scene of comparisons with outside
//! renderers; `atrium-lights` ([`atrium_lights`]) the many-lights scene.
//!
//! This file owns the scene registry ([`by_name`], [`NAMES`]); `common` the machinery the
//! scenes share. Every generator is a pure function of its arguments: the same call gives the
//! same bytes.

pub mod animated;
mod atrium;
mod atrium_lights;
mod box_scene;
mod common;
mod cornell;
mod organic;

use super::Scene;

/// The seed [`atrium`] is generated from by default.
pub const ATRIUM_DEFAULT_SEED: u64 = 1;

/// The names [`by_name`] accepts.
pub const NAMES: &[&str] = &["box", "organic", "atrium", "organic-skinned", "atrium-moving", "cornell", "atrium-lights"];

/// Point lights of [`atrium_lights`].
pub const ATRIUM_LIGHT_COUNT: usize = atrium_lights::LIGHT_COUNT;

/// The emitted radiance of the Cornell box's light quad (linear RGB, Mitsuba's `cbox`).
pub const CORNELL_LIGHT_RADIANCE: [f32; 3] = cornell::LIGHT_RADIANCE;

/// A cube with two textures (base colour and a roughness map): 12 triangles, 1 mesh.
pub fn box_scene() -> Scene {
    box_scene::build()
}

/// One closed, watertight head-like mesh with eye sockets, ears and a mouth: 3,920 triangles.
pub fn organic() -> Scene {
    organic::build()
}

/// A Sponza-like courtyard with two storeys of arcades, hanging cloth and an open roof,
/// generated from `seed` (the mesh, texture and triangle counts do not depend on the seed).
pub fn atrium(seed: u64) -> Scene {
    atrium::build(seed)
}

/// The atrium of `seed` at night: [`ATRIUM_LIGHT_COUNT`] coloured point lights and twenty
/// lanterns whose brass glows (emissive triangles), the sun off and the sky faint.
pub fn atrium_lights(seed: u64) -> Scene {
    atrium_lights::build(seed)
}

/// The Cornell box: five walls (red left, green right), two white blocks and an emissive light
/// quad below the ceiling, Lambert materials, no sun and no sky: 32 triangles.
pub fn cornell() -> Scene {
    cornell::build()
}

/// The procedural scene called `name` (one of [`NAMES`]); the atrium uses
/// [`ATRIUM_DEFAULT_SEED`].
pub fn by_name(name: &str) -> Option<Scene> {
    match name {
        "box" => Some(box_scene()),
        "organic" => Some(organic()),
        "atrium" => Some(atrium(ATRIUM_DEFAULT_SEED)),
        "organic-skinned" => Some(animated::organic_skinned()),
        "atrium-moving" => Some(animated::atrium_moving(ATRIUM_DEFAULT_SEED)),
        "cornell" => Some(cornell()),
        "atrium-lights" => Some(atrium_lights(ATRIUM_DEFAULT_SEED)),
        _ => None,
    }
}
