//! Bounds-checked reading of glTF accessors (the `gltf` crate's reader trusts offsets and strides;
//! here every range is checked in u64 before any slice or allocation).

use std::path::Path;

use glam::{Vec2, Vec3};
use gltf::accessor::{Accessor, DataType, Dimensions};

use super::err;
use crate::error::{ImportError, ImportErrorKind};

/// Largest element count of one accessor (vertices or indices).
pub const MAX_ACCESSOR_COUNT: u64 = 1 << 30;
/// Largest element count of an accessor without a buffer view (all zeros: nothing in the file
/// bounds it).
pub const MAX_ZERO_ACCESSOR_COUNT: u64 = 1 << 20;

/// The loaded buffers of a glTF file and the file, for messages.
pub(super) struct Buffers<'a> {
    /// The glTF file.
    pub file: &'a Path,
    /// Buffer data by buffer index (at least `byteLength` bytes each).
    pub data: &'a [Vec<u8>],
}

fn component_size(t: DataType) -> usize {
    match t {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    }
}

fn dims(d: Dimensions) -> usize {
    match d {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 | Dimensions::Mat2 => 4,
        Dimensions::Mat3 => 9,
        Dimensions::Mat4 => 16,
    }
}

/// One component at `b` (little-endian) as f32; normalised integers map to [0, 1] / [-1, 1].
fn component(b: &[u8], t: DataType, normalized: bool) -> f32 {
    match t {
        DataType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        DataType::U8 if normalized => f32::from(b[0]) / 255.0,
        DataType::U16 if normalized => f32::from(u16::from_le_bytes([b[0], b[1]])) / 65535.0,
        DataType::I8 if normalized => (f32::from(b[0] as i8) / 127.0).max(-1.0),
        DataType::I16 if normalized => (f32::from(i16::from_le_bytes([b[0], b[1]])) / 32767.0).max(-1.0),
        DataType::U8 => f32::from(b[0]),
        DataType::I8 => f32::from(b[0] as i8),
        DataType::U16 => f32::from(u16::from_le_bytes([b[0], b[1]])),
        DataType::I16 => f32::from(i16::from_le_bytes([b[0], b[1]])),
        DataType::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
    }
}

/// The checked location of an accessor's elements (`stride` 0: all zeros, no data).
struct Layout<'b> {
    data: &'b [u8],
    start: usize,
    stride: usize,
    size: usize,
    count: usize,
}

impl Layout<'_> {
    /// Calls `f` with the bytes of every element.
    fn for_each(&self, mut f: impl FnMut(&[u8])) {
        if self.stride == 0 {
            let zeros = vec![0u8; self.size];
            (0..self.count).for_each(|_| f(&zeros));
            return;
        }
        for i in 0..self.count {
            let s = self.start + i * self.stride;
            f(&self.data[s..s + self.size]);
        }
    }
}

impl<'a> Buffers<'a> {
    /// Where the elements of `acc` are, after checking that the accessor's type is one of
    /// `allowed` with `want` components and that all its bytes lie in its buffer view and buffer
    /// (so nothing is allocated for a count the file does not back). `pointer` is the JSON
    /// pointer of the reference, for messages.
    fn layout(
        &self,
        acc: &Accessor<'_>,
        pointer: &str,
        want: usize,
        allowed: &[DataType],
    ) -> Result<Layout<'a>, ImportError> {
        let at = format!("{pointer} (accessor {})", acc.index());
        let invalid = |msg: String| err(ImportErrorKind::InvalidValue, self.file, &at, msg);
        if acc.sparse().is_some() {
            return Err(err(ImportErrorKind::Unsupported, self.file, &at, "sparse accessors are not supported here"));
        }
        let (t, n) = (acc.data_type(), dims(acc.dimensions()));
        if n != want || !allowed.contains(&t) {
            return Err(invalid(format!("has {n} components of type {t:?}; expected {want} of {allowed:?}")));
        }
        let count = acc.count() as u64;
        if count > MAX_ACCESSOR_COUNT {
            return Err(err(
                ImportErrorKind::TooLarge,
                self.file,
                &at,
                format!("count {count} is more than the limit of {MAX_ACCESSOR_COUNT}"),
            ));
        }
        let size = (component_size(t) * n) as u64;
        let Some(view) = acc.view() else {
            // no buffer view: all zeros (glTF 2.0 section 3.6.2.3)
            if count > MAX_ZERO_ACCESSOR_COUNT {
                return Err(err(
                    ImportErrorKind::TooLarge,
                    self.file,
                    &at,
                    format!("count {count} of an accessor without bufferView is more than {MAX_ZERO_ACCESSOR_COUNT}"),
                ));
            }
            return Ok(Layout { data: &[], start: 0, stride: 0, size: size as usize, count: count as usize });
        };
        if count == 0 {
            return Ok(Layout { data: &[], start: 0, stride: 0, size: size as usize, count: 0 });
        }
        let stride = view.stride().map_or(size, |s| s as u64);
        if stride < size {
            return Err(invalid(format!(
                "buffer view {} stride {stride} is smaller than the element size {size}",
                view.index()
            )));
        }
        let vstart = view.offset() as u64;
        let vlen = view.length() as u64;
        let buffer = view.buffer().index();
        let data = self.data.get(buffer).ok_or_else(|| invalid(format!("buffer {buffer} does not exist")))?;
        let vend = vstart.checked_add(vlen).filter(|&e| e <= data.len() as u64).ok_or_else(|| {
            invalid(format!(
                "buffer view {} (bytes {vstart}..+{vlen}) lies outside buffer {buffer} ({} bytes)",
                view.index(),
                data.len()
            ))
        })?;
        let start = vstart + acc.offset() as u64;
        let end = (count - 1).checked_mul(stride).and_then(|x| x.checked_add(size)).and_then(|x| x.checked_add(start));
        match end {
            Some(e) if e <= vend => {}
            _ => {
                return Err(invalid(format!(
                    "{count} elements of {size} bytes (stride {stride}) at offset {} do not fit in buffer view {} ({vlen} bytes)",
                    acc.offset(),
                    view.index()
                )));
            }
        }
        Ok(Layout { data, start: start as usize, stride: stride as usize, size: size as usize, count: count as usize })
    }

    /// A VEC3 FLOAT accessor (positions, normals); every value must be finite.
    pub fn vec3(&self, acc: &Accessor<'_>, pointer: &str) -> Result<Vec<Vec3>, ImportError> {
        let l = self.layout(acc, pointer, 3, &[DataType::F32])?;
        let mut out = Vec::with_capacity(l.count);
        l.for_each(|b| {
            out.push(Vec3::new(
                component(&b[0..4], DataType::F32, false),
                component(&b[4..8], DataType::F32, false),
                component(&b[8..12], DataType::F32, false),
            ))
        });
        if let Some(i) = out.iter().position(|v| !v.is_finite()) {
            return Err(err(
                ImportErrorKind::InvalidValue,
                self.file,
                pointer,
                format!("element {i} of accessor {} is not finite: {}", acc.index(), out[i]),
            ));
        }
        Ok(out)
    }

    /// A VEC2 texture-coordinate accessor (FLOAT, or normalised UNSIGNED_BYTE/SHORT).
    pub fn vec2(&self, acc: &Accessor<'_>, pointer: &str) -> Result<Vec<Vec2>, ImportError> {
        let (t, norm) = (acc.data_type(), acc.normalized());
        let allowed: &[DataType] = if norm { &[DataType::U8, DataType::U16] } else { &[DataType::F32] };
        let cs = component_size(t);
        let l = self.layout(acc, pointer, 2, allowed)?;
        let mut out = Vec::with_capacity(l.count);
        l.for_each(|b| out.push(Vec2::new(component(&b[..cs], t, norm), component(&b[cs..2 * cs], t, norm))));
        Ok(out)
    }

    /// A vertex-colour accessor (`COLOR_0`: VEC3 or VEC4, FLOAT or normalised UNSIGNED_BYTE/SHORT)
    /// as linear RGB (alpha dropped); non-finite or negative values become 0.
    pub fn colors(&self, acc: &Accessor<'_>, pointer: &str) -> Result<Vec<[f32; 3]>, ImportError> {
        let (t, norm) = (acc.data_type(), acc.normalized());
        let allowed: &[DataType] = if norm { &[DataType::U8, DataType::U16] } else { &[DataType::F32] };
        let want = dims(acc.dimensions()).clamp(3, 4);
        let cs = component_size(t);
        let l = self.layout(acc, pointer, want, allowed)?;
        let mut out = Vec::with_capacity(l.count);
        l.for_each(|b| {
            out.push(std::array::from_fn(|k| {
                let v = component(&b[k * cs..(k + 1) * cs], t, norm);
                if v.is_finite() { v.max(0.0) } else { 0.0 }
            }))
        });
        Ok(out)
    }

    /// A SCALAR index accessor (UNSIGNED_BYTE/SHORT/INT); every index must be < `vertices`.
    pub fn indices(&self, acc: &Accessor<'_>, pointer: &str, vertices: usize) -> Result<Vec<u32>, ImportError> {
        let t = acc.data_type();
        let l = self.layout(acc, pointer, 1, &[DataType::U8, DataType::U16, DataType::U32])?;
        let mut out = Vec::with_capacity(l.count);
        l.for_each(|b| {
            out.push(match t {
                DataType::U8 => u32::from(b[0]),
                DataType::U16 => u32::from(u16::from_le_bytes([b[0], b[1]])),
                _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            })
        });
        if let Some(i) = out.iter().position(|&v| v as usize >= vertices) {
            return Err(err(
                ImportErrorKind::InvalidValue,
                self.file,
                pointer,
                format!("index {i} of accessor {} is {}, but there are only {vertices} vertices", acc.index(), out[i]),
            ));
        }
        Ok(out)
    }
}
