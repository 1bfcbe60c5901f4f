//! `quasar merge`: combines independent renders of one scene (shards of a render, or renders with
//! different seeds) into one image, exactly as if their samples had been accumulated together:
//! every mean channel is the per-pixel average weighted by the sample (iteration) counts of
//! `spp.Y`, `spp.Y` is their sum, and `stderr.Y` is recomputed from the pooled sums of squares;
//! the `illuminance.Y` layer and its `illuminance_stderr.Y` are pooled the same way over the
//! `illuminance_samples` of each image.

use crate::film::Channel;
use crate::output::ExrImage;
use crate::render::job::{ILLUMINANCE_LX, ILLUMINANCE_STDERR_LX};

/// Header keys that must agree between the merged images (they change what a sample means).
const MUST_AGREE: [&str; 12] = [
    "scene_fingerprint",
    "spectral_bins",
    "method",
    "width",
    "height",
    "masking",
    "max_depth",
    "photons_per_iteration",
    "gather_depth",
    "cone_deg",
    "radius",
    "alpha",
];

/// The random streams an image's samples came from: (seed, K, N) for shard K of N (a full
/// render is shard 0 of 1), from the `streams` list of a merged image or its `seed` and `shard`;
/// None for an image without them.
fn streams(img: &ExrImage) -> Option<Vec<(String, u32, u32)>> {
    let parse = |seed: &str, shard: &str| {
        let (k, n) = shard.split_once('/')?;
        Some((seed.to_string(), k.parse().ok()?, n.parse().ok()?))
    };
    match img.meta("streams") {
        Some(list) => list.split(',').map(|s| s.split_once(':').and_then(|(seed, sh)| parse(seed, sh))).collect(),
        None => Some(vec![parse(img.meta("seed")?, img.meta("shard")?)?]),
    }
}

/// Refuses inputs whose samples are not independent: two renders with one seed must be
/// different shards of one split of it (same N, different K); anything else repeats samples
/// (the same file twice, two full renders with the same seed) or overlaps them.
fn check_streams(images: &[ExrImage]) -> Result<Vec<(String, u32, u32)>, String> {
    let mut seen: Vec<(usize, (String, u32, u32))> = Vec::new();
    for (i, img) in images.iter().enumerate() {
        for s in streams(img).unwrap_or_default() {
            for (j, t) in &seen {
                if t.0 != s.0 {
                    continue;
                }
                if t.2 != s.2 {
                    return Err(format!(
                        "image {i} is shard {}/{} of seed {}, image {j} shard {}/{} of it: shards of one seed must split it the same way",
                        s.1, s.2, s.0, t.1, t.2
                    ));
                }
                if t.1 == s.1 {
                    return Err(format!(
                        "images {j} and {i} both hold shard {}/{} of seed {}: the same samples twice (the same file, or renders with the same seed and no --shard)",
                        s.1, s.2, s.0
                    ));
                }
            }
            seen.push((i, s));
        }
    }
    Ok(seen.into_iter().map(|(_, s)| s).collect())
}

/// Header keys summed over the inputs.
const SUMMED: [&str; 5] = ["spp", "iterations", "photons", "render_time_s", "illuminance_samples"];

/// Merges `images` (at least one). Errors name the first disagreement.
pub fn merge(images: &[ExrImage]) -> Result<ExrImage, String> {
    let first = images.first().ok_or("nothing to merge")?;
    let n_px = first.width * first.height;
    for (i, img) in images.iter().enumerate() {
        if (img.width, img.height) != (first.width, first.height) {
            return Err(format!("image {i} is {}x{}, image 0 {}x{}", img.width, img.height, first.width, first.height));
        }
        for key in MUST_AGREE {
            if img.meta(key) != first.meta(key) {
                return Err(format!(
                    "image {i} has {key} = {:?}, image 0 {:?}: renders of different settings do not merge",
                    img.meta(key),
                    first.meta(key)
                ));
            }
        }
        if img.channel("spp.Y").is_none() || img.channel("XYZ.Y").is_none() {
            return Err(format!("image {i} has no spp.Y or XYZ.Y channel (not a quasar render?)"));
        }
        for c in &first.channels {
            if img.channel(&c.name).is_none() {
                return Err(format!("image {i} has no channel {}", c.name));
            }
        }
    }
    let all_streams = check_streams(images)?;
    let counts: Vec<&[f32]> = images.iter().map(|img| img.channel("spp.Y").unwrap_or_default()).collect();
    let total: Vec<f64> = (0..n_px).map(|p| counts.iter().map(|c| c[p] as f64).sum()).collect();
    let spp_of = |k: usize, p: usize| counts[k][p] as f64;
    // the illuminance layer's samples: the same count at every pixel of an image
    let illuminance_n: Vec<f64> =
        images.iter().map(|img| img.meta("illuminance_samples").and_then(|v| v.parse().ok()).unwrap_or(0.0)).collect();
    let illuminance_of = |k: usize, _p: usize| illuminance_n[k];
    // images written before the count was recorded: their layers are averaged by spp.Y
    let illuminance_counted = images.iter().all(|img| img.meta("illuminance_samples").is_some());
    let mut channels = Vec::new();
    for c in &first.channels {
        let values: Vec<f32> = match c.name.as_str() {
            "spp.Y" => total.iter().map(|&t| t as f32).collect(),
            "depth.Z" => c.values.clone(),
            "stderr.Y" => pooled_stderr(images, &spp_of, "XYZ.Y", "stderr.Y"),
            ILLUMINANCE_LX if illuminance_counted => pooled_mean(images, &illuminance_of, ILLUMINANCE_LX),
            ILLUMINANCE_STDERR_LX => pooled_stderr(images, &illuminance_of, ILLUMINANCE_LX, ILLUMINANCE_STDERR_LX),
            name => match name.strip_prefix("stderr.block").and_then(|s| s.parse::<usize>().ok()) {
                Some(size) if size > 0 => pooled_block_stderr(images, &counts, name, size),
                _ => pooled_mean(images, &spp_of, name),
            },
        };
        channels.push(Channel { name: c.name.clone(), values });
    }
    let mut metadata: Vec<(String, String)> = first.metadata.clone();
    for (k, v) in metadata.iter_mut() {
        if SUMMED.contains(&k.as_str()) {
            let sum: f64 = images.iter().filter_map(|img| img.meta(k)?.parse::<f64>().ok()).sum();
            *v = if k == "render_time_s" { format!("{sum:.3}") } else { format!("{sum}") };
        } else if k == "partial" {
            *v = images.iter().any(|img| img.meta("partial") == Some("true")).to_string();
        } else if k == "shard" {
            *v = "merged".into();
        }
    }
    // the shards' spectral files are merged on their own (one `quasar merge` of them)
    metadata.retain(|(k, _)| k != "streams" && k != "spectral_file");
    let list: Vec<String> = all_streams.iter().map(|(seed, k, n)| format!("{seed}:{k}/{n}")).collect();
    metadata.push(("streams".into(), list.join(",")));
    metadata.push(("merged_from".into(), images.len().to_string()));
    Ok(ExrImage { width: first.width, height: first.height, channels, metadata })
}

/// Per pixel, the mean of channel `mean` over all the images' samples, `count(k, p)` of them in
/// image k at pixel p.
fn pooled_mean(images: &[ExrImage], count: &dyn Fn(usize, usize) -> f64, mean: &str) -> Vec<f32> {
    let n_px = images[0].width * images[0].height;
    let means: Vec<&[f32]> = images.iter().map(|img| img.channel(mean).unwrap_or_default()).collect();
    (0..n_px)
        .map(|p| {
            let (mut n, mut sum) = (0.0f64, 0.0f64);
            for (k, m) in means.iter().enumerate() {
                n += count(k, p);
                sum += count(k, p) * m[p] as f64;
            }
            if n > 0.0 { (sum / n) as f32 } else { 0.0 }
        })
        .collect()
}

/// Per pixel, the standard error of the mean of all the images' samples, from each image's
/// mean m, standard error se and sample count n (channels `mean`, `stderr`; `count(k, p)`): the
/// pooled sums sum y = n m and sum y^2 = (n - 1) n se^2 + n m^2.
fn pooled_stderr(images: &[ExrImage], count: &dyn Fn(usize, usize) -> f64, mean: &str, stderr: &str) -> Vec<f32> {
    let n_px = images[0].width * images[0].height;
    let channel =
        |name: &str| -> Vec<&[f32]> { images.iter().map(|img| img.channel(name).unwrap_or_default()).collect() };
    let (means, stderrs) = (channel(mean), channel(stderr));
    (0..n_px)
        .map(|p| {
            let (mut nt, mut sum, mut sq) = (0.0f64, 0.0f64, 0.0f64);
            for k in 0..images.len() {
                let (n, m, se) = (count(k, p), means[k][p] as f64, stderrs[k][p] as f64);
                nt += n;
                sum += n * m;
                sq += (n - 1.0).max(0.0) * n * se * se + n * m * m;
            }
            if nt < 2.0 {
                return 0.0;
            }
            let m = sum / nt;
            (((sq - nt * m * m) / (nt - 1.0)).max(0.0) / nt).sqrt() as f32
        })
        .collect()
}

/// The `stderr.block<size>` channel `name` of the merged image: per block, the batch
/// statistics of every input (K batches, block mean m, standard error se: sum of the squared
/// batch means = (K - 1) K se^2 + K m^2) pooled like the pixels' `stderr.Y`.
fn pooled_block_stderr(images: &[ExrImage], counts: &[&[f32]], name: &str, size: usize) -> Vec<f32> {
    let (w, h) = (images[0].width, images[0].height);
    let cols = w.div_ceil(size);
    let blocks = cols * h.div_ceil(size);
    let mut k_total = vec![0.0f64; blocks];
    let mut sum = vec![0.0f64; blocks];
    let mut sum_sq = vec![0.0f64; blocks];
    for (img, n) in images.iter().zip(counts) {
        let (y, se) = (img.channel("XYZ.Y").unwrap_or_default(), img.channel(name).unwrap_or_default());
        let mut mean = vec![(0.0f64, 0usize); blocks];
        for (p, &v) in y.iter().enumerate().take(w * h) {
            let b = (p / w / size) * cols + (p % w) / size;
            mean[b].0 += v as f64;
            mean[b].1 += 1;
        }
        for (b, (s, c)) in mean.iter().enumerate() {
            let first = (b / cols) * size * w + (b % cols) * size;
            let (k, m, e) = (n[first] as f64, s / (*c).max(1) as f64, se[first] as f64);
            k_total[b] += k;
            sum[b] += k * m;
            sum_sq[b] += (k - 1.0).max(0.0) * k * e * e + k * m * m;
        }
    }
    (0..w * h)
        .map(|p| {
            let b = (p / w / size) * cols + (p % w) / size;
            let k = k_total[b];
            if k < 2.0 {
                return 0.0;
            }
            let m = sum[b] / k;
            (((sum_sq[b] - k * m * m) / (k - 1.0)).max(0.0) / k).sqrt() as f32
        })
        .collect()
}
