//! `quasar merge`: combines independent renders of one scene (shards of a render, or renders with
//! different seeds) into one image, exactly as if their samples had been accumulated together.
//! Each channel is combined by the rule of its row of the output table
//! ([`crate::film::outputs::OUTPUTS`]: a mean channel is the per-pixel average weighted by the
//! sample counts of `spp.Y`, `spp.Y` their sum, a standard error recomputed from the pooled sums
//! of squares, `illuminance.Y` pooled over each image's `illuminance_samples`), and each header
//! entry by its row of the header table ([`crate::render::header::HEADER`]).

use crate::film::outputs::{self, MergeRule};
use crate::film::{Channel, LUMINANCE, REL_EPS, SAMPLES, STDERR};
use crate::output::ExrImage;
use crate::render::header::{HeaderMerge, header_key};

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

/// Merges `images` (at least one). Errors name the first disagreement.
pub fn merge(images: &[ExrImage]) -> Result<ExrImage, String> {
    let first = images.first().ok_or("nothing to merge")?;
    let n_px = first.width * first.height;
    for (i, img) in images.iter().enumerate() {
        if (img.width, img.height) != (first.width, first.height) {
            return Err(format!("image {i} is {}x{}, image 0 {}x{}", img.width, img.height, first.width, first.height));
        }
        for (key, value) in &img.metadata {
            let agree = header_key(key).is_some_and(|h| h.merge == HeaderMerge::Agree);
            if agree && first.meta(key) != Some(value) {
                return Err(format!(
                    "image {i} has {key} = {value:?}, image 0 {:?}: renders of different settings do not merge",
                    first.meta(key)
                ));
            }
        }
        for (key, _) in &first.metadata {
            if header_key(key).is_some_and(|h| h.merge == HeaderMerge::Agree) && img.meta(key).is_none() {
                return Err(format!("image {i} has no {key}, image 0 has: renders of different settings do not merge"));
            }
        }
        if img.channel(SAMPLES).is_none() || img.channel(LUMINANCE).is_none() {
            return Err(format!("image {i} has no {SAMPLES} or {LUMINANCE} channel (not a quasar render?)"));
        }
        for c in &first.channels {
            if img.channel(&c.name).is_none() {
                return Err(format!("image {i} has no channel {}", c.name));
            }
        }
    }
    let all_streams = check_streams(images)?;
    let counts: Vec<&[f32]> = images.iter().map(|img| img.channel(SAMPLES).unwrap_or_default()).collect();
    let total: Vec<f64> = (0..n_px).map(|p| counts.iter().map(|c| c[p] as f64).sum()).collect();
    let spp_of = |k: usize, p: usize| counts[k][p] as f64;
    // a count from the header: the same at every pixel of an image (None when an image lacks it)
    let header_counts = |key: &str| -> Option<Vec<f64>> {
        images.iter().map(|img| img.meta(key).and_then(|v| v.parse().ok())).collect()
    };
    let mut channels = Vec::new();
    for c in &first.channels {
        let row = outputs::group_of(&c.name).ok_or_else(|| {
            format!("channel {} is no output of this quasar (film/outputs.rs): it cannot be merged", c.name)
        })?;
        let values: Vec<f32> = match row.merge {
            MergeRule::Sum => total.iter().map(|&t| t as f32).collect(),
            MergeRule::First => c.values.clone(),
            MergeRule::SampleMean => pooled_mean(images, &spp_of, &c.name),
            MergeRule::PooledStderr { mean } => pooled_stderr(images, &spp_of, mean, &c.name),
            MergeRule::PooledBlockStderr => {
                let size = c.name.rsplit_once(".block").and_then(|(_, n)| n.parse::<usize>().ok()).unwrap_or(1);
                pooled_block_stderr(images, &counts, &c.name, size)
            }
            MergeRule::HeaderCountMean { count } => match header_counts(count) {
                Some(n) => pooled_mean(images, &|k, _| n[k], &c.name),
                // images written before the count was recorded: averaged by spp.Y
                None => pooled_mean(images, &spp_of, &c.name),
            },
            MergeRule::HeaderCountStderr { mean, count } => {
                let n = header_counts(count).unwrap_or_else(|| vec![0.0; images.len()]);
                pooled_stderr(images, &|k, _| n[k], mean, &c.name)
            }
        };
        channels.push(Channel { name: c.name.clone(), values });
    }
    let mut metadata: Vec<(String, String)> = Vec::new();
    for (k, v) in &first.metadata {
        let rule = header_key(k).map_or(HeaderMerge::First, |h| h.merge);
        let merged = match rule {
            HeaderMerge::Sum => {
                let sum: f64 = images.iter().filter_map(|img| img.meta(k)?.parse::<f64>().ok()).sum();
                if k == "render_time_s" { format!("{sum:.3}") } else { format!("{sum}") }
            }
            HeaderMerge::AnyTrue => images.iter().any(|img| img.meta(k) == Some("true")).to_string(),
            HeaderMerge::Merged => "merged".into(),
            HeaderMerge::Recomputed => format!("{:.6}", estimated_rel_error(&channels)),
            HeaderMerge::Dropped => continue,
            HeaderMerge::Agree | HeaderMerge::First => v.clone(),
        };
        metadata.push((k.clone(), merged));
    }
    let list: Vec<String> = all_streams.iter().map(|(seed, k, n)| format!("{seed}:{k}/{n}")).collect();
    metadata.push(("streams".into(), list.join(",")));
    metadata.push(("merged_from".into(), images.len().to_string()));
    Ok(ExrImage { width: first.width, height: first.height, channels, metadata })
}

/// The estimated RMS relative error of merged channels, sqrt of the mean over pixels of
/// stderr.Y² / (XYZ.Y² + 1e-3) (as the film estimates it, `Film::estimated_rel_error`).
fn estimated_rel_error(channels: &[Channel]) -> f64 {
    let get = |n: &str| channels.iter().find(|c| c.name == n).map(|c| c.values.as_slice()).unwrap_or_default();
    let (y, se) = (get(LUMINANCE), get(STDERR));
    let sum: f64 = y.iter().zip(se).map(|(&y, &e)| (e as f64).powi(2) / ((y as f64).powi(2) + REL_EPS)).sum();
    (sum / y.len().max(1) as f64).sqrt()
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
        let (y, se) = (img.channel(LUMINANCE).unwrap_or_default(), img.channel(name).unwrap_or_default());
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
