//! A minimal glTF 2.0 writer: geometry goes into one binary buffer, everything else is given as
//! JSON object text. Used by the tests, the glTF benchmark and the showcase generator
//! (`cargo run --example gltf_showcase`); it is not a general exporter.

use std::fmt::Write as _;

/// One primitive of a mesh: accessor indices (from [`GltfWriter`]) and an optional material.
#[derive(Clone, Debug, Default)]
pub struct Prim {
    /// POSITION accessor.
    pub position: usize,
    /// NORMAL accessor.
    pub normal: Option<usize>,
    /// TEXCOORD_0 accessor.
    pub uv: Option<usize>,
    /// Index accessor.
    pub indices: Option<usize>,
    /// Material index.
    pub material: Option<usize>,
    /// Primitive mode (4 = triangles when `None`).
    pub mode: Option<u32>,
}

/// How [`GltfWriter::to_gltf`] stores the binary buffer.
#[derive(Clone, Debug)]
pub enum BinStorage {
    /// Inline as a base64 `data:` URI.
    DataUri,
    /// In an external file with this URI (the caller writes the returned bytes there).
    External(String),
}

/// Builds a glTF document (see the module documentation).
#[derive(Clone, Debug, Default)]
pub struct GltfWriter {
    bin: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
    /// `meshes` entries (JSON objects; [`GltfWriter::mesh`] adds them).
    pub meshes: Vec<String>,
    /// `nodes` entries (JSON objects).
    pub nodes: Vec<String>,
    /// `materials` entries.
    pub materials: Vec<String>,
    /// `cameras` entries.
    pub cameras: Vec<String>,
    /// `KHR_lights_punctual.lights` entries.
    pub lights: Vec<String>,
    /// `textures` entries.
    pub textures: Vec<String>,
    /// `images` entries.
    pub images: Vec<String>,
    /// `samplers` entries.
    pub samplers: Vec<String>,
    /// `skins` entries.
    pub skins: Vec<String>,
    /// `animations` entries.
    pub animations: Vec<String>,
    /// Root nodes of the scene.
    pub roots: Vec<usize>,
    /// `extensionsUsed`.
    pub extensions_used: Vec<String>,
    /// `extensionsRequired`.
    pub extensions_required: Vec<String>,
}

fn list(items: &[String]) -> String {
    format!("[{}]", items.join(","))
}

impl GltfWriter {
    /// An empty document.
    pub fn new() -> Self {
        Self::default()
    }

    fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let off = self.bin.len();
        self.bin.extend_from_slice(bytes);
        let t = target.map_or(String::new(), |t| format!(",\"target\":{t}"));
        self.views.push(format!("{{\"buffer\":0,\"byteOffset\":{off},\"byteLength\":{}{t}}}", bytes.len()));
        self.views.len() - 1
    }

    fn float_accessor(&mut self, data: &[f32], n: usize, ty: &str, minmax: bool) -> usize {
        let bytes: Vec<u8> = data.iter().flat_map(|v| v.to_le_bytes()).collect();
        let v = self.view(&bytes, Some(34962));
        let count = data.len() / n;
        let mut mm = String::new();
        if minmax && count > 0 {
            let lo: Vec<String> = (0..n)
                .map(|k| format!("{}", data.iter().skip(k).step_by(n).fold(f32::INFINITY, |a, &b| a.min(b))))
                .collect();
            let hi: Vec<String> = (0..n)
                .map(|k| format!("{}", data.iter().skip(k).step_by(n).fold(f32::NEG_INFINITY, |a, &b| a.max(b))))
                .collect();
            let _ = write!(mm, ",\"min\":[{}],\"max\":[{}]", lo.join(","), hi.join(","));
        }
        self.accessors
            .push(format!("{{\"bufferView\":{v},\"componentType\":5126,\"count\":{count},\"type\":\"{ty}\"{mm}}}"));
        self.accessors.len() - 1
    }

    /// A VEC3 FLOAT accessor with min/max (positions).
    pub fn positions(&mut self, p: &[[f32; 3]]) -> usize {
        self.float_accessor(p.as_flattened(), 3, "VEC3", true)
    }

    /// A VEC3 FLOAT accessor (normals).
    pub fn normals(&mut self, n: &[[f32; 3]]) -> usize {
        self.float_accessor(n.as_flattened(), 3, "VEC3", false)
    }

    /// A VEC2 FLOAT accessor (texture coordinates).
    pub fn uvs(&mut self, uv: &[[f32; 2]]) -> usize {
        self.float_accessor(uv.as_flattened(), 2, "VEC2", false)
    }

    /// A SCALAR UNSIGNED_INT index accessor.
    pub fn indices(&mut self, idx: &[u32]) -> usize {
        let bytes: Vec<u8> = idx.iter().flat_map(|v| v.to_le_bytes()).collect();
        let v = self.view(&bytes, Some(34963));
        self.accessors
            .push(format!("{{\"bufferView\":{v},\"componentType\":5125,\"count\":{},\"type\":\"SCALAR\"}}", idx.len()));
        self.accessors.len() - 1
    }

    /// An accessor over `bytes` stored as given: `count` elements of `ty` (`"VEC4"`, ...) with
    /// glTF component type `component` (5121 = UNSIGNED_BYTE, ...), `normalized` or not.
    pub fn raw_bytes_accessor(&mut self, bytes: &[u8], ty: &str, component: u32, normalized: bool) -> usize {
        let n = match ty {
            "SCALAR" => 1,
            "VEC2" => 2,
            "VEC3" => 3,
            _ => 4,
        };
        let size = match component {
            5121 | 5120 => 1,
            5123 | 5122 => 2,
            _ => 4,
        };
        let v = self.view(bytes, Some(34962));
        let count = bytes.len() / (n * size);
        self.accessors.push(format!(
            "{{\"bufferView\":{v},\"componentType\":{component},\"normalized\":{normalized},\"count\":{count},\"type\":\"{ty}\"}}"
        ));
        self.accessors.len() - 1
    }

    /// Adds a raw accessor object (for malformed-input tests); returns its index.
    pub fn raw_accessor(&mut self, json: &str) -> usize {
        self.accessors.push(json.to_owned());
        self.accessors.len() - 1
    }

    /// An image stored in the buffer (e.g. PNG bytes); returns the image index.
    pub fn image(&mut self, bytes: &[u8], mime: &str) -> usize {
        let v = self.view(bytes, None);
        self.images.push(format!("{{\"bufferView\":{v},\"mimeType\":\"{mime}\"}}"));
        self.images.len() - 1
    }

    /// A mesh of `prims` named `name`; returns the mesh index.
    pub fn mesh(&mut self, name: &str, prims: &[Prim]) -> usize {
        let ps: Vec<String> = prims
            .iter()
            .map(|p| {
                let mut a = format!("\"POSITION\":{}", p.position);
                if let Some(n) = p.normal {
                    let _ = write!(a, ",\"NORMAL\":{n}");
                }
                if let Some(t) = p.uv {
                    let _ = write!(a, ",\"TEXCOORD_0\":{t}");
                }
                let mut s = format!("{{\"attributes\":{{{a}}}");
                if let Some(i) = p.indices {
                    let _ = write!(s, ",\"indices\":{i}");
                }
                if let Some(m) = p.material {
                    let _ = write!(s, ",\"material\":{m}");
                }
                if let Some(m) = p.mode {
                    let _ = write!(s, ",\"mode\":{m}");
                }
                s + "}"
            })
            .collect();
        self.meshes.push(format!("{{\"name\":\"{name}\",\"primitives\":{}}}", list(&ps)));
        self.meshes.len() - 1
    }

    /// Appends a JSON object to `v` and returns its index.
    pub fn push(v: &mut Vec<String>, json: &str) -> usize {
        v.push(json.to_owned());
        v.len() - 1
    }

    /// Marks an extension as used (and required when `required`).
    pub fn use_extension(&mut self, name: &str, required: bool) {
        if !self.extensions_used.iter().any(|e| e == name) {
            self.extensions_used.push(name.to_owned());
        }
        if required && !self.extensions_required.iter().any(|e| e == name) {
            self.extensions_required.push(name.to_owned());
        }
    }

    /// The JSON document; `buffer_uri` = `None` for a GLB (the buffer is the binary chunk).
    fn json(&self, buffer_uri: Option<&str>) -> String {
        let q = |s: &String| format!("\"{s}\"");
        let mut j = String::from("{\"asset\":{\"version\":\"2.0\",\"generator\":\"quasar gltf writer\"}");
        let uri = buffer_uri.map_or(String::new(), |u| format!(",\"uri\":\"{u}\""));
        let _ = write!(j, ",\"buffers\":[{{\"byteLength\":{}{uri}}}]", self.bin.len());
        for (k, v) in [
            ("bufferViews", &self.views),
            ("accessors", &self.accessors),
            ("meshes", &self.meshes),
            ("nodes", &self.nodes),
            ("materials", &self.materials),
            ("cameras", &self.cameras),
            ("textures", &self.textures),
            ("images", &self.images),
            ("samplers", &self.samplers),
            ("skins", &self.skins),
            ("animations", &self.animations),
        ] {
            if !v.is_empty() {
                let _ = write!(j, ",\"{k}\":{}", list(v));
            }
        }
        let roots: Vec<String> = self.roots.iter().map(|r| r.to_string()).collect();
        let _ = write!(j, ",\"scene\":0,\"scenes\":[{{\"nodes\":[{}]}}]", roots.join(","));
        if !self.lights.is_empty() {
            let _ = write!(j, ",\"extensions\":{{\"KHR_lights_punctual\":{{\"lights\":{}}}}}", list(&self.lights));
        }
        if !self.extensions_used.is_empty() {
            let _ = write!(j, ",\"extensionsUsed\":{}", list(&self.extensions_used.iter().map(q).collect::<Vec<_>>()));
        }
        if !self.extensions_required.is_empty() {
            let _ = write!(
                j,
                ",\"extensionsRequired\":{}",
                list(&self.extensions_required.iter().map(q).collect::<Vec<_>>())
            );
        }
        j + "}"
    }

    /// A `.gltf` document (JSON text) and the bytes of the external buffer file (empty with
    /// [`BinStorage::DataUri`]).
    pub fn to_gltf(&self, storage: &BinStorage) -> (String, Vec<u8>) {
        use base64::Engine;
        match storage {
            BinStorage::DataUri => {
                let b64 = base64::engine::general_purpose::STANDARD.encode(&self.bin);
                (self.json(Some(&format!("data:application/octet-stream;base64,{b64}"))), Vec::new())
            }
            BinStorage::External(uri) => (self.json(Some(uri)), self.bin.clone()),
        }
    }

    /// A `.glb` file.
    pub fn to_glb(&self) -> Vec<u8> {
        let mut json = self.json(None).into_bytes();
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
}
