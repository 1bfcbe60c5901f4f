//! Checkpoints (`--checkpoint FILE`, `--resume FILE`): the accumulated state of a render — pixel
//! sums, sample (iteration) count and, for the adaptive methods, the depth histograms — written
//! atomically at the end of passes, so that a render stopped at any point continues to exactly
//! the image an uninterrupted render gives (every pixel sums its samples in index order, and each
//! iteration depends only on its index and the stored histograms).
//!
//! Format (little-endian): magic `QSRCKPT2`, fingerprint u64 (scene and settings), width u32,
//! height u32, done u32, next u32, pixel count u64, then per pixel 12 f64 layer sums, y_sq f64,
//! 4 f64 layer y_sq, samples u64, rejected u64; then the block batch statistics: level count
//! u64 (0: none), batches u64, and per level and block 5 f64 sums and 5 f64 sums of squares;
//! then histogram count u64 and 8 u32 per pixel; then depth sums u64 and counts u32 per pixel
//! (count u64 first); then radius scale count u64 and one f32 per pixel.

use std::fmt::Write as _;
use std::io::{Read, Write};
use std::path::Path;

use crate::core::sampling::mix64;
use crate::film::{Film, N_LAYERS, N_QUANTITIES, PixelSum};

const MAGIC: &[u8; 8] = b"QSRCKPT2";

/// What a render has accumulated so far.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderState {
    /// Pixel sums.
    pub film: Film,
    /// Samples per pixel (pt) or iterations (bidirectional methods) accumulated.
    pub done: u32,
    /// Next sample / iteration index to render.
    pub next: u32,
    /// Adaptive depth histograms (empty for other methods).
    pub histogram: Vec<[u32; 8]>,
    /// Per-pixel sum of the gather depths used (bidirectional methods).
    pub depth_sum: Vec<u64>,
    /// Per-pixel number of iterations with a gather depth.
    pub depth_count: Vec<u32>,
    /// Per-pixel scale of the automatic gather radius (bidirectional methods; empty before the
    /// pilot).
    pub radius_scales: Vec<f32>,
}

/// A fingerprint of everything that must match for a resume: fed by `Debug` output in chunks,
/// never materialised (a million-triangle scene would make a huge string).
#[derive(Default)]
pub struct Fingerprint(u64);

impl std::fmt::Write for Fingerprint {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        for chunk in s.as_bytes().chunks(8) {
            let mut b = [0u8; 8];
            b[..chunk.len()].copy_from_slice(chunk);
            self.0 = mix64(self.0 ^ u64::from_le_bytes(b)).wrapping_add(chunk.len() as u64);
        }
        Ok(())
    }
}

impl Fingerprint {
    /// The fingerprint of `things` (their `Debug` forms).
    pub fn of(things: &[&dyn std::fmt::Debug]) -> u64 {
        let mut f = Fingerprint(0x51ab_c0de);
        for t in things {
            let _ = write!(f, "{t:?}|");
        }
        f.0
    }
}

fn put_u32(w: &mut Vec<u8>, v: u32) {
    w.extend_from_slice(&v.to_le_bytes());
}
fn put_u64(w: &mut Vec<u8>, v: u64) {
    w.extend_from_slice(&v.to_le_bytes());
}

/// Writes `state` with `fingerprint` to `path` atomically (temporary file + rename).
pub fn write(path: &Path, fingerprint: u64, state: &RenderState) -> Result<(), String> {
    let mut w = Vec::with_capacity(state.film.pixels.len() * 160 + 64);
    w.extend_from_slice(MAGIC);
    put_u64(&mut w, fingerprint);
    put_u32(&mut w, state.film.width);
    put_u32(&mut w, state.film.height);
    put_u32(&mut w, state.done);
    put_u32(&mut w, state.next);
    put_u64(&mut w, state.film.pixels.len() as u64);
    for p in &state.film.pixels {
        for layer in &p.xyz {
            for v in layer {
                w.extend_from_slice(&v.to_le_bytes());
            }
        }
        w.extend_from_slice(&p.y_sq.to_le_bytes());
        for v in &p.layer_y_sq {
            w.extend_from_slice(&v.to_le_bytes());
        }
        put_u64(&mut w, p.samples);
        put_u64(&mut w, p.rejected);
    }
    match &state.film.blocks {
        None => put_u64(&mut w, 0),
        Some(b) => {
            put_u64(&mut w, b.levels.len() as u64);
            put_u64(&mut w, b.batches);
            for l in &b.levels {
                for v in l.sum.iter().chain(&l.sum_sq).flatten() {
                    w.extend_from_slice(&v.to_le_bytes());
                }
            }
        }
    }
    put_u64(&mut w, state.histogram.len() as u64);
    for h in &state.histogram {
        for c in h {
            put_u32(&mut w, *c);
        }
    }
    put_u64(&mut w, state.depth_sum.len() as u64);
    for (s, c) in state.depth_sum.iter().zip(&state.depth_count) {
        put_u64(&mut w, *s);
        put_u32(&mut w, *c);
    }
    put_u64(&mut w, state.radius_scales.len() as u64);
    for v in &state.radius_scales {
        put_u32(&mut w, v.to_bits());
    }
    let tmp = path.with_file_name(format!(
        ".{}.tmp{}",
        path.file_name().map_or("checkpoint".into(), |n| n.to_string_lossy()),
        std::process::id()
    ));
    let err = |e: std::io::Error| format!("{}: {e}", path.display());
    let mut f = std::fs::File::create(&tmp).map_err(err)?;
    f.write_all(&w).map_err(err)?;
    f.sync_all().map_err(err)?;
    std::fs::rename(&tmp, path).map_err(err)
}

/// [`write`], reporting a failure on stderr instead of failing the render (a render must not be
/// lost because its checkpoint could not be written).
pub fn save(path: &Path, fingerprint: u64, state: &RenderState) {
    if let Err(e) = write(path, fingerprint, state) {
        eprintln!("warning: checkpoint not written: {e}");
    }
}

struct Reader<'a> {
    b: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8], String> {
        let s = self.b.get(self.at..self.at + n).ok_or("truncated checkpoint")?;
        self.at += n;
        Ok(s)
    }
    fn u32(&mut self) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().unwrap_or_default()))
    }
    fn u64(&mut self) -> Result<u64, String> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().unwrap_or_default()))
    }
    fn f64(&mut self) -> Result<f64, String> {
        Ok(f64::from_bits(self.u64()?))
    }
}

/// Reads a checkpoint; errors name the file and what is wrong, and a checkpoint of another scene
/// or other settings (`fingerprint`) is refused.
pub fn read(path: &Path, fingerprint: u64) -> Result<RenderState, String> {
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|mut f| f.read_to_end(&mut bytes))
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let e = |m: String| format!("{}: {m}", path.display());
    let mut r = Reader { b: &bytes, at: 0 };
    if r.take(8).map_err(e)? != MAGIC {
        return Err(e("not a quasar checkpoint".into()));
    }
    if r.u64().map_err(e)? != fingerprint {
        return Err(e("the checkpoint belongs to another scene or other render settings".into()));
    }
    let (width, height, done, next) =
        (r.u32().map_err(e)?, r.u32().map_err(e)?, r.u32().map_err(e)?, r.u32().map_err(e)?);
    let n = r.u64().map_err(e)?;
    if n != width as u64 * height as u64 || n > (bytes.len() / 152) as u64 {
        return Err(e(format!("pixel count {n} does not match {width}x{height} or the file size")));
    }
    let mut film = Film::new(width, height);
    for p in film.pixels.iter_mut() {
        let mut s = PixelSum::default();
        for l in 0..N_LAYERS {
            for k in 0..3 {
                s.xyz[l][k] = r.f64().map_err(e)?;
            }
        }
        s.y_sq = r.f64().map_err(e)?;
        for v in s.layer_y_sq.iter_mut() {
            *v = r.f64().map_err(e)?;
        }
        s.samples = r.u64().map_err(e)?;
        s.rejected = r.u64().map_err(e)?;
        *p = s;
    }
    let n_levels = r.u64().map_err(e)?;
    if n_levels > 0 {
        let mut blocks = crate::film::BlockBatches::new(width as usize, height as usize);
        if n_levels != blocks.levels.len() as u64 {
            return Err(e(format!("{n_levels} block levels for a {width}x{height} image")));
        }
        blocks.batches = r.u64().map_err(e)?;
        for l in blocks.levels.iter_mut() {
            for v in l.sum.iter_mut().chain(l.sum_sq.iter_mut()) {
                for q in v.iter_mut().take(N_QUANTITIES) {
                    *q = r.f64().map_err(e)?;
                }
            }
        }
        film.blocks = Some(blocks);
    }
    let nh = r.u64().map_err(e)?;
    if nh != 0 && nh != n {
        return Err(e("histogram size does not match".into()));
    }
    let mut histogram = Vec::with_capacity(nh as usize);
    for _ in 0..nh {
        let mut h = [0u32; 8];
        for c in h.iter_mut() {
            *c = r.u32().map_err(e)?;
        }
        histogram.push(h);
    }
    let nd = r.u64().map_err(e)?;
    if nd != 0 && nd != n {
        return Err(e("depth sums size does not match".into()));
    }
    let (mut depth_sum, mut depth_count) = (Vec::with_capacity(nd as usize), Vec::with_capacity(nd as usize));
    for _ in 0..nd {
        depth_sum.push(r.u64().map_err(e)?);
        depth_count.push(r.u32().map_err(e)?);
    }
    let nr = r.u64().map_err(e)?;
    if nr != 0 && nr != n {
        return Err(e("radius scales size does not match".into()));
    }
    let radius_scales = (0..nr).map(|_| r.u32().map(f32::from_bits)).collect::<Result<Vec<_>, _>>().map_err(e)?;
    if r.at != bytes.len() {
        return Err(e("trailing bytes".into()));
    }
    Ok(RenderState { film, done, next, histogram, depth_sum, depth_count, radius_scales })
}
