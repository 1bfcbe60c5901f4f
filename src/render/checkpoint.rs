//! Checkpoints (`--checkpoint FILE`, `--resume FILE`): the accumulated state of a render — the
//! film's sums, the units (samples per pixel, iterations) done, and the method's own state
//! (opaque here: the adaptive depth histograms, the radius scales) — written atomically by the
//! driver, so that a render stopped at any point continues to exactly the image an
//! uninterrupted render gives (every pixel sums its units in index order, and each unit depends
//! only on its index and the method's state).
//!
//! Format (little-endian): magic [`MAGIC`] (`QSRCKPT5`), the resume key (count u64, then per setting its name
//! and value, each as length u64 and UTF-8 bytes), width u32,
//! height u32, done u32, pixel count u64, then per pixel 12 f64 layer sums, y_sq f64, 4 f64
//! layer y_sq, samples u64, rejected u64; then the block batch statistics: level count u64
//! (0: none), batches u64, and per level and block 5 f64 sums and 5 f64 sums of squares; then
//! the method state: length u64 and its bytes.

use std::fmt::Write as _;
use std::path::Path;

use crate::core::bytes::{ByteReader, ByteWriter};
use crate::core::sampling::mix64;
use crate::film::{BlockBatches, Film, N_LAYERS, N_QUANTITIES, PixelSum, SpectralBins};

/// The first bytes of a checkpoint: the format and its version (a new layout, a new version).
pub const MAGIC: &[u8; 8] = b"QSRCKPT5";

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

/// What must match for a resume, setting by setting (name, value): the scene's content hash, the
/// method, image size, seed, shard, masking and every method parameter but the sample budget
/// (one left at its default as the default's text).
/// Kept as text in the checkpoint so that a mismatch names the setting that differs.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ResumeKey(pub Vec<(String, String)>);

impl ResumeKey {
    /// The settings of `self` (the render asked for) that differ from `stored` (the
    /// checkpoint's), as `name VALUE (the checkpoint has OLD)`; None when they match.
    pub fn mismatch(&self, stored: &ResumeKey) -> Option<String> {
        let get = |k: &ResumeKey, name: &str| k.0.iter().find(|(n, _)| n == name).map(|(_, v)| v.clone());
        let mut names: Vec<&str> = self.0.iter().map(|(n, _)| n.as_str()).collect();
        names.extend(stored.0.iter().map(|(n, _)| n.as_str()).filter(|n| !self.0.iter().any(|(m, _)| m == n)));
        let diffs: Vec<String> = names
            .into_iter()
            .filter_map(|n| {
                let (now, then) = (get(self, n), get(stored, n));
                (now != then).then(|| {
                    let show = |v: Option<String>| v.unwrap_or_else(|| "unset".into());
                    format!("{n} {} (the checkpoint has {})", show(now), show(then))
                })
            })
            .collect();
        (!diffs.is_empty()).then(|| diffs.join(", "))
    }
}

/// The bytes of `state` with its resume `key`.
pub fn encode(key: &ResumeKey, state: &RenderState) -> Vec<u8> {
    let mut w = ByteWriter::default();
    w.bytes(MAGIC);
    w.u64(key.0.len() as u64);
    for (n, v) in &key.0 {
        for t in [n, v] {
            w.u64(t.len() as u64);
            w.bytes(t.as_bytes());
        }
    }
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
    match &state.film.spectral {
        None => w.u32(0),
        Some(s) => {
            let (min, max) = s.bins.range_nm();
            w.u32(s.bins.count() as u32);
            w.f64(min as f64);
            w.f64(max as f64);
            s.sums.iter().for_each(|&v| w.f64(v));
        }
    }
    w.u64(state.method_state.len() as u64);
    w.bytes(&state.method_state);
    w.0
}

/// Writes `state` with its resume `key` to `path` atomically.
pub fn write(path: &Path, key: &ResumeKey, state: &RenderState) -> Result<(), String> {
    crate::output::write_atomic_bytes(path, &encode(key, state)).map_err(|e| e.to_string())
}

/// Longest name or value of a resume key setting read back (bytes).
const MAX_KEY_TEXT: u64 = 1 << 16;

/// Decodes checkpoint bytes; errors say what is wrong, and a checkpoint of another scene or
/// other settings than `key` is refused, naming the settings that differ.
pub fn decode(bytes: &[u8], key: &ResumeKey) -> Result<RenderState, String> {
    let mut r = ByteReader::new(bytes);
    if r.take(8).ok() != Some(&MAGIC[..]) {
        return Err("not a quasar checkpoint (or one of an older version)".into());
    }
    let count = r.u64()?;
    if count > 1024 {
        return Err(format!("{count} settings in the resume key"));
    }
    let mut stored = ResumeKey::default();
    for _ in 0..count {
        let mut text = || -> Result<String, String> {
            let len = r.u64()?;
            if len > MAX_KEY_TEXT {
                return Err(format!("a resume key entry of {len} bytes"));
            }
            String::from_utf8(r.take(len as usize)?.to_vec()).map_err(|_| "a resume key entry is not UTF-8".to_string())
        };
        let name = text()?;
        stored.0.push((name, text()?));
    }
    if let Some(diff) = key.mismatch(&stored) {
        return Err(format!("the checkpoint belongs to another scene or other render settings: {diff}"));
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
    let n_bins = r.u32()?;
    if n_bins > 0 {
        let (min, max) = (r.f64()? as f32, r.f64()? as f32);
        let bins = SpectralBins::new(n_bins, min, max)?;
        if n * n_bins as u64 > (r.remaining() / 8) as u64 {
            return Err(format!("{n_bins} spectral bins per pixel do not fit the file size"));
        }
        film = film.with_spectral(bins);
        if let Some(s) = film.spectral.as_mut() {
            for v in s.sums.iter_mut() {
                *v = r.f64()?;
            }
        }
    }
    let len = r.u64()? as usize;
    let method_state = r.take(len)?.to_vec();
    if r.remaining() != 0 {
        return Err("trailing bytes".into());
    }
    Ok(RenderState { film, done, method_state })
}

/// Reads a checkpoint file; errors name the file (see [`decode`]).
pub fn read(path: &Path, key: &ResumeKey) -> Result<RenderState, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    decode(&bytes, key).map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(pairs: &[(&str, &str)]) -> ResumeKey {
        ResumeKey(pairs.iter().map(|(n, v)| (n.to_string(), v.to_string())).collect())
    }

    #[test]
    fn a_mismatch_names_the_settings_that_differ() {
        let state = RenderState { film: Film::new(2, 1), done: 3, method_state: vec![1, 2] };
        let k = key(&[("scene", "ab12"), ("method", "vismap"), ("seed", "1"), ("radius", "0.5")]);
        let bytes = encode(&k, &state);
        assert_eq!(decode(&bytes, &k).unwrap(), state);
        let now = key(&[("scene", "ab12"), ("method", "vismap"), ("seed", "2"), ("alpha", "0.7")]);
        let e = decode(&bytes, &now).unwrap_err();
        assert!(e.contains("seed 2 (the checkpoint has 1)"), "{e}");
        assert!(e.contains("alpha 0.7 (the checkpoint has unset)"), "{e}");
        assert!(e.contains("radius unset (the checkpoint has 0.5)"), "{e}");
        assert!(!e.contains("method"), "{e}");
        // truncated anywhere: an error, never a panic
        for n in 0..bytes.len() {
            assert!(decode(&bytes[..n], &k).is_err());
        }
    }

    #[test]
    fn spectral_bins_round_trip() {
        let mut film = Film::new(2, 1).with_spectral(SpectralBins::new(3, 400.0, 700.0).unwrap());
        if let Some(s) = film.spectral.as_mut() {
            s.sums = vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        }
        let state = RenderState { film, done: 1, method_state: vec![] };
        let k = key(&[("spectral_bins", "3 over 400:700 nm")]);
        let bytes = encode(&k, &state);
        assert_eq!(decode(&bytes, &k).unwrap(), state);
        for n in 0..bytes.len() {
            assert!(decode(&bytes[..n], &k).is_err());
        }
    }
}
