//! The atrium's surfaces as recipes: each names a procedural texture, its colours (fixed, jittered
//! by the seed, or the seed's stone and warm tones) and its material's roughness. A recipe draws
//! from the texture randomness only when it is made into an image, in the order it is made.

use super::super::common::{jitter, rgb, tex_blocks, tex_diamonds, tex_marble, tex_noise, tex_tiles, tex_wood, Rgb, Rng};
use crate::scene::TextureImage;
use Colour::{Fixed, Jittered, Stone, Warm};

/// The seed's two building tones, the first draws of the texture randomness.
pub(super) struct Palette {
    stone: Rgb,
    warm: Rgb,
}

impl Palette {
    pub(super) fn draw(tr: &mut Rng) -> Self {
        let stone = jitter(tr, rgb(206, 192, 166), 0.05);
        let warm = jitter(tr, rgb(196, 160, 120), 0.05);
        Self { stone, warm }
    }
}

/// A colour in a texture recipe.
#[derive(Debug, Clone, Copy)]
pub(super) enum Colour {
    /// A fixed sRGB colour.
    Fixed(u8, u8, u8),
    /// An sRGB colour jittered by up to the amount (one draw of the texture randomness).
    Jittered(u8, u8, u8, f32),
    /// The seed's stone tone, scaled.
    Stone(f32),
    /// The seed's warm tone, scaled.
    Warm(f32),
}

impl Colour {
    fn resolve(self, tr: &mut Rng, palette: &Palette) -> Rgb {
        match self {
            Colour::Fixed(r, g, b) => rgb(r, g, b),
            Colour::Jittered(r, g, b, amount) => jitter(tr, rgb(r, g, b), amount),
            Colour::Stone(k) => palette.stone * k,
            Colour::Warm(k) => palette.warm * k,
        }
    }
}

/// Which texture generator of `common`, with its arguments.
#[derive(Debug, Clone, Copy)]
pub(super) enum Pattern {
    Tiles { a: Colour, b: Colour, cells: u32 },
    Blocks { block: Colour, mortar: Colour, rows: u32, cols: u32, vary: f32 },
    Noise { a: Colour, b: Colour, period: u32, contrast: f32 },
    Marble { base: Colour, vein: Colour, waves: f32 },
    Wood { light: Colour, dark: Colour, planks: u32 },
    Diamonds { a: Colour, b: Colour, border: Colour, n: u32 },
}

/// A texture recipe and the material made with it.
#[derive(Debug, Clone, Copy)]
pub(super) struct Surface {
    /// The texture's and the material's name.
    pub name: &'static str,
    /// Texels across (and down).
    pub size: u32,
    pub pattern: Pattern,
    pub roughness: f32,
    pub metallic: f32,
}

impl Surface {
    const fn new(name: &'static str, size: u32, pattern: Pattern, roughness: f32) -> Self {
        Self { name, size, pattern, roughness, metallic: 0.0 }
    }

    const fn metal(self, metallic: f32) -> Self {
        Self { metallic, ..self }
    }

    /// The texture, called `name`: its colours resolved in order, then the generator run.
    pub(super) fn image(&self, name: &str, tr: &mut Rng, palette: &Palette) -> TextureImage {
        let size = self.size;
        let mut two = |a: Colour, b: Colour| (a.resolve(tr, palette), b.resolve(tr, palette));
        match self.pattern {
            Pattern::Tiles { a, b, cells } => {
                let (a, b) = two(a, b);
                tex_tiles(name, size, a, b, cells, tr)
            }
            Pattern::Blocks { block, mortar, rows, cols, vary } => {
                let (block, mortar) = two(block, mortar);
                tex_blocks(name, size, block, mortar, rows, cols, vary, tr)
            }
            Pattern::Noise { a, b, period, contrast } => {
                let (a, b) = two(a, b);
                tex_noise(name, size, a, b, period, contrast, tr)
            }
            Pattern::Marble { base, vein, waves } => {
                let (base, vein) = two(base, vein);
                tex_marble(name, size, base, vein, waves, tr)
            }
            Pattern::Wood { light, dark, planks } => {
                let (light, dark) = two(light, dark);
                tex_wood(name, size, light, dark, planks, tr)
            }
            Pattern::Diamonds { a, b, border, n } => {
                let (a, b) = two(a, b);
                let border = border.resolve(tr, palette);
                tex_diamonds(name, size, a, b, border, n, tr)
            }
        }
    }
}

const fn blocks(block: Colour, mortar: Colour, rows: u32, cols: u32, vary: f32) -> Pattern {
    Pattern::Blocks { block, mortar, rows, cols, vary }
}

const fn noise(a: Colour, b: Colour, period: u32, contrast: f32) -> Pattern {
    Pattern::Noise { a, b, period, contrast }
}

const fn marble(base: Colour, vein: Colour, waves: f32) -> Pattern {
    Pattern::Marble { base, vein, waves }
}

// The shell.
pub(super) const FLOOR_TILES: Surface =
    Surface::new("atrium_floor_tiles", 256, Pattern::Tiles { a: Jittered(226, 214, 190, 0.05), b: Jittered(120, 124, 112, 0.05), cells: 8 }, 0.6);
pub(super) const AISLE_BRICKS: Surface = Surface::new("atrium_aisle_bricks", 128, blocks(Jittered(168, 92, 64, 0.06), Fixed(150, 140, 128), 16, 4, 0.12), 0.8);
pub(super) const SLAB_STONE: Surface = Surface::new("atrium_slab_stone", 128, noise(Stone(0.8), Stone(1.0), 6, 1.2), 0.8);
pub(super) const ROOF_SLABS: Surface = Surface::new("atrium_roof_slabs", 128, blocks(Stone(0.75), Stone(0.55), 4, 2, 0.08), 0.9);
pub(super) const WALL_PLASTER: Surface = Surface::new("atrium_wall_plaster", 128, noise(Jittered(214, 190, 150, 0.05), Fixed(170, 140, 104), 8, 1.6), 0.9);
pub(super) const END_WALL_BRICKS: Surface =
    Surface::new("atrium_end_wall_bricks", 128, blocks(Jittered(176, 104, 72, 0.06), Fixed(196, 188, 172), 16, 4, 0.1), 0.85);
pub(super) const ATTIC_ASHLAR: Surface = Surface::new("atrium_attic_ashlar", 128, blocks(Stone(1.0), Stone(0.7), 4, 2, 0.06), 0.8);
pub(super) const CORNICE: Surface = Surface::new("atrium_cornice", 64, noise(Stone(0.9), Stone(1.0), 4, 1.0), 0.7);

// The arcades: columns (three marbles for each storey), arches, balustrade, aisle ribs.
const fn column_marble(name: &'static str, base: (u8, u8, u8), waves: f32) -> Surface {
    Surface::new(name, 128, marble(Jittered(base.0, base.1, base.2, 0.06), Jittered(140, 130, 120, 0.1), waves), 0.35)
}
pub(super) const COLUMN_MARBLES: [Surface; 6] = [
    column_marble("atrium_column_marble_0", (222, 214, 200), 3.0),
    column_marble("atrium_column_marble_1", (222, 214, 200), 4.0),
    column_marble("atrium_column_marble_2", (222, 214, 200), 5.0),
    column_marble("atrium_column_marble_3", (208, 196, 176), 6.0),
    column_marble("atrium_column_marble_4", (208, 196, 176), 7.0),
    column_marble("atrium_column_marble_5", (208, 196, 176), 8.0),
];
pub(super) const ARCH_GROUND: Surface = Surface::new("atrium_arch_ground", 128, blocks(Stone(1.0), Stone(0.75), 4, 3, 0.07), 0.8);
pub(super) const ARCH_UPPER: Surface = Surface::new("atrium_arch_upper", 128, blocks(Warm(1.0), Warm(0.75), 4, 3, 0.07), 0.8);
pub(super) const ARCHIVOLT: Surface = Surface::new("atrium_archivolt", 64, noise(Stone(0.95), Stone(0.7), 4, 1.0), 0.6);
pub(super) const BALUSTER: Surface = Surface::new("atrium_baluster", 64, marble(Jittered(230, 224, 212, 0.04), Fixed(160, 150, 140), 2.0), 0.4);
pub(super) const RAIL: Surface = Surface::new("atrium_rail", 64, noise(Stone(0.8), Stone(1.0), 4, 1.0), 0.6);
pub(super) const WALL_PILASTER: Surface = Surface::new("atrium_wall_pilaster", 64, blocks(Stone(1.0), Stone(0.7), 8, 1, 0.06), 0.8);
pub(super) const RIB: Surface = Surface::new("atrium_rib", 64, blocks(Warm(1.0), Warm(0.7), 1, 6, 0.08), 0.8);

// Furniture.
pub(super) const BENCH_WOOD: Surface =
    Surface::new("atrium_bench_wood", 64, Pattern::Wood { light: Jittered(150, 104, 64, 0.05), dark: Fixed(80, 50, 30), planks: 4 }, 0.7);
pub(super) const IRON: Surface = Surface::new("atrium_iron", 64, noise(Fixed(40, 38, 36), Fixed(92, 86, 80), 8, 1.4), 0.5);
pub(super) const BRASS: [Surface; 2] = [
    Surface::new("atrium_brass_a", 64, noise(Jittered(180, 140, 60, 0.05), Fixed(110, 80, 30), 8, 1.4), 0.35).metal(0.8),
    Surface::new("atrium_brass_b", 64, noise(Jittered(160, 110, 70, 0.05), Fixed(90, 60, 40), 8, 1.4), 0.35).metal(0.8),
];

// The end walls: door frame, door leaf, rose window stone and glass, the masks' bronze.
pub(super) const END_WALL: [Surface; 5] = [
    Surface::new("atrium_door_frame", 64, noise(Warm(0.8), Warm(1.0), 4, 1.0), 0.7),
    Surface::new("atrium_door_wood", 128, Pattern::Wood { light: Jittered(120, 80, 50, 0.05), dark: Fixed(60, 36, 20), planks: 6 }, 0.7),
    Surface::new("atrium_rose_stone", 64, marble(Stone(1.0), Stone(0.6), 2.0), 0.6),
    Surface::new(
        "atrium_rose_glass",
        128,
        Pattern::Diamonds { a: Jittered(40, 60, 150, 0.1), b: Jittered(160, 40, 40, 0.1), border: Fixed(200, 170, 60), n: 6 },
        0.2,
    ),
    Surface::new("atrium_mask_bronze", 64, noise(Fixed(90, 70, 40), Fixed(60, 100, 80), 8, 1.6), 0.4).metal(0.7),
];
pub(super) const MEDALLIONS: [Surface; 2] = [
    Surface::new("atrium_medallion_a", 64, marble(Jittered(220, 210, 196, 0.05), Fixed(150, 110, 90), 2.0), 0.4),
    Surface::new("atrium_medallion_b", 64, noise(Jittered(120, 140, 110, 0.05), Fixed(80, 90, 70), 4, 1.2), 0.4),
];

// The fountain and the planted vases (each of these two recipes makes three numbered surfaces).
pub(super) const FOUNTAIN_BASIN: Surface = Surface::new("atrium_fountain_basin", 128, blocks(Stone(0.95), Stone(0.6), 2, 8, 0.06), 0.6);
pub(super) const WATER: Surface = Surface::new("atrium_water", 128, noise(Jittered(40, 90, 110, 0.05), Fixed(90, 150, 160), 8, 1.6), 0.05);
pub(super) const FOUNTAIN_MARBLE: Surface = Surface::new("atrium_fountain_marble", 128, marble(Jittered(236, 230, 220, 0.04), Fixed(120, 120, 130), 4.0), 0.3);
pub(super) const TERRACOTTA: Surface = Surface::new("atrium_terracotta", 64, noise(Jittered(178, 96, 60, 0.08), Fixed(120, 60, 40), 6, 1.2), 0.8);
pub(super) const FOLIAGE: Surface = Surface::new("atrium_foliage", 64, noise(Jittered(40, 90, 36, 0.08), Fixed(100, 140, 60), 16, 2.0), 0.9);
