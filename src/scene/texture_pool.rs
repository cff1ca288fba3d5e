//! How a scene's textures are pooled for a device with texture binding arrays: the textures of
//! one size and one encoding (colour or data) share one 2D array texture, one element of the
//! binding array, so a pass binds a few arrays instead of one texture per image (wgpu tracks
//! every bound texture at every dispatch: a frame's CPU time grew with the texture count).
//! A texture's reference, as the material and alpha records hold it, names its element and
//! its layer ([`TEXTURE_REF_LAYER_BITS`]); reference 0 is element 0, layer 0: plain white.
//! Without binding arrays the records hold the texture's index + 1 (a layer of one array).
//! Plain data: the GPU side is `runtime::scene_upload`.

use super::gltf_import::{fallback_texture, TextureSlot};
use super::{Scene, TextureImage};

/// Bits of a texture reference that hold its layer; the element is above them. The shaders'
/// decode (`common/scene_textures_texels_bindless.wgsl`) must agree.
pub const TEXTURE_REF_LAYER_BITS: u32 = 11;
/// Layers one pooled array holds at most: WebGPU's guaranteed `maxTextureArrayLayers`, so the
/// pooling is the same on every device.
pub const POOL_LAYERS: usize = 256;

/// One element of the binding array: textures of one size and encoding, one per layer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PoolArray {
    /// Width in texels of every layer.
    pub width: u32,
    /// Height in texels of every layer.
    pub height: u32,
    /// Whether the layers hold data (stored linearly) rather than sRGB colour.
    pub data: bool,
    /// The texture of each layer: `None` for the plain white one (element 0, layer 0), else its
    /// index in the scene's textures.
    pub layers: Vec<Option<usize>>,
}

/// The scene's textures pooled into arrays, and each texture's reference.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TexturePool {
    /// The binding array's elements; element 0 starts with the white texture.
    pub arrays: Vec<PoolArray>,
    /// Per scene texture, its reference (element << TEXTURE_REF_LAYER_BITS | layer).
    pub refs: Vec<u32>,
}

impl TexturePool {
    /// The pool of `scene`'s textures: in order of first appearance of each (size, encoding),
    /// white first; an array that is full continues in a new element.
    pub fn of(scene: &Scene) -> Self {
        let data = data_textures(scene);
        let sizes: Vec<(u32, u32)> = scene.textures().iter().map(uploaded_size).collect();
        let mut arrays = vec![PoolArray { width: 1, height: 1, data: false, layers: vec![None] }];
        let mut refs = Vec::with_capacity(sizes.len());
        for (t, &(width, height)) in sizes.iter().enumerate() {
            let open = arrays.iter().rposition(|a| (a.width, a.height, a.data) == (width, height, data[t]) && a.layers.len() < POOL_LAYERS);
            let element = open.unwrap_or_else(|| {
                arrays.push(PoolArray { width, height, data: data[t], layers: Vec::new() });
                arrays.len() - 1
            });
            refs.push((element as u32) << TEXTURE_REF_LAYER_BITS | arrays[element].layers.len() as u32);
            arrays[element].layers.push(Some(t));
        }
        Self { arrays, refs }
    }
}

/// Each scene texture's reference as the records hold it: pooled where the scene's textures are
/// a binding array of [`TexturePool`] arrays, else the texture's index + 1.
pub fn texture_refs(scene: &Scene, pooled: bool) -> Vec<u32> {
    if pooled {
        TexturePool::of(scene).refs
    } else {
        (1..=scene.textures().len() as u32).collect()
    }
}

/// The reference of texture `t` in `refs` (0, plain white, for none or an index out of range).
pub fn texture_ref(refs: &[u32], t: Option<usize>) -> u32 {
    t.and_then(|t| refs.get(t)).copied().unwrap_or(0)
}

/// The size a texture is uploaded at: its own, or the fallback's where its texels do not match
/// its size (`runtime::scene_upload` uploads the fallback then).
pub fn uploaded_size(img: &TextureImage) -> (u32, u32) {
    if img.width > 0 && img.height > 0 && img.rgba.len() as u64 == img.width as u64 * img.height as u64 * 4 {
        (img.width, img.height)
    } else {
        let fallback = fallback_texture(&img.name);
        (fallback.width, fallback.height)
    }
}

/// Which textures hold data rather than colour: those that only data slots use (normal,
/// metallic-roughness, occlusion and the lobe extensions' but specular colour: glTF stores them
/// linearly). A texture a colour slot also uses stays colour.
pub fn data_textures(scene: &Scene) -> Vec<bool> {
    let n = scene.textures().len();
    let (mut colour, mut data) = (vec![false; n], vec![false; n]);
    for m in scene.materials().iter() {
        for (slot, t) in TextureSlot::ALL.iter().zip(m.slot_textures()) {
            if let Some(t) = t.filter(|t| *t < n) {
                if slot.is_colour() {
                    colour[t] = true;
                } else {
                    data[t] = true;
                }
            }
        }
    }
    (0..n).map(|t| data[t] && !colour[t]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::builtin::checker;
    use crate::scene::camera::Camera;

    /// A scene whose textures have `sizes`; material k samples texture k as its base colour,
    /// and the textures listed in `normal_only` as normal maps only (data).
    fn scene(sizes: &[u32], normal_only: &[usize]) -> Scene {
        let mut s = Scene::new("pool", Camera::default());
        for (k, &size) in sizes.iter().enumerate() {
            s.textures_mut().push(checker(&format!("t{k}"), size, 2, [255, 255, 255], [0, 0, 0]));
            let mut m = crate::scene::Material::diffuse(&format!("m{k}"), [1.0; 4], None);
            if normal_only.contains(&k) {
                m.normal_texture = Some(k);
            } else {
                m.texture = Some(k);
            }
            s.materials_mut().push(m);
        }
        s
    }

    #[test]
    fn textures_of_one_size_and_encoding_share_an_array() {
        let pool = TexturePool::of(&scene(&[64, 32, 64, 64, 1], &[3]));
        let sizes: Vec<(u32, u32, bool)> = pool.arrays.iter().map(|a| (a.width, a.height, a.data)).collect();
        assert_eq!(sizes, [(1, 1, false), (64, 64, false), (32, 32, false), (64, 64, true)]);
        assert_eq!(pool.arrays[0].layers, [None, Some(4)], "white first, then the 1x1 colour texture");
        assert_eq!(pool.arrays[1].layers, [Some(0), Some(2)]);
        let r = |element: u32, layer: u32| element << TEXTURE_REF_LAYER_BITS | layer;
        assert_eq!(pool.refs, [r(1, 0), r(2, 0), r(1, 1), r(3, 0), r(0, 1)]);
    }

    #[test]
    fn the_shaders_decode_references_with_the_same_bits() {
        let wgsl = include_str!("../../shaders/common/scene_textures_texels_bindless.wgsl");
        assert!(wgsl.contains(&format!("const TEXTURE_REF_LAYER_BITS: u32 = {TEXTURE_REF_LAYER_BITS}u;")));
    }

    #[test]
    fn a_full_array_continues_in_a_new_element() {
        let pool = TexturePool::of(&scene(&vec![8; POOL_LAYERS + 3], &[]));
        let layers: Vec<usize> = pool.arrays.iter().map(|a| a.layers.len()).collect();
        assert_eq!(layers, [1, POOL_LAYERS, 3]);
        assert_eq!(pool.refs[POOL_LAYERS], 2 << TEXTURE_REF_LAYER_BITS);
    }

    #[test]
    fn references_without_pooling_are_indices_plus_one_and_zero_is_white() {
        let s = scene(&[16, 8], &[]);
        assert_eq!(texture_refs(&s, false), [1, 2]);
        assert_eq!(texture_ref(&texture_refs(&s, true), None), 0);
        assert_eq!(texture_ref(&[5, 6], Some(7)), 0, "an index out of range reads white");
    }

    #[test]
    fn a_texture_whose_texels_do_not_match_its_size_is_pooled_at_the_fallbacks_size() {
        let mut s = scene(&[16], &[]);
        s.textures_mut()[0].width = 17;
        let fallback = fallback_texture("t0");
        assert_eq!(uploaded_size(&s.textures()[0]), (fallback.width, fallback.height));
    }
}
