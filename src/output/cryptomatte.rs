//! Cryptomatte (Friedman and Jones 2015; the public specification that Nuke's, Blender's and
//! OpenImageIO-based decoders implement): a name's id is the float whose bits are the
//! MurmurHash3_x86_32 hash (seed 0) of its UTF-8 bytes, with the exponent kept away from 0 and
//! 255 (no denormal, inf or NaN); a pixel stores its ids ranked by coverage, two ranks per RGBA
//! layer `<name>00`, `<name>01`, ... as (id, coverage, id, coverage); the header holds, under
//! `cryptomatte/<key>/` with `<key>` the first 7 hex digits of the layer name's hash, the
//! layer's `name`, `hash` (`MurmurHash3_32`), `conversion` (`uint32_to_float32`) and the
//! `manifest`, a JSON object from each name to its id's bits as 8 hex digits.

use crate::film::Channel;

/// Ranks written per pixel (three RGBA layers), the depth the specification's examples use.
pub const RANKS: usize = 6;

/// MurmurHash3_x86_32 of `name` with seed 0.
pub fn murmur3(name: &str) -> u32 {
    murmur3::murmur3_32(&mut std::io::Cursor::new(name.as_bytes()), 0).unwrap_or(0)
}

/// The id of `name`: the bits of its hash with the exponent moved off 0 and 255 (bit 23
/// flipped), as the specification's float conversion.
pub fn id_bits(name: &str) -> u32 {
    let h = murmur3(name);
    let exponent = (h >> 23) & 0xff;
    if exponent == 0 || exponent == 0xff { h ^ (1 << 23) } else { h }
}

/// The header key of layer `layer`'s entry `entry`: `cryptomatte/<7 hex digits>/<entry>`.
pub fn header_key(layer: &str, entry: &str) -> String {
    format!("cryptomatte/{}/{entry}", &format!("{:08x}", murmur3(layer))[..7])
}

/// The header entries of layer `layer` over `names` (the manifest maps each to its id).
pub fn header(layer: &str, names: &[String]) -> Vec<(String, String)> {
    let manifest: serde_json::Map<String, serde_json::Value> =
        names.iter().map(|n| (n.clone(), serde_json::Value::String(format!("{:08x}", id_bits(n))))).collect();
    vec![
        (header_key(layer, "name"), layer.to_string()),
        (header_key(layer, "hash"), "MurmurHash3_32".into()),
        (header_key(layer, "conversion"), "uint32_to_float32".into()),
        (header_key(layer, "manifest"), serde_json::Value::Object(manifest).to_string()),
    ]
}

/// The channels of layer `layer` from each pixel's coverage: `coverage[p]` lists (index into
/// `names`, coverage) pairs; each pixel's [`RANKS`] largest, ranked by coverage (then by id, so
/// the order is fixed), as (id, coverage) pairs, zeros after the last.
pub fn channels(layer: &str, names: &[String], coverage: &[Vec<(u32, f32)>]) -> Vec<Channel> {
    let ids: Vec<f32> = names.iter().map(|n| f32::from_bits(id_bits(n))).collect();
    let mut out: Vec<Channel> = (0..RANKS / 2)
        .flat_map(|l| {
            ["R", "G", "B", "A"]
                .map(|c| Channel { name: format!("{layer}{l:02}.{c}"), values: vec![0.0; coverage.len()] })
        })
        .collect();
    for (p, cov) in coverage.iter().enumerate() {
        let mut ranked: Vec<(f32, u32)> = cov.iter().map(|&(i, c)| (c, i)).collect();
        ranked.sort_by(|a, b| b.0.total_cmp(&a.0).then(ids[a.1 as usize].to_bits().cmp(&ids[b.1 as usize].to_bits())));
        for (rank, &(c, i)) in ranked.iter().take(RANKS).enumerate() {
            out[2 * rank].values[p] = ids[i as usize];
            out[2 * rank + 1].values[p] = c;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// MurmurHash3_x86_32 test vectors (seed 0) and the specification's conversion.
    #[test]
    fn hashes_and_ids_follow_the_specification() {
        assert_eq!(murmur3(""), 0);
        assert_eq!(murmur3("hello"), 0x248b_fa47);
        assert_eq!(murmur3("The quick brown fox jumps over the lazy dog"), 0x2e4f_f723);
        for name in ["", "floor", "bunny", "CryptoObject", "a long material name / with a path"] {
            let f = f32::from_bits(id_bits(name));
            assert!(f.is_finite() && (f == 0.0 || f.is_normal()), "{name}: {f}");
            assert_eq!(id_bits(name) & !(1 << 23), murmur3(name) & !(1 << 23));
        }
        assert!(header_key("CryptoObject", "name").starts_with("cryptomatte/") && header_key("x", "name").len() == 24);
    }

    #[test]
    fn ranks_are_sorted_by_coverage() {
        let names = vec!["a".to_string(), "b".to_string(), "c".to_string()];
        let ch = channels("CryptoObject", &names, &[vec![(0, 0.25), (2, 0.5), (1, 0.25)], vec![]]);
        assert_eq!(ch.len(), 12);
        assert_eq!(ch[0].name, "CryptoObject00.R");
        assert_eq!(ch[0].values[0].to_bits(), id_bits("c"));
        assert_eq!((ch[1].values[0], ch[3].values[0], ch[5].values[0]), (0.5, 0.25, 0.25));
        assert_eq!(ch[1].values[1], 0.0);
        let manifest = &header("CryptoObject", &names)[3].1;
        assert!(manifest.contains(&format!("\"a\":\"{:08x}\"", id_bits("a"))), "{manifest}");
    }
}
