//! A tiny glTF 2.0 writer for tests: builds a document (JSON) and its binary buffer by hand,
//! so tests can cover every attribute type, index width and malformed case on purpose.

use base64::Engine;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

pub const BYTE: u32 = 5121;
pub const SHORT_U: u32 = 5123;
pub const UINT: u32 = 5125;
pub const FLOAT: u32 = 5126;

/// A document under construction.
pub struct Doc {
    pub json: Value,
    pub bin: Vec<u8>,
}

impl Doc {
    pub fn new() -> Self {
        Doc {
            json: json!({
                "asset": {"version": "2.0", "generator": "raygraph tests"},
                "buffers": [], "bufferViews": [], "accessors": [], "meshes": [], "nodes": [],
                "materials": [], "textures": [], "images": [], "samplers": [],
                "scenes": [{"nodes": []}], "scene": 0
            }),
            bin: Vec::new(),
        }
    }

    fn push(&mut self, key: &str, v: Value) -> usize {
        let a = self.json[key].as_array_mut().unwrap();
        a.push(v);
        a.len() - 1
    }

    /// Appends raw bytes as a buffer view (4-byte aligned).
    pub fn view(&mut self, bytes: &[u8]) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.push("bufferViews", json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len()}))
    }

    /// An accessor over a new view holding `bytes`.
    pub fn accessor(&mut self, bytes: &[u8], component: u32, ty: &str, count: usize, normalized: bool, minmax: Option<(Vec<f32>, Vec<f32>)>) -> usize {
        let view = self.view(bytes);
        let mut a = json!({"bufferView": view, "componentType": component, "type": ty, "count": count});
        if normalized {
            a["normalized"] = json!(true);
        }
        if let Some((min, max)) = minmax {
            a["min"] = json!(min);
            a["max"] = json!(max);
        }
        self.push("accessors", a)
    }

    /// Positions (VEC3 float) with min/max computed over the finite values.
    pub fn positions(&mut self, p: &[[f32; 3]]) -> usize {
        let mut min = vec![f32::MAX; 3];
        let mut max = vec![f32::MIN; 3];
        for v in p {
            for c in 0..3 {
                if v[c].is_finite() {
                    min[c] = min[c].min(v[c]);
                    max[c] = max[c].max(v[c]);
                }
            }
        }
        self.accessor(bytemuck::cast_slice(p), FLOAT, "VEC3", p.len(), false, Some((min, max)))
    }

    pub fn floats(&mut self, data: &[f32], ty: &str, count: usize) -> usize {
        self.accessor(bytemuck::cast_slice(data), FLOAT, ty, count, false, None)
    }

    pub fn indices_u8(&mut self, i: &[u8]) -> usize {
        self.accessor(i, BYTE, "SCALAR", i.len(), false, None)
    }

    pub fn indices_u16(&mut self, i: &[u16]) -> usize {
        self.accessor(bytemuck::cast_slice(i), SHORT_U, "SCALAR", i.len(), false, None)
    }

    pub fn indices_u32(&mut self, i: &[u32]) -> usize {
        self.accessor(bytemuck::cast_slice(i), UINT, "SCALAR", i.len(), false, None)
    }

    /// A mesh with one primitive; `attributes` maps semantic to accessor.
    pub fn mesh(&mut self, attributes: &[(&str, usize)], indices: Option<usize>, material: Option<usize>, mode: Option<u32>) -> usize {
        let mut attrs = serde_json::Map::new();
        for (k, v) in attributes {
            attrs.insert(k.to_string(), json!(v));
        }
        let mut prim = json!({"attributes": attrs});
        if let Some(i) = indices {
            prim["indices"] = json!(i);
        }
        if let Some(m) = material {
            prim["material"] = json!(m);
        }
        if let Some(m) = mode {
            prim["mode"] = json!(m);
        }
        self.push("meshes", json!({"primitives": [prim]}))
    }

    /// Adds a node; roots are listed in the scene.
    pub fn node(&mut self, node: Value, root: bool) -> usize {
        let n = self.push("nodes", node);
        if root {
            self.json["scenes"][0]["nodes"].as_array_mut().unwrap().push(json!(n));
        }
        n
    }

    pub fn material(&mut self, m: Value) -> usize {
        self.push("materials", m)
    }

    /// A texture of an image at `uri` (an external file or a data URI).
    pub fn texture_uri(&mut self, uri: &str) -> usize {
        let image = self.push("images", json!({"uri": uri}));
        let sampler = self.push("samplers", json!({"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 33648}));
        self.push("textures", json!({"source": image, "sampler": sampler}))
    }

    /// A texture of a PNG stored in the binary buffer.
    pub fn texture_embedded(&mut self, png: &[u8]) -> usize {
        let view = self.view(png);
        let image = self.push("images", json!({"bufferView": view, "mimeType": "image/png"}));
        self.push("textures", json!({"source": image}))
    }

    fn with_buffer(&self, uri: Option<String>) -> Value {
        let mut j = self.json.clone();
        let mut b = json!({"byteLength": self.bin.len()});
        if let Some(u) = uri {
            b["uri"] = json!(u);
        }
        j["buffers"] = json!([b]);
        j
    }

    /// `dir/name.gltf` with the buffer in `dir/name.bin`.
    pub fn write_gltf_external(&self, dir: &Path, name: &str) -> PathBuf {
        std::fs::write(dir.join(format!("{name}.bin")), &self.bin).unwrap();
        let path = dir.join(format!("{name}.gltf"));
        std::fs::write(&path, serde_json::to_string_pretty(&self.with_buffer(Some(format!("{name}.bin")))).unwrap()).unwrap();
        path
    }

    /// `dir/name.gltf` with the buffer embedded as a base64 data URI.
    pub fn write_gltf_embedded(&self, dir: &Path, name: &str) -> PathBuf {
        let uri = format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(&self.bin));
        let path = dir.join(format!("{name}.gltf"));
        std::fs::write(&path, serde_json::to_string(&self.with_buffer(Some(uri))).unwrap()).unwrap();
        path
    }

    /// GLB bytes (JSON chunk + BIN chunk).
    pub fn glb_bytes(&self) -> Vec<u8> {
        let mut json = serde_json::to_vec(&self.with_buffer(None)).unwrap();
        while !json.len().is_multiple_of(4) {
            json.push(b' ');
        }
        let mut bin = self.bin.clone();
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let total = 12 + 8 + json.len() + 8 + bin.len();
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(json.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&json);
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
        out
    }

    pub fn write_glb(&self, dir: &Path, name: &str) -> PathBuf {
        let path = dir.join(format!("{name}.glb"));
        std::fs::write(&path, self.glb_bytes()).unwrap();
        path
    }
}

/// A solid-colour PNG.
pub fn png(w: u32, h: u32, rgba: [u8; 4]) -> Vec<u8> {
    let img = image::RgbaImage::from_pixel(w, h, image::Rgba(rgba));
    let mut out = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut out), image::ImageFormat::Png).unwrap();
    out
}

/// A fresh empty directory under the system temp dir.
pub fn temp_dir(tag: &str) -> PathBuf {
    static N: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
    let n = N.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
    let d = std::env::temp_dir().join(format!("raygraph-{tag}-{}-{n}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}
