//! The scene's lights as the GPU reads them: one record per light (`scene_lights`) and the
//! raster mode's shadow slots, the view-projections the `shadow_map` layer draws through: the
//! first four directional or spot lights a map each, the two most powerful point lights a cube
//! map's six faces each.

use crate::scene::{LightKind, PunctualLight};
use crate::uniforms::{LightUniforms, CUBE_SHADOW_MAPS, LIGHT_DIRECTIONAL, LIGHT_POINT, LIGHT_SPOT, SHADOW_MAP_SLOTS, SHADOW_SLOTS};
use glam::{Mat4, Vec3};

/// The GPU form of a scene's lights: one record per light and the view-projection of each
/// raster shadow slot in use.
#[derive(Debug, Clone, Default)]
pub(crate) struct LightRecords {
    /// One record per light.
    pub(crate) records: Vec<LightUniforms>,
    /// The view-projection of each shadow slot (identity where unused).
    pub(crate) shadow_view_proj: [Mat4; SHADOW_SLOTS],
    /// The slots in use: bit `slot` set where a light has it.
    pub(crate) shadow_slots: u32,
    /// Lights without a shadow map in raster mode: directional or spot lights beyond the
    /// `SHADOW_MAP_SLOTS` first, point lights but the `CUBE_SHADOW_MAPS` most powerful.
    pub(crate) unshadowed_in_raster: usize,
}

/// The shadow slots of a scene's lights: the first `SHADOW_MAP_SLOTS` directional or spot
/// lights one each, in order; the `CUBE_SHADOW_MAPS` most powerful point lights (intensity
/// times the colour's largest channel; the earlier of two equal) a cube map's six, the cube
/// maps in the lights' order.
struct ShadowSlots {
    maps: usize,
    /// The indices of the point lights with a cube map, in order.
    cube_lights: Vec<usize>,
}

impl ShadowSlots {
    fn new(lights: &[PunctualLight]) -> Self {
        let mut points: Vec<usize> = (0..lights.len()).filter(|&i| matches!(lights[i].kind, LightKind::Point { .. })).collect();
        let power = |i: usize| lights[i].intensity * lights[i].color.max_element();
        // A stable sort: equal powers keep the file's order.
        points.sort_by(|&a, &b| power(b).total_cmp(&power(a)));
        points.truncate(CUBE_SHADOW_MAPS);
        points.sort_unstable();
        Self { maps: 0, cube_lights: points }
    }

    /// The first slot of light `i`'s shadow map and its view-projections, if it has one.
    fn take(&mut self, i: usize, light: &PunctualLight, direction: Vec3, center: Vec3, radius: f32) -> Option<(usize, Vec<Mat4>, f32)> {
        if let LightKind::Point { range } = light.kind {
            let cube = self.cube_lights.iter().position(|&c| c == i)?;
            let (faces, depth_range) = cube_projections(light.position, range, center, radius);
            return Some((SHADOW_MAP_SLOTS + 6 * cube, faces.to_vec(), depth_range));
        }
        if self.maps == SHADOW_MAP_SLOTS {
            return None;
        }
        let (view_proj, depth_range) = shadow_projection(light, direction, center, radius)?;
        self.maps += 1;
        Some((self.maps - 1, vec![view_proj], depth_range))
    }
}

/// Records of `lights` for a scene inside the sphere (`center`, `radius`), with their raster
/// shadow slots ([`ShadowSlots`]): directional, an orthographic projection along the light
/// over the scene's sphere; spot, a perspective projection over its outer cone from its
/// position to the far side of the sphere (or its range); point, a cube map
/// ([`cube_projections`]).
pub(crate) fn light_records(lights: &[PunctualLight], center: Vec3, radius: f32) -> LightRecords {
    let mut out = LightRecords { shadow_view_proj: [Mat4::IDENTITY; SHADOW_SLOTS], ..Default::default() };
    let mut slots = ShadowSlots::new(lights);
    for (i, light) in lights.iter().enumerate() {
        let direction = light.direction.try_normalize().unwrap_or(Vec3::NEG_Y);
        let (kind, range, cos_inner, cos_outer) = match light.kind {
            LightKind::Directional => (LIGHT_DIRECTIONAL, None, 1.0, 1.0),
            LightKind::Point { range } => (LIGHT_POINT, range, -1.0, -1.0),
            LightKind::Spot { range, inner_cone, outer_cone } => (LIGHT_SPOT, range, inner_cone.cos(), outer_cone.cos()),
        };
        let (shadow_map, shadow_depth_range) = match slots.take(i, light, direction, center, radius) {
            Some((first, view_projs, depth_range)) => {
                for (k, m) in view_projs.into_iter().enumerate() {
                    out.shadow_view_proj[first + k] = m;
                    out.shadow_slots |= 1 << (first + k);
                }
                (first as i32, depth_range)
            }
            None => {
                out.unshadowed_in_raster += 1;
                (-1, 0.0)
            }
        };
        out.records.push(LightUniforms {
            position: light.position.into(),
            kind,
            direction: direction.into(),
            range: range.filter(|r| r.is_finite() && *r > 0.0).unwrap_or(0.0),
            radiance: (light.color * light.intensity).into(),
            cos_inner,
            cos_outer,
            shadow_map,
            shadow_depth_range,
            _pad: 0,
        });
    }
    out
}

/// How far past 90 degrees a cube face's frustum reaches: the tangent of its half angle is
/// 1 + this. The face a shading point falls in is chosen by its major axis, so its
/// percentage-closer taps (at most 4 texels out, `forward` layer's `pcf`) stay inside the
/// face's own map down to 512-texel faces (8 texels of margin at 1024).
const CUBE_FACE_MARGIN: f32 = 1.0 / 64.0;

/// The six view-projections of a point light's cube shadow map at `position` (faces +x, -x,
/// +y, -y, +z, -z, each a perspective projection a little wider than 90 degrees,
/// [`CUBE_FACE_MARGIN`]) out to the far side of the scene's sphere (or the light's range),
/// and the world length of their depth range.
pub(crate) fn cube_projections(position: Vec3, range: Option<f32>, center: Vec3, radius: f32) -> ([Mat4; 6], f32) {
    let far = ((center - position).length() + radius).min(range.unwrap_or(f32::INFINITY)).max(radius * 1e-3);
    let near = far * 1e-3;
    let fov = 2.0 * (1.0 + CUBE_FACE_MARGIN).atan();
    let projection = Mat4::perspective_rh(fov, 1.0, near, far);
    let faces = [
        (Vec3::X, Vec3::NEG_Y),
        (Vec3::NEG_X, Vec3::NEG_Y),
        (Vec3::Y, Vec3::Z),
        (Vec3::NEG_Y, Vec3::NEG_Z),
        (Vec3::Z, Vec3::NEG_Y),
        (Vec3::NEG_Z, Vec3::NEG_Y),
    ];
    (faces.map(|(axis, up)| projection * Mat4::look_at_rh(position, position + axis, up)), far - near)
}

/// A shadow map's view-projection and the world length of its depth range, for a directional
/// or spot light.
fn shadow_projection(light: &PunctualLight, direction: Vec3, center: Vec3, radius: f32) -> Option<(Mat4, f32)> {
    let up = if direction.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    match light.kind {
        LightKind::Directional => {
            let view = Mat4::look_at_rh(center - direction * radius * 2.0, center, up);
            Some((Mat4::orthographic_rh(-radius, radius, -radius, radius, radius * 0.5, radius * 3.5) * view, radius * 3.0))
        }
        LightKind::Spot { range, outer_cone, .. } => {
            let distance = (center - light.position).length();
            let far = (distance + radius).min(range.unwrap_or(f32::INFINITY)).max(radius * 1e-3);
            let near = (distance - radius).max(far * 1e-3);
            let fov = (2.0 * outer_cone).clamp(1f32.to_radians(), 170f32.to_radians());
            let view = Mat4::look_at_rh(light.position, light.position + direction, up);
            Some((Mat4::perspective_rh(fov, 1.0, near, far) * view, far - near))
        }
        LightKind::Point { .. } => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn light(kind: LightKind, position: Vec3) -> PunctualLight {
        PunctualLight { name: String::new(), kind, position, direction: Vec3::NEG_Y, color: Vec3::ONE, intensity: 1.0 }
    }

    #[test]
    fn cubes_go_to_the_two_most_powerful_point_lights_in_the_files_order() {
        let at = |intensity: f32, red: f32| PunctualLight { intensity, color: Vec3::new(red, 0.5, 0.5), ..light(LightKind::Point { range: None }, Vec3::Y) };
        // Powers 2, 8, 1.5 (its largest channel 0.5), 8: the second and the fourth.
        let records = light_records(&[at(2.0, 1.0), at(4.0, 2.0), at(3.0, 0.2), at(8.0, 1.0)], Vec3::ZERO, 4.0);
        let slots: Vec<i32> = records.records.iter().map(|r| r.shadow_map).collect();
        assert_eq!(slots, [-1, 4, -1, 10]);
        assert_eq!(records.unshadowed_in_raster, 2);
    }

    #[test]
    fn maps_go_to_the_first_four_directional_or_spot_lights_and_cubes_to_the_first_two_point_lights() {
        let point = light(LightKind::Point { range: None }, Vec3::new(0.5, 2.0, 0.0));
        let spot = light(LightKind::Spot { range: None, inner_cone: 0.3, outer_cone: 0.5 }, Vec3::new(0.0, 3.0, 0.0));
        let sun = light(LightKind::Directional, Vec3::ZERO);
        let lights = [point.clone(), sun.clone(), point.clone(), spot.clone(), point.clone(), sun.clone(), sun.clone(), spot];
        let records = light_records(&lights, Vec3::ZERO, 4.0);
        let slots: Vec<i32> = records.records.iter().map(|r| r.shadow_map).collect();
        assert_eq!(slots, [4, 0, 10, 1, -1, 2, 3, -1]);
        assert_eq!(records.unshadowed_in_raster, 2);
        assert_eq!(records.shadow_slots, 0xffff, "every slot is in use");
    }

    /// Every direction from the light projects inside the face its major axis picks (the
    /// shader's `shadow_slot_at`), at least the margin's share of the face from its edge, and in
    /// front of the light with a depth inside 0..1 for points between near and far.
    #[test]
    fn a_cube_face_holds_every_direction_of_its_major_axis_with_a_margin() {
        let position = Vec3::new(0.3, 1.0, -0.2);
        let (faces, range) = cube_projections(position, None, Vec3::ZERO, 2.0);
        assert!(range > 0.0);
        let mut worst = 0.0f32;
        for i in 0..2000 {
            // A spread of directions (a Fibonacci sphere).
            let z = 1.0 - 2.0 * (i as f32 + 0.5) / 2000.0;
            let phi = i as f32 * 2.399_963;
            let d = Vec3::new((1.0 - z * z).sqrt() * phi.cos(), z, (1.0 - z * z).sqrt() * phi.sin());
            let a = d.abs();
            let face = if a.x >= a.y && a.x >= a.z {
                if d.x >= 0.0 {
                    0
                } else {
                    1
                }
            } else if a.y >= a.z {
                if d.y >= 0.0 {
                    2
                } else {
                    3
                }
            } else if d.z >= 0.0 {
                4
            } else {
                5
            };
            let c = faces[face] * (position + d * 1.5).extend(1.0);
            let ndc = c.truncate() / c.w;
            assert!(c.w > 0.0 && ndc.z > 0.0 && ndc.z < 1.0, "direction {d:?}: depth {}", ndc.z);
            worst = worst.max(ndc.x.abs()).max(ndc.y.abs());
        }
        let edge = 1.0 / (1.0 + CUBE_FACE_MARGIN);
        assert!(worst <= edge + 1e-5, "a direction reaches {worst} of the face's half width (its own region ends at {edge})");
    }
}
