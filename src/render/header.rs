//! The header table: one row per entry of the `quasar` header attribute of a render's EXR
//! (`key=value` lines, each also a typed `quasar:key` attribute), with how `quasar merge`
//! combines it over renders of disjoint samples and what it records. The render job and the
//! methods write these keys, `merge` reads the rules, and a test renders with every method and
//! checks that each key it wrote has a row.

use HeaderMerge::*;

/// How `quasar merge` combines a header entry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HeaderMerge {
    /// Must be equal in every image: it changes what a sample means (merging refuses otherwise).
    Agree,
    /// The sum over the images (counts and times).
    Sum,
    /// `true` when any image's is.
    AnyTrue,
    /// Recomputed from the merged channels (the estimated error).
    Recomputed,
    /// Replaced by `merged` (the shard).
    Merged,
    /// Dropped: the merge writes its own (`streams`, `merged_from`) or none (`spectral_file`:
    /// the shards' spectral files are merged on their own).
    Dropped,
    /// The first image's (a description of the render that the merge does not change).
    First,
}

/// One header entry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HeaderKey {
    /// The key.
    pub key: &'static str,
    /// How `merge` combines it.
    pub merge: HeaderMerge,
    /// What it records.
    pub doc: &'static str,
}

/// A row of [`HEADER`].
const fn row(key: &'static str, merge: HeaderMerge, doc: &'static str) -> HeaderKey {
    HeaderKey { key, merge, doc }
}

/// Every header entry a render or a merge writes.
pub const HEADER: &[HeaderKey] = &[
    row("software", First, "quasar and its version"),
    row("scene", First, "the scene file"),
    row(
        "scene_fingerprint",
        Agree,
        "a hash of the scene's content (geometry, materials, textures, lights, camera), not of the places it was read from",
    ),
    row("method", Agree, "the method that rendered"),
    row("method_requested", First, "the method asked for (`auto` resolves to one)"),
    row("spp", Sum, "samples per pixel (iterations for the bidirectional methods)"),
    row("iterations", Sum, "bidirectional methods: iterations"),
    row("seed", First, "the seed of the random streams"),
    row("masking", Agree, "the microfacet masking-shadowing form"),
    row("width", Agree, "image width"),
    row("height", Agree, "image height"),
    row("wavelengths", First, "how wavelengths are sampled"),
    row("units", First, "the units of the channels"),
    row("partial", AnyTrue, "whether the render was interrupted before its budget"),
    row("shard", Merged, "the share K/N of the samples (`merged` after a merge)"),
    row("streams", Dropped, "after a merge: the seeds and shards merged (seed:K/N,...)"),
    row("merged_from", Dropped, "after a merge: the number of images merged"),
    row("rejected_samples", Sum, "non-finite samples dropped (each counted as zero)"),
    row("target_error", First, "the error target (`--target-error`), or none"),
    row("target_error_reached", First, "whether the render stopped at its error target"),
    row(
        "estimated_rel_error",
        Recomputed,
        "the image's estimated RMS relative error, sqrt(mean stderr² / (Y² + 1e-3))",
    ),
    row("threads", First, "worker threads"),
    row("isa", First, "the instruction set of the render kernels"),
    row("render_time_s", Sum, "wall-clock seconds of the render (summed over merged images)"),
    row("illuminance_samples", Sum, "samples per pixel of `illuminance.Y`"),
    row("spectral_bins", Agree, "the spectral bins (`N x D nm over MIN:MAX nm`)"),
    row("spectral_units", First, "the units of the `S0` channels"),
    row("spectral_file", Dropped, "the file of the spectral bins beside the image"),
    row("auto_pilot", First, "`auto`: what each method's pilot measured and the choice"),
    row("max_depth", Agree, "`pt`, `direct`: the path length cap"),
    row("photons_per_iteration", Agree, "bidirectional methods: photons traced per iteration"),
    row("gather_depth", Agree, "bidirectional methods: the gather depth (fixed or adaptive)"),
    row("cone_deg", Agree, "`quasi`: the cone half-angle, or none"),
    row("radius", Agree, "bidirectional methods: the initial gather radius"),
    row("caustic_radius_ratio", Agree, "bidirectional methods: the caustic photons' radius over the others'"),
    row("alpha", Agree, "bidirectional methods: the radius reduction alpha"),
    row("photons", Sum, "bidirectional methods: photons traced"),
    row("time_share", First, "bidirectional methods: the share of time per phase"),
    row("aov_samples", First, "with `--aov`: rays per pixel of the auxiliary outputs"),
    row("material_ids", First, "with `--aov material_id`: a JSON object from each id to its material's name"),
    row("object_ids", First, "with `--aov object_id`: a JSON object from each id to its mesh's name"),
    row(
        "cryptomatte/*",
        First,
        "with `--aov crypto_*`: the Cryptomatte layers' `name`, `hash`, `conversion` and `manifest`, as string attributes of these names",
    ),
];

/// The row of `key`, if any (a row whose key ends in `*` holds every key with its prefix).
pub fn header_key(key: &str) -> Option<&'static HeaderKey> {
    HEADER.iter().find(|h| match h.key.strip_suffix('*') {
        Some(prefix) => key.starts_with(prefix),
        None => h.key == key,
    })
}
