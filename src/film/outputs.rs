//! The output table (docs/architecture.md §6): one row per EXR channel group, with the pass that
//! produces it, how `quasar merge` combines it over renders of disjoint samples, whether
//! `quasar compare` and the z-test read it as an image of the scene, its unit and its doc line.
//! The film, the render job, `merge`, `compare` and the README's channel table all read this
//! table; adding an output is one row here plus its producer.

/// The channels of a group, after its layer name and a '.'.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ChannelSet {
    /// `R`, `G`, `B`: linear sRGB (D65).
    Rgb,
    /// `X`, `Y`, `Z`: CIE 1931 XYZ, or a world-space vector's components.
    Xyz,
    /// One scalar `Y`.
    Y,
    /// One scalar `Z` (a depth, OpenEXR's convention).
    Z,
    /// `<lambda>nm` per spectral bin, after the `S0` layer of the spectral layout of Fichet et
    /// al. 2021 ([`crate::film::SpectralBins::channel_name`]).
    SpectralBins,
    /// `block<N>` per block size N (`stderr.block4`, ...).
    BlockSizes,
    /// Cryptomatte's rank pairs: layers `<layer>00`, `<layer>01`, ... each with `R`, `G`, `B`,
    /// `A` = (id, coverage) of two ranks (the Cryptomatte specification).
    Cryptomatte,
}

impl ChannelSet {
    /// Whether `channel` (the part after the layer's '.') belongs to this set.
    pub fn contains(self, channel: &str) -> bool {
        match self {
            Self::Rgb => matches!(channel, "R" | "G" | "B"),
            Self::Xyz => matches!(channel, "X" | "Y" | "Z"),
            Self::Y => channel == "Y",
            Self::Z => channel == "Z",
            Self::SpectralBins => channel.ends_with("nm"),
            Self::BlockSizes => channel.strip_prefix("block").is_some_and(|n| n.parse::<usize>().is_ok_and(|n| n > 0)),
            Self::Cryptomatte => matches!(channel, "R" | "G" | "B" | "A"),
        }
    }

    /// The channels of a fixed set (empty for the sets whose channels depend on the render).
    pub fn names(self) -> &'static [&'static str] {
        match self {
            Self::Rgb => &["R", "G", "B"],
            Self::Xyz => &["X", "Y", "Z"],
            Self::Y => &["Y"],
            Self::Z => &["Z"],
            Self::SpectralBins | Self::BlockSizes | Self::Cryptomatte => &[],
        }
    }

    /// The channel suffixes for the docs (`{R,G,B}`, `Y`, `<λ>nm`, `block<N>`).
    fn pattern(self) -> &'static str {
        match self {
            Self::Rgb => "{R,G,B}",
            Self::Xyz => "{X,Y,Z}",
            Self::Y => "Y",
            Self::Z => "Z",
            Self::SpectralBins => "<λ>nm",
            Self::BlockSizes => "block<N>",
            Self::Cryptomatte => "{R,G,B,A}",
        }
    }
}

/// The pass that computes a group.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Producer {
    /// The film's per-pixel sums of the method's samples ([`crate::film::Film::channels`]).
    Film,
    /// The render job, from the film's `XYZ.Y` (photometric units).
    Photometry,
    /// The illuminance pass over the first surfaces the camera sees (`render::sensors`).
    IlluminancePass,
    /// The depth pass along the pixel-centre rays (`render::driver::depth_pass`).
    DepthPass,
    /// The bidirectional methods (`RenderPass::extra_channels`).
    Method,
    /// The pass of auxiliary outputs over the first surfaces the camera sees (`render::aovs`),
    /// for the rows asked for by `--aov`.
    AovPass,
}

/// How `quasar merge` combines a group over images of disjoint samples of one render.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MergeRule {
    /// The mean over all samples: per pixel, the images' values weighted by their `spp.Y`.
    SampleMean,
    /// The sum (the sample counts `spp.Y`).
    Sum,
    /// The standard error of the pooled samples of the mean channel `mean` (counts `spp.Y`),
    /// from each image's mean, standard error and count.
    PooledStderr {
        /// The channel whose standard error this is.
        mean: &'static str,
    },
    /// Per block of N x N pixels, the pooled batch statistics of the block means.
    PooledBlockStderr,
    /// The mean over all samples, each image's weighted by the count in header entry `count`
    /// (the same at every pixel).
    HeaderCountMean {
        /// The header key of the per-pixel sample count.
        count: &'static str,
    },
    /// [`MergeRule::PooledStderr`] with the counts of header entry `count`.
    HeaderCountStderr {
        /// The channel whose standard error this is.
        mean: &'static str,
        /// The header key of the per-pixel sample count.
        count: &'static str,
    },
    /// The first image's: the group does not depend on the samples (the scene and camera
    /// determine it).
    First,
}

/// One channel group of the output image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OutputGroup {
    /// The layer name before the '.' ("" for the bare beauty channels `R`, `G`, `B`).
    pub layer: &'static str,
    /// The channels after it.
    pub channels: ChannelSet,
    /// What computes it.
    pub producer: Producer,
    /// When it is written ("always", or the option that asks for it).
    pub when: &'static str,
    /// The name that asks for it in `--aov` and `[render] aovs` (None: not an opt-in output).
    pub aov: Option<&'static str>,
    /// How `quasar merge` combines it.
    pub merge: MergeRule,
    /// Whether `quasar compare` (and a z-test) measures it against a reference: an estimate of
    /// a quantity of the scene, not a statistic of the render.
    pub compared: bool,
    /// The unit of its values.
    pub unit: &'static str,
    /// What it holds (the README's channel table, markdown).
    pub doc: &'static str,
}

/// The full name of channel `c` of layer `layer` (`direct.R`; `R` for the beauty's "").
pub fn channel_name(layer: &str, c: &str) -> String {
    if layer.is_empty() { c.to_string() } else { format!("{layer}.{c}") }
}

impl OutputGroup {
    /// The full names of the group's channels (none for a set that depends on the render).
    pub fn channel_names(&self) -> Vec<String> {
        self.channels.names().iter().map(|c| channel_name(self.layer, c)).collect()
    }

    /// The group's channels as the docs name them (`` `direct.{R,G,B}` ``).
    pub fn pattern(&self) -> String {
        if self.layer.is_empty() {
            "`R`, `G`, `B`".to_string()
        } else if self.channels == ChannelSet::Cryptomatte {
            format!("`{}NN.{}`", self.layer, self.channels.pattern())
        } else {
            format!("`{}.{}`", self.layer, self.channels.pattern())
        }
    }

    /// Whether the group holds channel `name`.
    pub fn holds(&self, name: &str) -> bool {
        match name.rsplit_once('.') {
            Some((layer, c)) if self.channels == ChannelSet::Cryptomatte => {
                let rank = layer.strip_prefix(self.layer).unwrap_or_default();
                !self.layer.is_empty()
                    && rank.len() == 2
                    && rank.bytes().all(|b| b.is_ascii_digit())
                    && self.channels.contains(c)
            }
            Some((layer, c)) => layer == self.layer && self.channels.contains(c),
            None => self.layer.is_empty() && self.channels.contains(name),
        }
    }
}

/// The channel of the beauty's luminance Y (CIE 1931, the sensor of docs/architecture.md §3).
pub const LUMINANCE: &str = "XYZ.Y";
/// The channel of the samples (iterations) per pixel.
pub const SAMPLES: &str = "spp.Y";
/// The channel of the standard error of [`LUMINANCE`].
pub const STDERR: &str = "stderr.Y";
/// The channel of the depth along the pixel-centre ray.
pub const DEPTH: &str = "depth.Z";
/// The channel of the photometric luminance in cd/m² (`LUMINANCE_PER_Y` x `XYZ.Y`).
pub const LUMINANCE_CD: &str = "luminance.Y";
/// The channel of the illuminance in lux at the first surface the pixel's camera rays hit.
pub const ILLUMINANCE_LX: &str = "illuminance.Y";
/// The channel of the standard error (lx) of [`ILLUMINANCE_LX`].
pub const ILLUMINANCE_STDERR_LX: &str = "illuminance_stderr.Y";
/// The header entry of the illuminance layer's samples per pixel.
pub const ILLUMINANCE_SAMPLES: &str = "illuminance_samples";

/// A radiance layer of the film (a row of [`OUTPUTS`] for each of [`crate::film::LAYER_NAMES`]).
const fn radiance_layer(layer: &'static str, doc: &'static str) -> OutputGroup {
    OutputGroup {
        layer,
        channels: ChannelSet::Rgb,
        producer: Producer::Film,
        when: "always",
        aov: None,
        merge: MergeRule::SampleMean,
        compared: true,
        unit: "relative radiance, linear sRGB",
        doc,
    }
}

/// A row of the auxiliary outputs (`--aov NAME`): computed by the AOV pass, the same in every
/// shard, not a radiance estimate.
const fn aov(
    layer: &'static str,
    name: &'static str,
    channels: ChannelSet,
    unit: &'static str,
    doc: &'static str,
) -> OutputGroup {
    OutputGroup {
        layer,
        channels,
        producer: Producer::AovPass,
        when: "--aov",
        aov: Some(name),
        merge: MergeRule::First,
        compared: false,
        unit,
        doc,
    }
}

/// Every channel group quasar writes, in the README's order.
pub const OUTPUTS: &[OutputGroup] = &[
    OutputGroup {
        layer: "",
        channels: ChannelSet::Rgb,
        producer: Producer::Film,
        when: "always",
        aov: None,
        merge: MergeRule::SampleMean,
        compared: true,
        unit: "relative radiance, linear sRGB",
        doc: "beauty, linear sRGB (D65; the `chromaticities` attribute says so); = emission + direct + indirect per pixel. The default layer holds only these, so tools that read an EXR as RGB(A) (`oiiotool out.exr -o out.png`) get the beauty",
    },
    OutputGroup {
        layer: "XYZ",
        channels: ChannelSet::Xyz,
        producer: Producer::Film,
        when: "always",
        aov: None,
        merge: MergeRule::SampleMean,
        compared: true,
        unit: "relative radiance, CIE 1931 XYZ",
        doc: "CIE 1931 XYZ of the beauty; `XYZ.Y` is the luminance (a spectrally flat radiance of 1 gives Y = 1; with lights in absolute units, cd/m² = 72 983 × Y)",
    },
    radiance_layer("emission", "lights seen directly or through specular chains"),
    radiance_layer("direct", "light after one non-specular scattering event"),
    radiance_layer("indirect", "light after two or more non-specular events (photons in the bidirectional methods)"),
    radiance_layer(
        "caustic",
        "the part of `indirect` that reached its single non-specular vertex through specular events only (light -> specular -> diffuse -> specular* -> eye)",
    ),
    OutputGroup {
        layer: "luminance",
        channels: ChannelSet::Y,
        producer: Producer::Photometry,
        when: "always",
        aov: None,
        merge: MergeRule::SampleMean,
        compared: true,
        unit: "cd/m²",
        doc: "photometric luminance in cd/m² = 72 983 × `XYZ.Y` (683 lm/W × ∫ L ȳ dλ); absolute when the lights are (photometric files, glTF/USD photometric units; [docs/photometry.md](docs/photometry.md))",
    },
    OutputGroup {
        layer: "illuminance",
        channels: ChannelSet::Y,
        producer: Producer::IlluminancePass,
        when: "--illuminance-samples N",
        aov: None,
        merge: MergeRule::HeaderCountMean { count: ILLUMINANCE_SAMPLES },
        compared: true,
        unit: "lx",
        doc: "only with `--illuminance-samples N`: illuminance in lux at the first surface the pixel's (jittered) camera rays hit ([docs/photometry.md](docs/photometry.md))",
    },
    OutputGroup {
        layer: "illuminance_stderr",
        channels: ChannelSet::Y,
        producer: Producer::IlluminancePass,
        when: "--illuminance-samples N",
        aov: None,
        merge: MergeRule::HeaderCountStderr { mean: ILLUMINANCE_LX, count: ILLUMINANCE_SAMPLES },
        compared: false,
        unit: "lx",
        doc: "with `illuminance.Y`: its standard error per pixel (lx)",
    },
    OutputGroup {
        layer: "S0",
        channels: ChannelSet::SpectralBins,
        producer: Producer::Film,
        when: "--spectral-bins N",
        aov: None,
        merge: MergeRule::SampleMean,
        compared: true,
        unit: "relative spectral radiance per nm (W m⁻² sr⁻¹ nm⁻¹ with absolute lights)",
        doc: "in `<stem>.spectral.exr` only (a complete image with every layer of this table besides these; the image itself names it in its `spectral_file` header entry and has no `S0` channels, since Blender refuses a whole file with more than 24 channels in one layer), and only with `--spectral-bins N` (and `--spectral-range MIN:MAX`, default 360:830): the beauty's mean spectral radiance over each of N equal bins, W m⁻² sr⁻¹ nm⁻¹ with absolute lights, named after the bin centre (`S0.550,000000nm`) in the OpenEXR spectral layout of Fichet et al. 2021 that pbrt-v4 writes and colour-science reads; the header gets `spectralLayoutVersion` and `emissiveUnits` ([docs/photometry.md](docs/photometry.md))",
    },
    OutputGroup {
        layer: "depth",
        channels: ChannelSet::Z,
        producer: Producer::DepthPass,
        when: "always",
        aov: None,
        merge: MergeRule::First,
        compared: false,
        unit: "m",
        doc: "camera distance (m) of the first hit along the pixel-centre ray; `+inf` where the ray hits nothing (OpenEXR's convention for an infinitely far sample; tools that need a finite far value clamp it)",
    },
    OutputGroup {
        layer: "spp",
        channels: ChannelSet::Y,
        producer: Producer::Film,
        when: "always",
        aov: None,
        merge: MergeRule::Sum,
        compared: false,
        unit: "samples",
        doc: "samples per pixel (iterations for the bidirectional methods)",
    },
    OutputGroup {
        layer: "stderr",
        channels: ChannelSet::Y,
        producer: Producer::Film,
        when: "always",
        aov: None,
        merge: MergeRule::PooledStderr { mean: LUMINANCE },
        compared: false,
        unit: "as `XYZ.Y`",
        doc: "standard error of the pixel's mean luminance, from the per-sample (per-iteration) variance",
    },
    OutputGroup {
        layer: "stderr",
        channels: ChannelSet::BlockSizes,
        producer: Producer::Film,
        when: "bidirectional methods",
        aov: None,
        merge: MergeRule::PooledBlockStderr,
        compared: false,
        unit: "as `XYZ.Y`",
        doc: "bidirectional methods: standard error of the mean luminance of the pixel's N x N block, from the iterations (their pixels' errors are correlated: see [docs/validation.md](docs/validation.md))",
    },
    OutputGroup {
        layer: "trace_depth",
        channels: ChannelSet::Y,
        producer: Producer::Method,
        when: "bidirectional methods",
        aov: None,
        merge: MergeRule::SampleMean,
        compared: false,
        unit: "scattering events",
        doc: "bidirectional methods: the gather depth used, mean over iterations",
    },
    aov(
        "normal",
        "normal",
        ChannelSet::Xyz,
        "unit vector, world space",
        "with `--aov normal`: the shading normal (world space, the side of the triangle's winding) at the first surface the pixel's camera rays hit, averaged over the AOV samples (0 where they miss)",
    ),
    aov(
        "normal_geometric",
        "normal_geometric",
        ChannelSet::Xyz,
        "unit vector, world space",
        "with `--aov normal_geometric`: the triangle's geometric normal there, averaged the same way",
    ),
    aov(
        "position",
        "position",
        ChannelSet::Xyz,
        "m, world space",
        "with `--aov position`: the world-space point (m) there, averaged the same way",
    ),
    aov(
        "albedo",
        "albedo",
        ChannelSet::Rgb,
        "reflectance, linear sRGB",
        "with `--aov albedo`: the directional-hemispherical reflectance (reflection plus transmission) of the BSDF at the first non-specular surface, through mirrors and smooth glass, under D65 in linear sRGB (a white diffuse surface is 1, 1, 1); estimated by one BSDF sample per AOV sample",
    ),
    aov(
        "material_id",
        "material_id",
        ChannelSet::Y,
        "integer id",
        "with `--aov material_id`: the index + 1 of the material covering most of the pixel's AOV samples (0: none); the header's `material_ids` maps ids to names",
    ),
    aov(
        "object_id",
        "object_id",
        ChannelSet::Y,
        "integer id",
        "with `--aov object_id`: the same for the mesh (object); the header's `object_ids` maps ids to names",
    ),
    aov(
        "CryptoMaterial",
        "crypto_material",
        ChannelSet::Cryptomatte,
        "Cryptomatte id, coverage",
        "with `--aov crypto_material`: Cryptomatte of the material names (MurmurHash3 ids, six ranks of id and coverage in `CryptoMaterial00`-`02`, the manifest in the header's `cryptomatte/<key>/manifest`), for Nuke's and Blender's Cryptomatte nodes",
    ),
    aov(
        "CryptoObject",
        "crypto_object",
        ChannelSet::Cryptomatte,
        "Cryptomatte id, coverage",
        "with `--aov crypto_object`: the same for the mesh (object) names",
    ),
];

/// The rows of the auxiliary outputs that `--aov` can ask for, by name.
pub fn aov_names() -> Vec<&'static str> {
    OUTPUTS.iter().filter_map(|g| g.aov).collect()
}

/// The row asked for by `--aov name`, if any.
pub fn aov_row(name: &str) -> Option<&'static OutputGroup> {
    OUTPUTS.iter().find(|g| g.aov == Some(name))
}

/// The row of [`OUTPUTS`] that holds channel `name`, if any.
pub fn group_of(name: &str) -> Option<&'static OutputGroup> {
    OUTPUTS.iter().find(|g| g.holds(name))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_channel_name_finds_its_one_row() {
        for (name, layer) in [
            ("R", ""),
            ("XYZ.Y", "XYZ"),
            ("caustic.B", "caustic"),
            ("stderr.Y", "stderr"),
            ("S0.550,000000nm", "S0"),
            ("depth.Z", "depth"),
        ] {
            assert_eq!(group_of(name).map(|g| g.layer), Some(layer), "{name}");
        }
        assert_eq!(group_of("stderr.block16").map(|g| g.channels), Some(ChannelSet::BlockSizes));
        assert_eq!(group_of("CryptoObject01.A").map(|g| g.layer), Some("CryptoObject"));
        assert_eq!(group_of("normal.Y").map(|g| g.aov), Some(Some("normal")));
        for unknown in
            ["Y", "direct.Y", "stderr.block0", "stderr.blockx", "nothing.R", "CryptoObject.R", "CryptoObject1.R"]
        {
            assert!(group_of(unknown).is_none(), "{unknown}");
        }
        // no two rows hold one channel
        for (i, a) in OUTPUTS.iter().enumerate() {
            for b in &OUTPUTS[i + 1..] {
                assert!(
                    !(a.layer == b.layer && a.channels == b.channels),
                    "rows {} and {} are the same group",
                    a.pattern(),
                    b.pattern()
                );
            }
        }
    }
}
