//! Checkpoints (`--checkpoint FILE`, `--resume FILE`): the accumulated state of a render — the
//! film's sums, the units (samples per pixel, iterations) done, and the method's own state
//! (opaque here: the adaptive depth histograms, the radius scales) — written atomically by the
//! driver, so that a render stopped at any point continues to exactly the image an
//! uninterrupted render gives (every pixel sums its units in index order, and each unit depends
//! only on its index and the method's state).
//!
//! Format (little-endian): magic `QSRCKPT3`, fingerprint u64 (scene and settings), width u32,
//! height u32, done u32, pixel count u64, then per pixel 12 f64 layer sums, y_sq f64, 4 f64
//! layer y_sq, samples u64, rejected u64; then the block batch statistics: level count u64
//! (0: none), batches u64, and per level and block 5 f64 sums and 5 f64 sums of squares; then
//! the method state: length u64 and its bytes.

use std::fmt::Write as _;
use std::path::Path;

use crate::core::bytes::{ByteReader, ByteWriter};
use crate::core::sampling::mix64;
use crate::film::{BlockBatches, Film, N_LAYERS, N_QUANTITIES, PixelSum};

const MAGIC: &[u8; 8] = b"QSRCKPT3";

/// What a render has accumulated so far.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderState {
    /// Pixel sums.
    pub film: Film,
    /// Units (samples per pixel or iterations) of this render share done.
    pub done: u32,
    /// The method's own state ([`crate::integrator::pass::RenderMethod::save_state`]).
    pub method_state: Vec<u8>,
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

/// The bytes of `state` with `fingerprint`.
pub fn encode(fingerprint: u64, state: &RenderState) -> Vec<u8> {
    let mut w = ByteWriter::default();
    w.bytes(MAGIC);
    w.u64(fingerprint);
    w.u32(state.film.width);
    w.u32(state.film.height);
    w.u32(state.done);
    w.u64(state.film.pixels.len() as u64);
    for p in &state.film.pixels {
        p.xyz.iter().flatten().for_each(|&v| w.f64(v));
        w.f64(p.y_sq);
        p.layer_y_sq.iter().for_each(|&v| w.f64(v));
        w.u64(p.samples);
        w.u64(p.rejected);
    }
    match &state.film.blocks {
        None => w.u64(0),
        Some(b) => {
            w.u64(b.levels.len() as u64);
            w.u64(b.batches);
            for l in &b.levels {
                l.sum.iter().chain(&l.sum_sq).flatten().for_each(|&v| w.f64(v));
            }
        }
    }
    w.u64(state.method_state.len() as u64);
    w.bytes(&state.method_state);
    w.0
}

/// Writes `state` with `fingerprint` to `path` atomically.
pub fn write(path: &Path, fingerprint: u64, state: &RenderState) -> Result<(), String> {
    crate::output::write_atomic_bytes(path, &encode(fingerprint, state)).map_err(|e| e.to_string())
}

/// Decodes checkpoint bytes; errors say what is wrong, and a checkpoint of another scene or
/// other settings (`fingerprint`) is refused.
pub fn decode(bytes: &[u8], fingerprint: u64) -> Result<RenderState, String> {
    let mut r = ByteReader::new(bytes);
    if r.take(8).ok() != Some(&MAGIC[..]) {
        return Err("not a quasar checkpoint (or one of an older version)".into());
    }
    if r.u64()? != fingerprint {
        return Err("the checkpoint belongs to another scene or other render settings".into());
    }
    let (width, height, done) = (r.u32()?, r.u32()?, r.u32()?);
    let n = r.u64()?;
    if n != width as u64 * height as u64 || n > (bytes.len() / 152) as u64 {
        return Err(format!("pixel count {n} does not match {width}x{height} or the file size"));
    }
    let mut film = Film::new(width, height);
    for p in film.pixels.iter_mut() {
        let mut s = PixelSum::default();
        for l in 0..N_LAYERS {
            for k in 0..3 {
                s.xyz[l][k] = r.f64()?;
            }
        }
        s.y_sq = r.f64()?;
        for v in s.layer_y_sq.iter_mut() {
            *v = r.f64()?;
        }
        s.samples = r.u64()?;
        s.rejected = r.u64()?;
        *p = s;
    }
    let n_levels = r.u64()?;
    if n_levels > 0 {
        let mut blocks = BlockBatches::new(width as usize, height as usize);
        if n_levels != blocks.levels.len() as u64 {
            return Err(format!("{n_levels} block levels for a {width}x{height} image"));
        }
        blocks.batches = r.u64()?;
        for l in blocks.levels.iter_mut() {
            for v in l.sum.iter_mut().chain(l.sum_sq.iter_mut()) {
                for q in v.iter_mut().take(N_QUANTITIES) {
                    *q = r.f64()?;
                }
            }
        }
        film.blocks = Some(blocks);
    }
    let len = r.u64()? as usize;
    let method_state = r.take(len)?.to_vec();
    if r.remaining() != 0 {
        return Err("trailing bytes".into());
    }
    Ok(RenderState { film, done, method_state })
}

/// Reads a checkpoint file; errors name the file (see [`decode`]).
pub fn read(path: &Path, fingerprint: u64) -> Result<RenderState, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    decode(&bytes, fingerprint).map_err(|e| format!("{}: {e}", path.display()))
}
