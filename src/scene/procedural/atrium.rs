//! The "atrium" scene: a Sponza-like courtyard generated from a seed.
//!
//! Layout (metres, y up): the open courtyard runs along x over [-15, 15] and across z over
//! [-3.1, 3.1], with no roof. Along each long side a colonnade of nine columns (x = -12..12,
//! z = ±3.5) carries ten semicircular arches on the ground storey (springing at 4.15 m) and
//! ten on the upper storey (springing at 9.45 m) above a gallery floor at 6.35 m with a
//! balustrade. Behind the arcades are aisles out to the outer walls at z = ±7, spanned by
//! transverse ribs and roofed at 11 m; an attic wall with a cornice and medallions closes the
//! courtyard façade at 12 m. The end walls (x = ±15) carry a door, a rose window and lion
//! masks. Thin single-sided cloth (the thin features) hangs in front of alternate ground
//! arches (curtains), over the gallery balustrade in the other bays (rugs) and in front of the
//! upper columns (banners); a fountain, planted vases, lanterns and benches furnish it. In all:
//! about 262,500 triangles over 468 instances of 103 meshes, 69 textures (64² to 256²).
//!
//! The seed changes shapes (column weathering, cloth folds, plants, vases) and colours, never
//! the structure: every seed gives the same mesh, texture, material and triangle counts.
//! Long-side elements are modelled for the south side (courtyard towards +z) and turned by
//! half a turn about y for the north side; no instance transform mirrors.
//!
//! The layout is data (`layout`: dimensions, storeys, the shell's parts, furniture and views;
//! `surfaces`: the texture recipes), the shapes are `shapes`; this file walks the tables in a
//! fixed order, which fixes the order of the meshes, materials, instances and random draws.

mod layout;
mod shapes;
mod surfaces;

use super::common::{jitter, material, rgb, tex_diamonds, tex_stripes, MeshBuilder, Rgb, Rng};
use crate::scene::{Camera, Instance, Light, Material, Mesh, Scene, TextureImage};
use glam::{Mat4, Vec3};
use layout::{
    at, bay_x, column_x, side, Finish, Shape, ShellPart, Storey, ARCADE_Z, BANNER, BANNER_BORDER, BANNER_TOP, BAY, BAYS, BENCH_BAYS, CLOTH_DYES, CLOTH_Z,
    COLUMNS, COLUMN_VARIANTS, CORNER_VASES, CURTAIN, G_PANEL_T, HALF_X, LANTERNS, MASKS, ROOF_Y0, RUG, SHELL, SLAB_Y0, SLAB_Y1, STOREYS, VASE_COLUMNS, VIEWS,
    WALL_Z,
};
use shapes::{
    arch_panel, archivolt, baluster, bench, bush, cloth, column, curtain_rod, door_frame, door_leaf, fountain_basin, fountain_pedestal, fountain_water,
    lantern, mask, medallion, moulding, pier, rail, rib, rose_glass, rose_tracery, vase, wall_pilaster,
};
use std::f32::consts::FRAC_PI_2;
use surfaces::{
    Palette, Surface, ARCHIVOLT, ATTIC_ASHLAR, BALUSTER, BENCH_WOOD, BRASS, COLUMN_MARBLES, END_WALL, FOLIAGE, FOUNTAIN_BASIN, FOUNTAIN_MARBLE, IRON,
    MEDALLIONS, RAIL, RIB, TERRACOTTA, WALL_PILASTER, WATER,
};

/// A part of the fountain, standing in the middle of the courtyard.
struct FountainPart {
    mesh: &'static str,
    shape: fn() -> MeshBuilder,
    surface: Surface,
}

const FOUNTAIN: [FountainPart; 3] = [
    FountainPart { mesh: "fountain_basin", shape: fountain_basin, surface: FOUNTAIN_BASIN },
    FountainPart { mesh: "fountain_water", shape: fountain_water, surface: WATER },
    FountainPart { mesh: "fountain_pedestal", shape: fountain_pedestal, surface: FOUNTAIN_MARBLE },
];

/// The atrium generated from `seed`.
pub(super) fn build(seed: u64) -> Scene {
    let mut a = Atrium::new(seed);
    for part in &SHELL {
        a.shell_part(part);
    }
    a.columns();
    a.piers();
    a.arcades();
    a.balustrade();
    a.aisle_bays();
    a.benches();
    a.lanterns();
    a.hangings();
    a.end_walls();
    a.medallions();
    a.fountain();
    a.planted_vases();
    a.into_scene()
}

/// The scene being assembled, and the randomness it is drawn from.
struct Atrium {
    meshes: Vec<Mesh>,
    materials: Vec<Material>,
    instances: Vec<Instance>,
    textures: Vec<TextureImage>,
    /// Texture randomness.
    tr: Rng,
    /// Geometry randomness.
    gr: Rng,
    palette: Palette,
}

impl Atrium {
    fn new(seed: u64) -> Self {
        let mut rng = Rng::new(seed ^ 0xA791_0A5E_5EED_0001);
        let mut tr = rng.fork();
        let gr = rng.fork();
        let palette = Palette::draw(&mut tr);
        Self { meshes: Vec::new(), materials: Vec::new(), instances: Vec::new(), textures: Vec::new(), tr, gr, palette }
    }

    /// A texture with its own (untinted) material.
    fn textured(&mut self, tex: TextureImage, roughness: f32) -> usize {
        self.textures.push(tex);
        let t = self.textures.len() - 1;
        let name = self.textures[t].name.clone();
        self.materials.push(material(&name, [1.0, 1.0, 1.0, 1.0], Some(t), roughness));
        self.materials.len() - 1
    }

    /// The material of `surface`, its texture called `name`.
    fn surface_named(&mut self, surface: &Surface, name: &str) -> usize {
        let tex = surface.image(name, &mut self.tr, &self.palette);
        let m = self.textured(tex, surface.roughness);
        self.materials[m].metallic = surface.metallic;
        m
    }

    fn surface(&mut self, surface: &Surface) -> usize {
        self.surface_named(surface, surface.name)
    }

    /// The material made earlier from the surface called `name`.
    fn material(&self, name: &str) -> usize {
        self.materials.iter().position(|m| m.name == name).unwrap_or_else(|| panic!("the atrium's surface `{name}` is made before it is reused"))
    }

    fn mesh(&mut self, b: MeshBuilder, name: &str) -> usize {
        self.meshes.push(b.finish(name));
        self.meshes.len() - 1
    }

    fn put(&mut self, mesh: usize, material: usize, transform: Mat4) {
        self.instances.push(Instance { mesh, material, transform });
    }

    /// One mesh per storey, named `{prefix}_{storey}`.
    fn storey_meshes(&mut self, prefix: &str, shape: impl Fn(&Storey) -> MeshBuilder) -> Vec<usize> {
        STOREYS.iter().map(|st| self.mesh(shape(st), &format!("{prefix}_{}", st.name))).collect()
    }

    fn shell_part(&mut self, part: &ShellPart) {
        let material = match &part.finish {
            Finish::New(surface) => self.surface(surface),
            Finish::Like(name) => self.material(name),
        };
        let b = match part.shape {
            Shape::Floor { origin, eu, ev, cells: [nu, nv], uv_per_m } => {
                let mut b = MeshBuilder::new();
                b.patch(origin, eu, ev, nu, nv, uv_per_m, Vec3::Y);
                b
            }
            Shape::Block { min, max, cell, uv_per_m } => {
                let mut b = MeshBuilder::new();
                b.cuboid(min, max, cell, uv_per_m);
                b
            }
            Shape::Moulding { profile, segments } => moulding(profile, segments),
        };
        let mesh = self.mesh(b, part.mesh);
        for transform in part.placement.transforms() {
            self.put(mesh, material, transform);
        }
    }

    /// The columns of both storeys: six marbles, six variants per storey, used in turn.
    fn columns(&mut self) {
        let marbles: Vec<usize> = COLUMN_MARBLES.iter().map(|s| self.surface(s)).collect();
        let variants: Vec<Vec<usize>> = STOREYS.iter().map(|st| self.column_variants(st)).collect();
        for s in 0..2 {
            for k in 0..COLUMNS {
                let v = (k + 3 * s) % COLUMN_VARIANTS;
                for (st, variants) in STOREYS.iter().zip(&variants) {
                    self.put(variants[v], marbles[st.marbles + v % 3], side(s) * at(column_x(k), st.floor, -ARCADE_Z));
                }
            }
        }
    }

    fn column_variants(&mut self, st: &Storey) -> Vec<usize> {
        (0..COLUMN_VARIANTS)
            .map(|i| {
                let twist = if i == st.twisted_variant { st.twist } else { 0.0 };
                let b = column(&st.column, &mut self.gr, twist);
                self.mesh(b, &format!("column_{}_{i}", st.name))
            })
            .collect()
    }

    /// Engaged piers where the arcades meet the end walls.
    fn piers(&mut self) {
        let m_pier = self.material(ATTIC_ASHLAR.name);
        let piers = self.storey_meshes("pier", |st| pier(st.radius, st.panel_t, st.pier_height));
        for sx in [-1.0f32, 1.0] {
            for sz in [-1.0f32, 1.0] {
                for (st, &mesh) in STOREYS.iter().zip(&piers) {
                    self.put(mesh, m_pier, at(sx * (HALF_X - (BAY / 2.0 - st.radius) / 2.0), st.floor, sz * ARCADE_Z));
                }
            }
        }
    }

    /// The arch walls with their archivolts, in every bay of both storeys.
    fn arcades(&mut self) {
        let arches: Vec<usize> = STOREYS.iter().map(|st| self.surface(&st.arch)).collect();
        let m_volt = self.surface(&ARCHIVOLT);
        let panels = self.storey_meshes("arch_panel", |st| arch_panel(st.radius, st.top - st.spring, st.panel_t, 32, 4));
        let volts = self.storey_meshes("archivolt", |st| archivolt(st.radius, st.panel_t, 28));
        for s in 0..2 {
            for k in 0..BAYS {
                for (i, st) in STOREYS.iter().enumerate() {
                    let t = side(s) * at(bay_x(k), st.spring, -ARCADE_Z);
                    self.put(panels[i], arches[i], t);
                    self.put(volts[i], m_volt, t);
                }
            }
        }
    }

    /// The gallery's balustrade: two rails and four balusters in every bay.
    fn balustrade(&mut self) {
        let m_baluster = self.surface(&BALUSTER);
        let m_rail = self.surface(&RAIL);
        let bal = self.mesh(baluster(0.75, 8), "baluster");
        let rail_low = self.mesh(rail(0.13, 0.15), "rail_low");
        let rail_top = self.mesh(rail(0.15, 0.12), "rail_top");
        for s in 0..2 {
            for k in 0..BAYS {
                let base = side(s) * at(bay_x(k), SLAB_Y1, -ARCADE_Z);
                self.put(rail_low, m_rail, base);
                self.put(rail_top, m_rail, base * at(0.0, 0.9, 0.0));
                for j in 0..4 {
                    self.put(bal, m_baluster, base * at(-0.84 + 0.56 * j as f32, 0.15, 0.0));
                }
            }
        }
    }

    /// The aisles behind the columns: wall pilasters and transverse ribs on both storeys.
    fn aisle_bays(&mut self) {
        let m_wpil = self.surface(&WALL_PILASTER);
        let m_rib = self.surface(&RIB);
        let wpil = self.mesh(wall_pilaster(), "wall_pilaster");
        let ribs = self.storey_meshes("rib", |st| rib(st.rib_span, st.top - st.spring - 0.05, 32));
        for s in 0..2 {
            for k in 0..COLUMNS {
                let x = column_x(k);
                for st in &STOREYS {
                    self.put(wpil, m_wpil, side(s) * at(x, st.floor, -WALL_Z) * Mat4::from_scale(Vec3::new(1.0, st.pilaster_height, 1.0)));
                }
                for (st, &rib) in STOREYS.iter().zip(&ribs) {
                    self.put(rib, m_rib, side(s) * at(x, st.spring, -ARCADE_Z - st.panel_t / 2.0));
                }
            }
        }
    }

    fn benches(&mut self) {
        let m_wood = self.surface(&BENCH_WOOD);
        let bench = self.mesh(bench(), "bench");
        for s in 0..2 {
            for k in BENCH_BAYS {
                self.put(bench, m_wood, side(s) * at(bay_x(k), 0.0, -WALL_Z + 0.45));
            }
        }
    }

    /// Brass lanterns under the gallery (and the iron the curtain rods use).
    fn lanterns(&mut self) {
        self.surface(&IRON);
        let brass = BRASS.map(|s| self.surface(&s));
        let lanterns = LANTERNS.map(|(name, chain)| {
            let b = lantern(&mut self.gr, chain, 12);
            self.mesh(b, name)
        });
        for s in 0..2 {
            for k in 0..BAYS {
                self.put(lanterns[k % 2], brass[k % 2], side(s) * at(bay_x(k), SLAB_Y0, -(ARCADE_Z + WALL_Z) / 2.0));
            }
        }
    }

    /// Cloth: curtains in the odd ground bays, rugs over the balustrade in the others, banners
    /// in front of the upper columns.
    fn hangings(&mut self) {
        let rod = self.mesh(curtain_rod(), "curtain_rod");
        let cloth_materials = self.curtains(rod);
        self.rugs(&cloth_materials);
        self.banners();
    }

    /// Two dyes of [`CLOTH_DYES`], each jittered.
    fn cloth_colours(&mut self) -> (Rgb, Rgb) {
        let (i0, i1) = (self.tr.below(CLOTH_DYES.len()), self.tr.below(CLOTH_DYES.len()));
        let dye = |i: usize| rgb(CLOTH_DYES[i].0, CLOTH_DYES[i].1, CLOTH_DYES[i].2);
        let c0 = jitter(&mut self.tr, dye(i0), 0.08);
        let c1 = jitter(&mut self.tr, dye(i1), 0.08);
        (c0, c1)
    }

    /// A double-sided cloth material.
    fn cloth_material(&mut self, tex: TextureImage) -> usize {
        let m = self.textured(tex, 0.9);
        self.materials[m].double_sided = true;
        m
    }

    /// The curtains, each with its own striped material, and their iron rods; the curtains'
    /// materials.
    fn curtains(&mut self, rod: usize) -> Vec<usize> {
        let m_iron = self.material(IRON.name);
        let mut materials = Vec::new();
        for s in 0..2 {
            for k in (1..BAYS).step_by(2) {
                let n = materials.len();
                let (c0, c1) = self.cloth_colours();
                let bands = 3 + self.tr.below(5) as u32;
                let tex = tex_stripes(&format!("atrium_curtain_{n}"), 128, &[c0, c1, c0 * 0.8], bands, 32, &mut self.tr);
                let m = self.cloth_material(tex);
                materials.push(m);
                let b = cloth(&mut self.gr, &CURTAIN);
                let me = self.mesh(b, &format!("curtain_{n}"));
                let top = side(s) * at(bay_x(k), SLAB_Y0 - 0.25, -CLOTH_Z);
                self.put(me, m, top);
                self.put(rod, m_iron, top * at(0.0, 0.0, 0.1));
            }
        }
        materials
    }

    /// Rugs hung out over the gallery balustrade in the bays without curtains, in the curtains'
    /// materials.
    fn rugs(&mut self, cloth_materials: &[usize]) {
        let mut n = 0;
        for s in 0..2 {
            for k in (0..BAYS).step_by(2) {
                let b = cloth(&mut self.gr, &RUG);
                let me = self.mesh(b, &format!("rug_{n}"));
                let m = cloth_materials[(n * 3 + 1) % cloth_materials.len()];
                self.put(me, m, side(s) * at(bay_x(k), SLAB_Y1 + 1.02, -ARCADE_Z + 0.16));
                n += 1;
            }
        }
    }

    /// Banners in front of the upper columns: diamonds and stripes in turn.
    fn banners(&mut self) {
        let mut n = 0;
        for s in 0..2 {
            for k in 0..COLUMNS {
                let (c0, c1) = self.cloth_colours();
                let border = jitter(&mut self.tr, rgb(BANNER_BORDER.0, BANNER_BORDER.1, BANNER_BORDER.2), 0.08);
                let count = 3 + self.tr.below(4) as u32;
                let name = format!("atrium_banner_{n}");
                let tex = if k % 2 == 0 {
                    tex_diamonds(&name, 128, c0, c1, border, count, &mut self.tr)
                } else {
                    tex_stripes(&name, 128, &[c0, border, c1, border], count + 1, 24, &mut self.tr)
                };
                let m = self.cloth_material(tex);
                let b = cloth(&mut self.gr, &BANNER);
                let me = self.mesh(b, &format!("banner_{n}"));
                self.put(me, m, side(s) * at(column_x(k), BANNER_TOP.y, BANNER_TOP.z));
                n += 1;
            }
        }
    }

    /// The end walls: a door, a rose window and two lion masks each.
    fn end_walls(&mut self) {
        let [m_frame, m_door, m_rose, m_glass, m_bronze] = END_WALL.map(|s| self.surface(&s));
        let frame = self.mesh(door_frame(), "door_frame");
        let door = self.mesh(door_leaf(), "door_leaf");
        let rose = self.mesh(rose_tracery(), "rose_window_tracery");
        let glass = self.mesh(rose_glass(), "rose_window_glass");
        let masks = MASKS.map(|(name, _)| {
            let b = mask(&mut self.gr, 32, 16);
            self.mesh(b, name)
        });
        for s in 0..2 {
            // Models face +z at z = 0; this turns that to face -x at the east wall.
            let wall = side(s) * at(HALF_X, 0.0, 0.0) * Mat4::from_rotation_y(-FRAC_PI_2);
            self.put(frame, m_frame, wall);
            self.put(door, m_door, wall);
            self.put(rose, m_rose, wall * at(0.0, 8.4, 0.0));
            self.put(glass, m_glass, wall * at(0.0, 8.4, 0.03) * Mat4::from_rotation_x(FRAC_PI_2));
            for (mesh, (_, x)) in masks.into_iter().zip(MASKS) {
                self.put(mesh, m_bronze, wall * at(x, 4.6, 0.0) * Mat4::from_rotation_x(FRAC_PI_2) * Mat4::from_scale(Vec3::splat(0.32)));
            }
        }
    }

    /// Medallions on the attic over the columns, the two kinds in turn.
    fn medallions(&mut self) {
        let materials = MEDALLIONS.map(|s| self.surface(&s));
        let meds = ["medallion_a", "medallion_b"].map(|name| {
            let b = medallion(&mut self.gr, 0.3, 16);
            self.mesh(b, name)
        });
        for s in 0..2 {
            for k in 0..COLUMNS {
                let t = side(s) * at(column_x(k), ROOF_Y0 + 0.35, -ARCADE_Z + G_PANEL_T / 2.0) * Mat4::from_rotation_x(FRAC_PI_2);
                self.put(meds[k % 2], materials[k % 2], t);
            }
        }
    }

    fn fountain(&mut self) {
        let materials = FOUNTAIN.map(|part| self.surface(&part.surface));
        for (part, material) in FOUNTAIN.iter().zip(materials) {
            let mesh = self.mesh((part.shape)(), part.mesh);
            self.put(mesh, material, Mat4::IDENTITY);
        }
    }

    /// Planted vases in front of some columns and in the courtyard's corners.
    fn planted_vases(&mut self) {
        let m_vase: Vec<usize> = (0..3).map(|i| self.surface_named(&TERRACOTTA, &format!("{}_{i}", TERRACOTTA.name))).collect();
        let m_leaf: Vec<usize> = (0..3).map(|i| self.surface_named(&FOLIAGE, &format!("{}_{i}", FOLIAGE.name))).collect();
        let vases: Vec<usize> = (0..4)
            .map(|i| {
                let b = vase(&mut self.gr, 22);
                self.mesh(b, &format!("vase_{i}"))
            })
            .collect();
        let mut n = 0;
        for s in 0..2 {
            for (j, k) in VASE_COLUMNS.into_iter().enumerate() {
                let (bush, h) = self.bush_for(vases[j], (0.45, 0.6), n);
                let pos = side(s) * at(column_x(k), 0.0, -ARCADE_Z + 1.3);
                self.put(vases[j], m_vase[(j + s) % 3], pos);
                self.put(bush, m_leaf[n % 3], pos * at(0.0, h, 0.0));
                n += 1;
            }
        }
        for (j, (x, z)) in CORNER_VASES.into_iter().enumerate() {
            let (bush, h) = self.bush_for(vases[3 - j], (0.4, 0.55), n);
            self.put(vases[3 - j], m_vase[j % 3], at(x, 0.0, z));
            self.put(bush, m_leaf[n % 3], at(x, h, z));
            n += 1;
        }
    }

    /// Bush number `n`, of a radius drawn from `radii`, for `vase`: its mesh and the height it
    /// sits at above the vase's foot.
    fn bush_for(&mut self, vase: usize, radii: (f32, f32), n: usize) -> (usize, f32) {
        let h = self.meshes[vase].bounds().max.y;
        let r = self.gr.range(radii.0, radii.1);
        let b = bush(&mut self.gr, r, 28, 18);
        (self.mesh(b, &format!("bush_{n}")), h + 0.25)
    }

    fn into_scene(self) -> Scene {
        let presets: Vec<(String, Camera)> =
            VIEWS.iter().map(|v| (v.name.to_string(), Camera { up: v.up, ..Camera::look(v.eye, v.target, v.fov, 0.05, 120.0) })).collect();
        Scene {
            name: "atrium".into(),
            meshes: self.meshes.into_iter().map(Into::into).collect(),
            materials: self.materials.into(),
            instances: self.instances.into(),
            textures: self.textures,
            camera: presets[0].1,
            presets,
            light: Light { direction: Vec3::new(-0.32, 0.88, 0.36).normalize(), color: Vec3::new(1.0, 0.95, 0.86), intensity: 3.2, ambient: 0.25 },
            point_light: None,
            lights: Vec::new(),
            rig: None,
            posed: None,
            environment: None,
        }
    }
}
