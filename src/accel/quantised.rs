//! The BLAS child pairs with 16-bit boxes that the `compute` back-end's WGSL traverses where it
//! can: the same tree as the exact `blas_nodes` ([`super::layout`]), the two children of an
//! interior node in 32 bytes (two 16-byte loads a step) instead of 64.
//!
//! `blas_quant` has one [`QuantEntry`] per index of `blas_nodes`. The entry at a child pair's
//! first index (an interior node's `left_or_first`) holds both children: each child's box as
//! three words `min | max << 16`, one per axis, then both children's descriptors
//! (`left_or_first << 3 | count`, as the WGSL carries them). The entry at a BLAS's root index
//! (never a pair's first) holds the BLAS's grid: per axis a base `g` (f32) and a power of two
//! `S`, and a word that says whether the grid is valid. A 16-bit value `q` stands for the plane
//! `g + S * (1 + q / 65536)`, exactly, in real arithmetic: the WGSL forms `1 + q / 65536` by
//! placing `q` in an f32's mantissa, so the slab test stays one multiply-add per plane. Every
//! child box is rounded outward onto the grid, so a box never loses a point of the exact one.
//!
//! A BLAS whose grid cannot hold its boxes (an extent past 2^40, a non-finite box) gets an
//! invalid grid, and so does every tree this module did not write (the GPU builder's, a tree
//! refitted on the GPU): the WGSL then traverses the exact nodes.

use super::layout::GpuBvhNode;
use bytemuck::{Pod, Zeroable};

/// One entry of `blas_quant`: a child pair, a BLAS's grid, or unused (zeros).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Pod, Zeroable)]
pub struct QuantEntry(pub [u32; 8]);

/// Word 3 of a grid entry when the grid is valid.
const GRID_VALID: u32 = 1;
/// Grid cells a box may span: 16 bits, one cell spare at each end for outward rounding.
const CELLS: f64 = 65534.0;
/// The smallest grid cell (below it the WGSL's per-ray scale `S / dir` could leave the normal
/// f32 range; the WGSL checks that range per ray as well).
const MIN_CELL: f64 = 1.0 / (1u64 << 40) as f64;
/// The largest extent given a grid.
const MAX_EXTENT: f64 = (1u64 << 40) as f64;

/// One axis of a BLAS's grid: `plane(q) = base + scale * (1 + q / 65536)`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct GridAxis {
    base: f32,
    scale: f32,
}

impl GridAxis {
    /// The plane of `q`, exactly (f64 holds every such sum of an f32 and a multiple of a power
    /// of two within 2^16 cells of it).
    fn plane(self, q: u32) -> f64 {
        self.base as f64 + self.scale as f64 * (1.0 + q as f64 / 65536.0)
    }

    /// A grid over `[lo, hi]`, `None` past [`MAX_EXTENT`] or for a non-finite bound.
    fn covering(lo: f32, hi: f32) -> Option<GridAxis> {
        if !(lo.is_finite() && hi.is_finite() && lo <= hi) || (hi as f64 - lo as f64) > MAX_EXTENT {
            return None;
        }
        let mut cell = ((hi as f64 - lo as f64) / CELLS).max(MIN_CELL);
        cell = 2f64.powi(cell.log2().ceil() as i32);
        // Doubling the cell until the f32 base below `lo` leaves room for `hi`: far from the
        // origin the base rounds down by up to an ulp of `lo`.
        for _ in 0..64 {
            let scale = cell * 65536.0;
            let ideal = (lo as f64 / cell).floor() * cell - scale;
            let mut base = ideal as f32;
            if base as f64 > ideal {
                base = base.next_down();
            }
            let axis = GridAxis { base, scale: scale as f32 };
            if (axis.scale as f64) == scale && axis.plane(0) <= lo as f64 && axis.plane(65535) >= hi as f64 {
                return Some(axis);
            }
            cell *= 2.0;
        }
        None
    }

    /// The largest `q` whose plane is at most `x`.
    fn below(self, x: f32) -> u32 {
        let cell = self.scale as f64 / 65536.0;
        let mut q = ((x as f64 - self.plane(0)) / cell).floor().clamp(0.0, 65535.0) as u32;
        while q > 0 && self.plane(q) > x as f64 {
            q -= 1;
        }
        q
    }

    /// The smallest `q` whose plane is at least `x`.
    fn above(self, x: f32) -> u32 {
        let cell = self.scale as f64 / 65536.0;
        let mut q = ((x as f64 - self.plane(0)) / cell).ceil().clamp(0.0, 65535.0) as u32;
        while q < 65535 && self.plane(q) < x as f64 {
            q += 1;
        }
        q
    }
}

/// The grid of a BLAS whose root box is `root`.
fn grid_of(root: &GpuBvhNode) -> Option<[GridAxis; 3]> {
    let axes = [0, 1, 2].map(|a| GridAxis::covering(root.min[a], root.max[a]));
    match axes {
        [Some(x), Some(y), Some(z)] => Some([x, y, z]),
        _ => None,
    }
}

/// A box's three words on `grid`, `None` if it does not lie within the grid.
fn box_words(grid: &[GridAxis; 3], n: &GpuBvhNode) -> Option<[u32; 3]> {
    let mut words = [0; 3];
    for a in 0..3 {
        let (lo, hi) = (grid[a].below(n.min[a]), grid[a].above(n.max[a]));
        if !(grid[a].plane(lo) <= n.min[a] as f64 && grid[a].plane(hi) >= n.max[a] as f64) {
            return None;
        }
        words[a] = lo | hi << 16;
    }
    Some(words)
}

/// A grid entry.
fn grid_entry(grid: Option<&[GridAxis; 3]>) -> QuantEntry {
    match grid {
        Some(g) => QuantEntry([
            g[0].base.to_bits(),
            g[1].base.to_bits(),
            g[2].base.to_bits(),
            GRID_VALID,
            g[0].scale.to_bits(),
            g[1].scale.to_bits(),
            g[2].scale.to_bits(),
            0,
        ]),
        None => QuantEntry::default(),
    }
}

/// Writes the entries of the BLAS whose nodes are `nodes[root..end]` (indices absolute, as in
/// `blas_nodes`) into `quant` (as long as `nodes`): its grid at `root` and a pair at every
/// interior node's first child. A BLAS whose grid or boxes do not fit gets an invalid grid.
pub(crate) fn quantise_blas(nodes: &[GpuBvhNode], root: usize, end: usize, quant: &mut [QuantEntry]) {
    let Some(grid) = nodes.get(root).and_then(grid_of) else {
        quant[root] = grid_entry(None);
        return;
    };
    for n in &nodes[root..end] {
        if n.count != 0 {
            continue;
        }
        let first = n.left_or_first as usize;
        let (Some(l), Some(r)) = (nodes.get(first), nodes.get(first + 1)) else {
            quant[root] = grid_entry(None);
            return;
        };
        let (Some(lw), Some(rw)) = (box_words(&grid, l), box_words(&grid, r)) else {
            quant[root] = grid_entry(None);
            return;
        };
        let desc = |c: &GpuBvhNode| c.left_or_first << 3 | c.count;
        quant[first] = QuantEntry([lw[0], lw[1], lw[2], rw[0], rw[1], rw[2], desc(l), desc(r)]);
    }
    quant[root] = grid_entry(Some(&grid));
}

/// The exact box of `words` on the grid of `grid_entry` (`None` for an invalid grid): what the
/// WGSL's slab test sees, for tests.
pub fn decoded_box(grid_entry: &QuantEntry, words: [u32; 3]) -> Option<([f64; 3], [f64; 3])> {
    if grid_entry.0[3] != GRID_VALID {
        return None;
    }
    let axis = |a: usize| GridAxis { base: f32::from_bits(grid_entry.0[a]), scale: f32::from_bits(grid_entry.0[4 + a]) };
    let lo = [0, 1, 2].map(|a| axis(a).plane(words[a] & 0xFFFF));
    let hi = [0, 1, 2].map(|a| axis(a).plane(words[a] >> 16));
    Some((lo, hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn node(min: [f32; 3], max: [f32; 3], left_or_first: u32, count: u32) -> GpuBvhNode {
        GpuBvhNode { min, left_or_first, max, count }
    }

    #[test]
    fn boxes_round_outward_onto_the_grid() {
        let mut rng = 0x2545F4914F6CDD1Du64;
        let mut next = || {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            (rng >> 40) as f32 / (1u64 << 24) as f32
        };
        for (offset, extent) in [(0.0f32, 1.0f32), (-3.0, 40.0), (1.0e5, 2.0), (-7.5e6, 1.0e-3), (1.0e9, 3.0e8), (0.0, 0.0)] {
            let root = node([offset; 3], [offset + extent; 3], 1, 0);
            let grid = grid_of(&root).expect("a grid");
            for _ in 0..200 {
                let a = [0, 1, 2].map(|_| offset + extent * next());
                let b = [0, 1, 2].map(|_| offset + extent * next());
                let child = node([0, 1, 2].map(|k| a[k].min(b[k])), [0, 1, 2].map(|k| a[k].max(b[k])), 0, 1);
                let words = box_words(&grid, &child).expect("inside the root");
                let (lo, hi) = decoded_box(&grid_entry(Some(&grid)), words).unwrap();
                for k in 0..3 {
                    assert!(lo[k] <= child.min[k] as f64 && hi[k] >= child.max[k] as f64, "{offset} {extent}: {lo:?} {hi:?} {child:?}");
                    // At most two cells wider on each side than the exact box (one cell is
                    // the grid's resolution; the base's rounding may cost another far from
                    // the origin).
                    let cell = grid[k].scale as f64 / 65536.0;
                    assert!(child.min[k] as f64 - lo[k] <= 2.0 * cell && hi[k] - child.max[k] as f64 <= 2.0 * cell);
                }
            }
        }
    }

    #[test]
    fn a_grid_fits_within_a_few_cells_of_the_extent() {
        let g = GridAxis::covering(-3.0, 37.0).unwrap();
        let cell = g.scale as f64 / 65536.0;
        assert!(cell >= 40.0 / CELLS && cell < 2.0 * 40.0 / CELLS, "cell {cell}");
        assert!(GridAxis::covering(0.0, f32::MAX).is_none());
        assert!(GridAxis::covering(f32::NAN, 1.0).is_none());
    }

    #[test]
    fn pairs_and_grid_are_written_where_the_wgsl_reads_them() {
        let nodes = [
            node([0.0; 3], [4.0; 3], 1, 0),
            node([0.0; 3], [1.0; 3], 7, 2),
            node([2.0; 3], [4.0; 3], 3, 0),
            node([2.0; 3], [3.0; 3], 9, 1),
            node([3.0; 3], [4.0; 3], 10, 3),
        ];
        let mut quant = vec![QuantEntry::default(); nodes.len()];
        quantise_blas(&nodes, 0, nodes.len(), &mut quant);
        assert_eq!(quant[0].0[3], GRID_VALID);
        assert_eq!(quant[1].0[6..], [7 << 3 | 2, 3 << 3]);
        assert_eq!(quant[3].0[6..], [9 << 3 | 1, 10 << 3 | 3]);
        assert_eq!(quant[2], QuantEntry::default());
        let (lo, hi) = decoded_box(&quant[0], [quant[3].0[3], quant[3].0[4], quant[3].0[5]]).unwrap();
        assert!(lo.iter().all(|&x| x <= 3.0) && hi.iter().all(|&x| x >= 4.0));
        let bad = [node([0.0; 3], [f32::INFINITY; 3], 1, 0), nodes[1], nodes[2]];
        let mut quant = vec![QuantEntry([9; 8]); 3];
        quantise_blas(&bad, 0, 3, &mut quant);
        assert_eq!(quant[0], QuantEntry::default());
    }
}
