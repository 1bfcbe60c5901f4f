//! Distributed rendering: `--shard K/N` renders disjoint shares of the samples (iterations) and
//! `quasar merge` combines them into the full render — equal up to float summation order (the
//! merge averages per-shard means weighted by their counts instead of summing the samples in one
//! pass), for every method of the method table.

mod common;

use std::path::Path;

use common::render_file;
use quasar::output::ExrImage;
use quasar::render::job::JobOverrides;

fn scene() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/glass-plate/glass-plate.toml")
}

fn ov(method: &str, shard: Option<(u32, u32)>) -> JobOverrides {
    JobOverrides {
        width: Some(24),
        height: Some(18),
        spp: Some(8),
        seed: Some(17),
        method: Some(method.into()),
        shard,
        // the spectral channels merge and resume like every other mean channel
        spectral_bins: Some(quasar::film::SpectralBins::new(8, 360.0, 830.0).unwrap()),
        // so do the illuminance layer's samples (K + N j of 8) and its standard errors
        illuminance_samples: Some(8),
        // and every auxiliary output (the same in every shard)
        aovs: Some(quasar::film::outputs::aov_names().iter().map(|s| s.to_string()).collect()),
        aov_samples: Some(4),
        ..Default::default()
    }
    .with_photons_if_read(method, 3000)
}

trait Photons {
    fn with_photons_if_read(self, method: &str, n: u32) -> Self;
}

impl Photons for JobOverrides {
    /// `photons_per_iteration = n` for the methods that read it.
    fn with_photons_if_read(self, method: &str, n: u32) -> Self {
        let entry = quasar::integrator::method::find(method).unwrap();
        if entry.params.iter().any(|p| p.key == "photons_per_iteration") {
            self.with_param("photons_per_iteration", n)
        } else {
            self
        }
    }
}

fn assert_close(merged: &ExrImage, full: &ExrImage, what: &str) {
    for c in &full.channels {
        let m = merged.channel(&c.name).unwrap_or_else(|| panic!("{what}: no {}", c.name));
        for (i, (&a, &b)) in m.iter().zip(&c.values).enumerate() {
            let tol = if c.name.contains("stderr.Y") { 1e-3 } else { 2e-5 } * b.abs().max(1e-3);
            assert!((a - b).abs() <= tol || (a.is_infinite() && a == b), "{what}: {} pixel {i}: {a} vs {b}", c.name);
        }
    }
}

/// Every method's shards merge into its full render, channel by channel by the rule of the
/// output table. The tables cover what is written: each channel has its row of the output table
/// and each header entry its row of the header table, every row of the output table is written
/// by some method, and `quasar compare` measures exactly the channels of the rows marked
/// `compared`.
#[test]
fn four_shards_merge_into_the_full_render() {
    use quasar::film::outputs::{OUTPUTS, group_of};
    let mut rows_written = vec![false; OUTPUTS.len()];
    for method in quasar::integrator::method::METHODS.iter().map(|m| m.name) {
        let full = render_file(&scene(), &ov(method, None)).image;
        for c in &full.channels {
            let row = group_of(&c.name).unwrap_or_else(|| panic!("{method}: {} has no row in OUTPUTS", c.name));
            rows_written[OUTPUTS.iter().position(|r| r == row).unwrap()] = true;
        }
        for (k, _) in &full.metadata {
            assert!(quasar::render::header::header_key(k).is_some(), "{method}: header entry {k} has no row in HEADER");
        }
        let measured: Vec<String> =
            quasar::tools::compare::compare(&full, &full, None).unwrap().into_iter().map(|e| e.layer).collect();
        for row in OUTPUTS.iter().filter(|r| full.channels.iter().any(|c| r.holds(&c.name))) {
            let layer = if row.layer.is_empty() { "beauty" } else { row.layer };
            assert_eq!(measured.iter().any(|l| l == layer), row.compared, "{method}: compare and the row of {layer}");
        }
        let shards: Vec<ExrImage> = (0..4).map(|k| render_file(&scene(), &ov(method, Some((k, 4)))).image).collect();
        for s in &shards {
            assert_eq!((s.meta("spp"), s.meta("illuminance_samples")), (Some("2"), Some("2")), "{method}");
        }
        let merged = quasar::tools::merge::merge(&shards).unwrap();
        assert_eq!(merged.meta("spp"), Some("8"));
        assert_eq!(merged.meta("merged_from"), Some("4"));
        assert_eq!(merged.meta("illuminance_samples"), Some("8"));
        assert_close(&merged, &full, method);
        // header entries by the header table: summed, recomputed from the merged channels
        assert_eq!(merged.meta("rejected_samples"), full.meta("rejected_samples"), "{method}");
        let error = |img: &ExrImage| img.meta("estimated_rel_error").unwrap().parse::<f64>().unwrap();
        assert!((error(&merged) / error(&full) - 1.0).abs() < 1e-3, "{method}: {} vs {}", error(&merged), error(&full));
    }
    for (row, written) in OUTPUTS.iter().zip(rows_written) {
        assert!(written, "no method wrote {}", row.pattern());
    }
}

#[test]
fn merge_refuses_mismatched_renders() {
    let a = render_file(&scene(), &ov("pt", Some((0, 2)))).image;
    let b = render_file(&scene(), &ov("vismap", Some((1, 2)))).image;
    assert!(quasar::tools::merge::merge(&[a.clone(), b]).unwrap_err().contains("method"));
    let c = render_file(&scene(), &JobOverrides { width: Some(12), ..ov("pt", None) }).image;
    assert!(quasar::tools::merge::merge(&[a, c]).is_err());
    assert!(quasar::tools::merge::merge(&[]).is_err());
    // another gather radius (here the automatic one's pixel footprints) changes what a sample means
    let d = render_file(&scene(), &ov("vismap", Some((0, 2)))).image;
    let e = render_file(&scene(), &ov("vismap", Some((1, 2))).with_param("radius_pixels", 1.5)).image;
    assert_eq!(e.meta("radius"), Some("auto (1.5 pixel footprints)"));
    assert!(quasar::tools::merge::merge(&[d, e]).unwrap_err().contains("radius"));
}

/// `quasar merge` refuses inputs that do not hold independent samples of one scene (issue 18):
/// another scene, the same file twice, two full renders with one seed, shards of one seed split
/// differently; renders with different seeds, and a merged image with the remaining shard, merge.
#[test]
fn merge_refuses_repeated_samples_and_other_scenes() {
    let merge = |imgs: &[&ExrImage]| quasar::tools::merge::merge(&imgs.iter().map(|&i| i.clone()).collect::<Vec<_>>());
    let full = render_file(&scene(), &ov("pt", None)).image;
    let other_scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell-box/cornell-box.toml");
    let cornell = render_file(&other_scene, &ov("pt", None)).image;
    assert!(merge(&[&full, &cornell]).unwrap_err().contains("scene_fingerprint"));
    assert!(merge(&[&full, &full]).unwrap_err().contains("the same samples twice"));
    let full_again = render_file(&scene(), &ov("pt", None)).image;
    assert!(merge(&[&full, &full_again]).unwrap_err().contains("the same samples twice"));
    let (a, b, c) = (
        render_file(&scene(), &ov("pt", Some((0, 3)))).image,
        render_file(&scene(), &ov("pt", Some((1, 3)))).image,
        render_file(&scene(), &ov("pt", Some((1, 2)))).image,
    );
    assert!(merge(&[&a, &c]).unwrap_err().contains("split it the same way"));
    assert!(merge(&[&a, &full]).unwrap_err().contains("split it the same way"));
    let other_seed = render_file(&scene(), &JobOverrides { seed: Some(99), ..ov("pt", None) }).image;
    let two_seeds = merge(&[&full, &other_seed]).unwrap();
    assert_eq!(two_seeds.meta("spp"), Some("16"));
    let ab = merge(&[&a, &b]).unwrap();
    assert_eq!(ab.meta("streams"), Some("17:0/3,17:1/3"));
    assert!(merge(&[&ab, &b]).unwrap_err().contains("the same samples twice"));
    let c2 = render_file(&scene(), &ov("pt", Some((2, 3)))).image;
    assert_eq!(merge(&[&ab, &c2]).unwrap().meta("spp"), Some("8"));
}

/// A render stopped and resumed from its checkpoint equals the uninterrupted render bit for bit,
/// for every method (the adaptive ones keep their depth histograms in the state); a checkpoint of
/// other settings is refused.
#[test]
fn resume_equals_the_uninterrupted_render() {
    let dir = tempfile::tempdir().unwrap();
    for method in quasar::integrator::method::METHODS.iter().map(|m| m.name) {
        let cp = dir.path().join(format!("{method}.ckpt"));
        let full = render_file(&scene(), &ov(method, None)).image;
        let first = JobOverrides { spp: Some(3), checkpoint: Some(cp.clone()), ..ov(method, None) };
        render_file(&scene(), &first);
        let rest = JobOverrides { resume: Some(cp.clone()), ..ov(method, None) };
        let resumed = render_file(&scene(), &rest).image;
        assert_eq!(resumed.meta("spp"), Some("8"), "{method}");
        for c in &full.channels {
            let r = resumed.channel(&c.name).unwrap();
            assert!(c.values.iter().zip(r).all(|(a, b)| a.to_bits() == b.to_bits()), "{method}: {}", c.name);
        }
        let other_seed = JobOverrides { seed: Some(18), resume: Some(cp.clone()), ..ov(method, None) };
        let desc = quasar::render::job::load_scene(&scene()).unwrap();
        let err = quasar::render::job::render_desc(&desc, &other_seed, false).err().unwrap();
        // the error names the setting that differs (issue 18: it only said that one did)
        let msg = format!("{err:#}");
        assert!(msg.contains("other render settings: seed 18 (the checkpoint has"), "{msg}");
        let diffs = msg.split("settings: ").nth(1).unwrap();
        assert!(!diffs.contains("method") && !diffs.contains("scene"), "{msg}");
        let no_bins = JobOverrides { spectral_bins: None, resume: Some(cp.clone()), ..ov(method, None) };
        let msg = format!("{:#}", quasar::render::job::render_desc(&desc, &no_bins, false).err().unwrap());
        assert!(msg.contains("spectral_bins unset (the checkpoint has 8 x"), "{msg}");
    }
    std::fs::write(dir.path().join("bad.ckpt"), b"QSRCKPT1garbage").unwrap();
    let desc = quasar::render::job::load_scene(&scene()).unwrap();
    let bad = JobOverrides { resume: Some(dir.path().join("bad.ckpt")), ..ov("pt", None) };
    assert!(quasar::render::job::render_desc(&desc, &bad, false).is_err());
}

/// A setting left at its default is part of the resume key as its default: a checkpoint written
/// with the default given explicitly resumes without it, and one written with another value (or
/// by a build with another default) is refused, naming the setting.
#[test]
fn defaults_are_part_of_the_resume_key() {
    let dir = tempfile::tempdir().unwrap();
    let desc = quasar::render::job::load_scene(&scene()).unwrap();
    let default_alpha = quasar::integrator::bidir::settings::DEFAULT_ALPHA;
    let checkpoint = |alpha: f64, name: &str| {
        let cp = dir.path().join(name);
        let first = JobOverrides { spp: Some(3), checkpoint: Some(cp.clone()), ..ov("vismap", None) };
        render_file(&scene(), &first.with_param("alpha", alpha));
        cp
    };
    let explicit = checkpoint(default_alpha as f64, "explicit.ckpt");
    let full = render_file(&scene(), &ov("vismap", None)).image;
    let resumed = render_file(&scene(), &JobOverrides { resume: Some(explicit), ..ov("vismap", None) }).image;
    for c in &full.channels {
        let r = resumed.channel(&c.name).unwrap();
        assert!(c.values.iter().zip(r).all(|(a, b)| a.to_bits() == b.to_bits()), "{}", c.name);
    }
    let other = checkpoint(0.7, "other.ckpt");
    let err =
        quasar::render::job::render_desc(&desc, &JobOverrides { resume: Some(other), ..ov("vismap", None) }, false);
    let msg = format!("{:#}", err.err().unwrap());
    assert!(msg.contains(&format!("alpha {default_alpha} (the checkpoint has 0.7)")), "{msg}");
}

/// From the 17th iteration on, a pixel's adaptive-depth pilots stop once no remaining pilot
/// could change its depth: a render checkpointed there and resumed still chooses, iteration by
/// iteration, the depths of the uninterrupted render (the image and `trace_depth.Y` bit for bit).
#[test]
fn resume_where_pilots_are_skipped_equals_the_uninterrupted_render() {
    let dir = tempfile::tempdir().unwrap();
    let cp = dir.path().join("adaptive.ckpt");
    let long = JobOverrides { spp: Some(28), ..ov("adaptive", None) };
    let full = render_file(&scene(), &long).image;
    render_file(&scene(), &JobOverrides { spp: Some(21), checkpoint: Some(cp.clone()), ..long.clone() });
    let resumed = render_file(&scene(), &JobOverrides { resume: Some(cp), ..long }).image;
    assert_eq!(resumed.meta("spp"), Some("28"));
    for c in &full.channels {
        let r = resumed.channel(&c.name).unwrap();
        assert!(c.values.iter().zip(r).all(|(a, b)| a.to_bits() == b.to_bits()), "{}", c.name);
    }
}

/// Images written before the illuminance layer's sample count was recorded in the header merge
/// their layers by `spp.Y` as before (not to zero).
#[test]
fn illuminance_layers_without_a_count_merge_by_spp() {
    let mut shards: Vec<ExrImage> = (0..2).map(|k| render_file(&scene(), &ov("pt", Some((k, 2)))).image).collect();
    for s in &mut shards {
        s.metadata.retain(|(k, _)| k != "illuminance_samples");
    }
    let merged = quasar::tools::merge::merge(&shards).unwrap();
    let (a, b, m) = (
        shards[0].channel("illuminance.Y").unwrap(),
        shards[1].channel("illuminance.Y").unwrap(),
        merged.channel("illuminance.Y").unwrap(),
    );
    for i in 0..m.len() {
        assert!(
            (m[i] - 0.5 * (a[i] + b[i])).abs() <= 1e-5 * m[i].abs().max(1e-3),
            "pixel {i}: {} vs {} {}",
            m[i],
            a[i],
            b[i]
        );
    }
    assert!(m.iter().any(|&v| v > 0.0));
}
