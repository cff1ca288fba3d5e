//! The atrium's layout as data: its dimensions, the two storeys of the arcades, the parts of the
//! shell, the cloth's sizes, where the furniture stands and the views. The assembly in `super`
//! walks these tables.

use super::surfaces::{
    Surface, AISLE_BRICKS, ARCH_GROUND, ARCH_UPPER, ATTIC_ASHLAR, CORNICE, END_WALL_BRICKS, FLOOR_TILES, ROOF_SLABS, SLAB_STONE, WALL_PLASTER,
};
use glam::{Mat4, Vec2, Vec3};
use std::f32::consts::PI;

/// Inner face of the end walls.
pub(super) const HALF_X: f32 = 15.0;
/// Column line of the arcades.
pub(super) const ARCADE_Z: f32 = 3.5;
/// Inner face of the outer (long) walls.
pub(super) const WALL_Z: f32 = 7.0;
const WALL_T: f32 = 0.4;
pub(super) const BAY: f32 = 3.0;
pub(super) const BAYS: usize = 10;
pub(super) const COLUMNS: usize = BAYS - 1;
const G_SPRING: f32 = 4.15;
const G_RADIUS: f32 = 1.1;
pub(super) const G_PANEL_T: f32 = 0.8;
pub(super) const SLAB_Y0: f32 = 6.0;
pub(super) const SLAB_Y1: f32 = 6.35;
const U_SPRING: f32 = 9.45;
const U_RADIUS: f32 = 1.15;
const U_PANEL_T: f32 = 0.7;
pub(super) const ROOF_Y0: f32 = 11.0;
const ROOF_Y1: f32 = 11.25;
const TOP_Y: f32 = 12.0;
/// Curtains hang in the ground bays with odd index, this far in front of the column line.
pub(super) const CLOTH_Z: f32 = 2.9;

pub(super) fn column_x(k: usize) -> f32 {
    -HALF_X + BAY * (k + 1) as f32
}

pub(super) fn bay_x(k: usize) -> f32 {
    -HALF_X + BAY * (k as f32 + 0.5)
}

/// The south side as modelled, or the north side (half a turn about y).
pub(super) fn side(s: usize) -> Mat4 {
    if s == 0 {
        Mat4::IDENTITY
    } else {
        Mat4::from_rotation_y(PI)
    }
}

pub(super) fn at(x: f32, y: f32, z: f32) -> Mat4 {
    Mat4::from_translation(Vec3::new(x, y, z))
}

// ---------------------------------------------------------------------------------------------
// The arcades
// ---------------------------------------------------------------------------------------------

/// A column's dimensions (metres) and tessellation.
pub(super) struct ColumnSpec {
    pub plinth_hw: f32,
    pub plinth_h: f32,
    pub base_h: f32,
    pub base_r: f32,
    pub shaft_r0: f32,
    pub shaft_r1: f32,
    pub shaft_h: f32,
    pub cap_h: f32,
    pub cap_r: f32,
    pub abacus_hw: f32,
    pub abacus_h: f32,
    pub flutes: u32,
    pub segments: u32,
    pub rings: u32,
    pub lathe_segments: u32,
}

pub(super) const GROUND_COLUMN: ColumnSpec = ColumnSpec {
    plinth_hw: 0.35,
    plinth_h: 0.25,
    base_h: 0.2,
    base_r: 0.34,
    shaft_r0: 0.27,
    shaft_r1: 0.235,
    shaft_h: 3.1,
    cap_h: 0.4,
    cap_r: 0.38,
    abacus_hw: 0.4,
    abacus_h: 0.2,
    flutes: 10,
    segments: 40,
    rings: 12,
    lathe_segments: 24,
};

pub(super) const UPPER_COLUMN: ColumnSpec = ColumnSpec {
    plinth_hw: 0.28,
    plinth_h: 0.2,
    base_h: 0.15,
    base_r: 0.26,
    shaft_r0: 0.2,
    shaft_r1: 0.18,
    shaft_h: 2.3,
    cap_h: 0.3,
    cap_r: 0.31,
    abacus_hw: 0.35,
    abacus_h: 0.15,
    flutes: 8,
    segments: 32,
    rings: 8,
    lathe_segments: 20,
};

/// One storey of the arcades: its columns, arches, end piers, aisle ribs and wall pilasters.
pub(super) struct Storey {
    /// In mesh names: `column_ground_0`, `arch_panel_upper`, ...
    pub name: &'static str,
    /// Where its columns, piers and pilasters stand.
    pub floor: f32,
    pub column: ColumnSpec,
    /// The one column variant (of [`COLUMN_VARIANTS`]) with twisted flutes, and its twist.
    pub twisted_variant: usize,
    pub twist: f32,
    /// The first of its three column marbles ([`super::surfaces::COLUMN_MARBLES`]).
    pub marbles: usize,
    /// The arches: springing height, radius, wall thickness, and the top of the wall above them.
    pub spring: f32,
    pub radius: f32,
    pub panel_t: f32,
    pub top: f32,
    pub arch: Surface,
    /// The engaged piers at the end walls, from `floor`.
    pub pier_height: f32,
    /// The transverse rib across the aisle, from the arcade to the outer wall.
    pub rib_span: f32,
    /// The wall pilaster under the rib, from `floor`.
    pub pilaster_height: f32,
}

/// Column meshes made for each storey (the two sides use them in turn).
pub(super) const COLUMN_VARIANTS: usize = 6;

pub(super) const STOREYS: [Storey; 2] = [
    Storey {
        name: "ground",
        floor: 0.0,
        column: GROUND_COLUMN,
        twisted_variant: 5,
        twist: 1.2,
        marbles: 0,
        spring: G_SPRING,
        radius: G_RADIUS,
        panel_t: G_PANEL_T,
        top: SLAB_Y0,
        arch: ARCH_GROUND,
        pier_height: G_SPRING,
        rib_span: (WALL_Z - 0.15) - (ARCADE_Z + G_PANEL_T / 2.0),
        pilaster_height: G_SPRING - 0.08,
    },
    Storey {
        name: "upper",
        floor: SLAB_Y1,
        column: UPPER_COLUMN,
        twisted_variant: 2,
        twist: -1.6,
        marbles: 3,
        spring: U_SPRING,
        radius: U_RADIUS,
        panel_t: U_PANEL_T,
        top: ROOF_Y0,
        arch: ARCH_UPPER,
        pier_height: U_SPRING - SLAB_Y1,
        rib_span: WALL_Z - 0.15 - ARCADE_Z - U_PANEL_T / 2.0,
        pilaster_height: U_SPRING - SLAB_Y1 - 0.08,
    },
];

// ---------------------------------------------------------------------------------------------
// The shell: floors, slabs, roofs, walls and mouldings
// ---------------------------------------------------------------------------------------------

/// Where a part goes.
#[derive(Debug, Clone, Copy)]
pub(super) enum Placement {
    /// Once, as modelled.
    Once,
    /// On both sides, as modelled.
    Sides,
    /// On both sides, moved by this much first.
    SidesAt(Vec3),
}

impl Placement {
    pub(super) fn transforms(self) -> Vec<Mat4> {
        match self {
            Placement::Once => vec![Mat4::IDENTITY],
            Placement::Sides => (0..2).map(side).collect(),
            Placement::SidesAt(p) => (0..2).map(|s| side(s) * at(p.x, p.y, p.z)).collect(),
        }
    }
}

/// A part's material: made from a new surface, or the one made earlier under that name.
pub(super) enum Finish {
    New(Surface),
    Like(&'static str),
}

/// A part's shape.
pub(super) enum Shape {
    /// A flat floor facing +y: a corner, its two edges, cells along each, uv repeats per metre.
    Floor { origin: Vec3, eu: Vec3, ev: Vec3, cells: [u32; 2], uv_per_m: f32 },
    /// A box: corners, the largest cell, uv repeats per metre.
    Block { min: Vec3, max: Vec3, cell: f32, uv_per_m: f32 },
    /// A moulding along the whole length (x) with this profile of (y, z) offsets.
    Moulding { profile: &'static [Vec2], segments: usize },
}

pub(super) struct ShellPart {
    pub mesh: &'static str,
    pub finish: Finish,
    pub shape: Shape,
    pub placement: Placement,
}

/// The cornice's profile is drawn up to this height, then lowered so that it ends at the top of
/// the attic wall.
const CORNICE_HEIGHT: f32 = 0.35;

/// A point of the cornice's profile: (y, z) as drawn, lowered by [`CORNICE_HEIGHT`].
const fn cornice_point(y: f32, z: f32) -> Vec2 {
    Vec2::new(y - CORNICE_HEIGHT, z)
}

const CORNICE_PROFILE: [Vec2; 7] = [
    cornice_point(-0.3, -0.1),
    cornice_point(0.0, -0.1),
    cornice_point(0.05, 0.05),
    cornice_point(0.18, 0.12),
    cornice_point(0.25, 0.3),
    cornice_point(0.35, 0.32),
    cornice_point(0.35, -0.1),
];
const STRING_COURSE_PROFILE: [Vec2; 7] = [
    Vec2::new(0.0, -0.1),
    Vec2::new(0.0, 0.08),
    Vec2::new(0.06, 0.16),
    Vec2::new(0.22, 0.16),
    Vec2::new(0.3, 0.08),
    Vec2::new(0.35, 0.08),
    Vec2::new(0.35, -0.1),
];
const SKIRTING_PROFILE: [Vec2; 5] = [Vec2::new(0.0, -0.05), Vec2::new(0.0, 0.04), Vec2::new(0.2, 0.04), Vec2::new(0.3, 0.0), Vec2::new(0.3, -0.05)];

/// The courtyard face of the attic and gallery (the front of the arch walls).
const FACADE_Z: f32 = -ARCADE_Z + G_PANEL_T / 2.0;

/// The shell, in the order it is built.
pub(super) const SHELL: [ShellPart; 10] = [
    ShellPart {
        mesh: "courtyard_floor",
        finish: Finish::New(FLOOR_TILES),
        shape: Shape::Floor {
            origin: Vec3::new(-HALF_X, 0.0, -3.1),
            eu: Vec3::new(2.0 * HALF_X, 0.0, 0.0),
            ev: Vec3::new(0.0, 0.0, 6.2),
            cells: [96, 20],
            uv_per_m: 0.5,
        },
        placement: Placement::Once,
    },
    ShellPart {
        mesh: "aisle_floor",
        finish: Finish::New(AISLE_BRICKS),
        shape: Shape::Floor {
            origin: Vec3::new(-HALF_X, 0.0, -WALL_Z),
            eu: Vec3::new(2.0 * HALF_X, 0.0, 0.0),
            ev: Vec3::new(0.0, 0.0, WALL_Z - 3.1),
            cells: [60, 8],
            uv_per_m: 0.5,
        },
        placement: Placement::Sides,
    },
    ShellPart {
        mesh: "gallery_slab",
        finish: Finish::New(SLAB_STONE),
        shape: Shape::Block {
            min: Vec3::new(-HALF_X, SLAB_Y0, -WALL_Z),
            max: Vec3::new(HALF_X, SLAB_Y1, -ARCADE_Z + G_PANEL_T / 2.0),
            cell: 1.0,
            uv_per_m: 0.5,
        },
        placement: Placement::Sides,
    },
    ShellPart {
        mesh: "aisle_roof",
        finish: Finish::New(ROOF_SLABS),
        shape: Shape::Block {
            min: Vec3::new(-HALF_X, ROOF_Y0, -WALL_Z),
            max: Vec3::new(HALF_X, ROOF_Y1, -ARCADE_Z + U_PANEL_T / 2.0),
            cell: 1.0,
            uv_per_m: 0.5,
        },
        placement: Placement::Sides,
    },
    ShellPart {
        mesh: "outer_wall",
        finish: Finish::New(WALL_PLASTER),
        shape: Shape::Block {
            min: Vec3::new(-HALF_X - WALL_T, 0.0, -WALL_Z - WALL_T),
            max: Vec3::new(HALF_X + WALL_T, TOP_Y, -WALL_Z),
            cell: 1.0,
            uv_per_m: 0.25,
        },
        placement: Placement::Sides,
    },
    ShellPart {
        mesh: "end_wall",
        finish: Finish::New(END_WALL_BRICKS),
        shape: Shape::Block {
            min: Vec3::new(HALF_X, 0.0, -WALL_Z - WALL_T),
            max: Vec3::new(HALF_X + WALL_T, TOP_Y, WALL_Z + WALL_T),
            cell: 0.6,
            uv_per_m: 0.25,
        },
        placement: Placement::Sides,
    },
    ShellPart {
        mesh: "attic_wall",
        finish: Finish::New(ATTIC_ASHLAR),
        shape: Shape::Block {
            min: Vec3::new(-HALF_X, ROOF_Y0, -ARCADE_Z - G_PANEL_T / 2.0),
            max: Vec3::new(HALF_X, TOP_Y, -ARCADE_Z + G_PANEL_T / 2.0),
            cell: 0.5,
            uv_per_m: 0.5,
        },
        placement: Placement::Sides,
    },
    // Cornice on top of the attic and a string course under the gallery, on the courtyard face.
    ShellPart {
        mesh: "cornice",
        finish: Finish::New(CORNICE),
        shape: Shape::Moulding { profile: &CORNICE_PROFILE, segments: 60 },
        placement: Placement::SidesAt(Vec3::new(0.0, TOP_Y, FACADE_Z)),
    },
    ShellPart {
        mesh: "string_course",
        finish: Finish::Like(CORNICE.name),
        shape: Shape::Moulding { profile: &STRING_COURSE_PROFILE, segments: 60 },
        placement: Placement::SidesAt(Vec3::new(0.0, SLAB_Y0, FACADE_Z)),
    },
    ShellPart {
        mesh: "skirting",
        finish: Finish::Like(SLAB_STONE.name),
        shape: Shape::Moulding { profile: &SKIRTING_PROFILE, segments: 30 },
        placement: Placement::SidesAt(Vec3::new(0.0, 0.0, -WALL_Z)),
    },
];

// ---------------------------------------------------------------------------------------------
// Cloth, furniture and views
// ---------------------------------------------------------------------------------------------

/// The size of a hanging cloth: width, drop, grid cells (across, down) and how deep its folds are.
#[derive(Debug, Clone, Copy)]
pub(super) struct Drape {
    pub width: f32,
    pub drop: f32,
    pub cells: [u32; 2],
    pub fold_amp: f32,
}

/// In front of alternate ground arches.
pub(super) const CURTAIN: Drape = Drape { width: 2.3, drop: 3.4, cells: [20, 32], fold_amp: 0.14 };
/// Over the gallery balustrade in the bays without curtains.
pub(super) const RUG: Drape = Drape { width: 1.9, drop: 0.95, cells: [20, 14], fold_amp: 0.05 };
/// In front of the upper columns.
pub(super) const BANNER: Drape = Drape { width: 0.9, drop: 2.8, cells: [10, 24], fold_amp: 0.05 };

/// The dyes curtains and banners draw their two colours from.
pub(super) const CLOTH_DYES: [(u8, u8, u8); 7] = [(150, 30, 34), (30, 70, 140), (40, 110, 60), (190, 150, 40), (110, 40, 110), (200, 190, 170), (180, 80, 30)];
/// The banners' border colour.
pub(super) const BANNER_BORDER: (u8, u8, u8) = (200, 170, 60);
/// Banners hang from under the aisle roof, just in front of the arch wall.
pub(super) const BANNER_TOP: Vec3 = Vec3::new(0.0, ROOF_Y0 - 0.15, -ARCADE_Z + G_PANEL_T / 2.0 + 0.2);

/// The aisle bays with a bench against the outer wall.
pub(super) const BENCH_BAYS: [usize; 4] = [1, 3, 6, 8];
/// The two lanterns (mesh name, chain length), hung in alternate aisle bays under the gallery.
pub(super) const LANTERNS: [(&str, f32); 2] = [("lantern_a", 0.9), ("lantern_b", 1.2)];
/// The two lion masks (mesh name, x across the end wall).
pub(super) const MASKS: [(&str, f32); 2] = [("mask_a", -2.6), ("mask_b", 2.6)];
/// The columns with a planted vase in front of them, on each side.
pub(super) const VASE_COLUMNS: [usize; 4] = [0, 2, 6, 8];
/// The planted vases in the courtyard's corners (x, z).
pub(super) const CORNER_VASES: [(f32, f32); 4] = [(-13.6, -2.2), (13.6, -2.2), (-13.6, 2.2), (13.6, 2.2)];

/// A camera preset.
pub(super) struct View {
    pub name: &'static str,
    pub eye: Vec3,
    pub target: Vec3,
    /// Vertical field of view in degrees.
    pub fov: f32,
    pub up: Vec3,
}

/// The presets; the first is the default view.
pub(super) const VIEWS: [View; 6] = [
    View { name: "courtyard", eye: Vec3::new(-13.2, 1.8, 0.6), target: Vec3::new(6.0, 4.2, -0.4), fov: 60.0, up: Vec3::Y },
    View { name: "gallery", eye: Vec3::new(-12.0, 7.6, -5.0), target: Vec3::new(10.0, 5.0, -4.0), fov: 60.0, up: Vec3::Y },
    View { name: "aisle", eye: Vec3::new(12.0, 1.7, 5.2), target: Vec3::new(-10.0, 2.5, 5.0), fov: 60.0, up: Vec3::Y },
    View { name: "sky", eye: Vec3::new(0.5, 30.0, 0.0), target: Vec3::new(0.0, 0.0, 0.0), fov: 55.0, up: Vec3::Y },
    // The Stress view (`bench rays`): down the south aisle under the gallery, no sky.
    View { name: "stress", eye: Vec3::new(12.0, 1.7, 5.2), target: Vec3::new(-10.0, 2.5, 5.0), fov: 60.0, up: Vec3::Y },
    // Miss (inside): from the middle of the courtyard, above the fountain (2.35 m), straight up
    // through the open roof (its opening is 6.2 m across at 12 m; 24 degrees over the 6.2 m side
    // leaves the cornice out), so rays cross the scene's box and hit nothing.
    View { name: "miss_inside", eye: Vec3::new(0.0, 2.6, 0.0), target: Vec3::new(0.0, 12.0, 0.0), fov: 24.0, up: Vec3::Z },
];
