//! Where on one textured emissive triangle its light samples and photons start (issue 50 item 3,
//! docs/architecture.md §4): a piecewise-constant density over a regular grid of sub-triangles,
//! each weighted by the emitted luminance its texels carry, so that a mostly black emissive
//! texture spends its samples where it is lit.

use glam::{Vec2, Vec3};

use crate::core::emission::{EmissionTexture, bary_uv, rgb_luminance, textured_weight};
use crate::core::geometry::TriangleGeom;
use crate::core::sampling::{Distribution1D, uniform_triangle};

/// Most subdivisions of a triangle's edges (at most 64^2 = 4096 sub-triangles).
const MAX_DIVISIONS: u32 = 64;

/// Most texels read to bound the sub-triangles' emission exactly; beyond, the weights come
/// from points in each sub-triangle with a floor.
const MAX_BOUND_READS: usize = 1 << 22;

/// Subdivisions of a sub-triangle's edges whose centroids weigh it (16 points).
const POINT_DIVISIONS: u32 = 4;

/// Share of the mean sub-triangle weight that every sub-triangle keeps when the weights come
/// from points only (lit places between the points read keep a non-zero density), and share of
/// its texels' bound that a sub-triangle keeps when its points read black.
const FLOOR: f64 = 0.01;

/// A grid density is kept only where it is this much more uneven than uniform (its largest
/// weight over its mean); below, uniform sampling is as good and costs nothing.
const MIN_CONTRAST: f64 = 1.25;

/// The density of sample points over one triangle, relative to uniform: the triangle's
/// barycentric square (b1, b2) is cut into N x N cells, each an upright sub-triangle (cell
/// fractions f1 + f2 < 1) and, off the diagonal, an inverted one; sub-triangle k is chosen with
/// probability w_k / sum w and sampled uniformly, so the area density is
/// N^2 w_k / sum(w) / area (pbrt-v4's piecewise-constant 2D distributions, on a triangle).
#[derive(Clone, Debug)]
pub struct EmissionGrid {
    /// N: subdivisions of each edge.
    divisions: u32,
    /// Over the N (N + 1) slots ([`slot`]: the N (N + 1) / 2 cells, upright then inverted).
    slots: Distribution1D,
}

/// How the points of one textured emissive triangle are drawn.
#[derive(Clone, Debug)]
pub enum Coverage {
    /// No texel within reach of the triangle is lit: it emits nothing anywhere.
    Dark,
    /// Uniformly by area (a triangle within a few texels, or an even texture).
    Even,
    /// From the grid.
    Grid(EmissionGrid),
}

impl EmissionGrid {
    /// How to draw the points of a triangle with vertex texture coordinates `uv` emitting `t`:
    /// N^2 about four times the texels it covers (N <= 64, snapped to texel edges by
    /// `aligned_divisions`), each sub-triangle weighted by the mean emitted luminance of 16
    /// points in it (the centroids of its own 4 x 4 grid: about its lit share where a texel edge
    /// crosses it), or, where those read black, by 1% of the largest luminance of the texels
    /// that its lookups can read (nearest or bilinear, over its texture-space box): that bound
    /// is 0 only where no light is, so every lit point keeps a non-zero density. Where the
    /// bounds would read more than 4M texels, every sub-triangle keeps 1% of the mean weight
    /// instead. A grid within 1.25x of uniform is not kept.
    pub fn cover(t: &EmissionTexture, uv: &[Vec2; 3]) -> Coverage {
        let (w, h) = t.image.size();
        let m = uv.map(|p| crate::core::texture::mapped(&t.reference, p));
        let texels = 0.5 * ((m[1] - m[0]).perp_dot(m[2] - m[0])).abs() * w as f32 * h as f32;
        if !texels.is_finite() {
            return Coverage::Even;
        }
        let target = (2.0 * texels.sqrt()).ceil().clamp(1.0, MAX_DIVISIONS as f32) as u32;
        let texel = |p: Vec2| p * Vec2::new(w as f32, h as f32);
        let n = aligned_divisions([texel(m[0]), texel(m[1] - m[0]), texel(m[2] - m[0])], target);
        if n < 2 {
            return Coverage::Even;
        }
        let texel_box = |p: [Vec2; 3]| {
            let q = p.map(|b| crate::core::texture::mapped(&t.reference, bary_uv(uv, b.x, b.y)));
            let (lo, hi) = (q[0].min(q[1]).min(q[2]), q[0].max(q[1]).max(q[2]));
            // a lookup at texel coordinate s reads texel floor(s) (nearest) or floor(s - 1/2) and
            // the next (bilinear)
            let range = |lo: f32, hi: f32, size: u32| {
                let (lo, hi) = (lo * size as f32, hi * size as f32);
                if t.image.is_nearest() {
                    (lo.floor() as i64, hi.floor() as i64)
                } else {
                    ((lo - 0.5).floor() as i64, (hi - 0.5).floor() as i64 + 1)
                }
            };
            (range(lo.x, hi.x, w), range(lo.y, hi.y, h))
        };
        let reads: usize = sub_triangles(n)
            .map(|(i, j, inverted)| {
                let ((x0, x1), (y0, y1)) = texel_box(corners(n, i, j, inverted));
                ((x1 - x0 + 1) as usize).saturating_mul((y1 - y0 + 1) as usize)
            })
            .fold(0usize, usize::saturating_add);
        let exact = reads <= MAX_BOUND_READS;
        let lum = |p: Vec2| f64::from(rgb_luminance(t.rgb(bary_uv(uv, p.x, p.y))));
        let mut weights = vec![0.0f64; slot_count(n)];
        for (i, j, inverted) in sub_triangles(n) {
            let c = corners(n, i, j, inverted);
            // the mean luminance of the centroids of a 4 x 4 grid of the sub-triangle's own
            // sub-triangles: about its lit share where a texel edge crosses it
            let points = (0..POINT_DIVISIONS)
                .flat_map(|a| (0..POINT_DIVISIONS - a).flat_map(move |b| [(a, b, false), (a, b, true)]))
                .filter(|&(a, b, inv)| !inv || a + b + 1 < POINT_DIVISIONS)
                .map(|(a, b, inv)| {
                    let k = corners(POINT_DIVISIONS, a, b, inv);
                    let q = (k[0] + k[1] + k[2]) / 3.0;
                    lum(c[0] + (c[1] - c[0]) * q.x + (c[2] - c[0]) * q.y)
                })
                .sum::<f64>()
                / f64::from(POINT_DIVISIONS * POINT_DIVISIONS);
            weights[slot(n, i, j, inverted)] = if exact {
                let ((x0, x1), (y0, y1)) = texel_box(c);
                let mut bound = 0.0f32;
                for y in y0..=y1 {
                    for x in x0..=x1 {
                        let centre = Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                        let texel = t.image.sample(centre, true);
                        bound = bound.max(rgb_luminance([0, 1, 2].map(|k| t.factor[k] * texel[k])));
                    }
                }
                points.max(FLOOR * f64::from(bound))
            } else {
                points
            };
        }
        let mean = weights.iter().sum::<f64>() / (n * n) as f64;
        let max = weights.iter().copied().fold(0.0, f64::max);
        if exact && max == 0.0 {
            return Coverage::Dark;
        }
        if !(mean > 0.0 && mean.is_finite()) || max <= MIN_CONTRAST * mean {
            return Coverage::Even;
        }
        if !exact {
            for (i, j, inverted) in sub_triangles(n) {
                weights[slot(n, i, j, inverted)] += FLOOR * mean;
            }
        }
        Coverage::Grid(Self { divisions: n, slots: Distribution1D::new(&weights) })
    }

    /// A point (b1, b2) of the triangle drawn from the density with uniform numbers `u`, and
    /// the density there relative to uniform (area pdf times the triangle's area).
    #[inline]
    pub fn sample(&self, u: Vec2) -> (f32, f32, f32) {
        let n = self.divisions;
        let Some((k, pmf, r)) = self.slots.sample_remapped(u.x) else {
            let (b1, b2) = uniform_triangle(u);
            return (b1, b2, 1.0);
        };
        let (i, j) = cell(n, k / 2);
        let [a, b, c] = corners(n, i, j, k % 2 == 1);
        let (s1, s2) = uniform_triangle(Vec2::new(r, u.y));
        let p = a + (b - a) * s1 + (c - a) * s2;
        (p.x, p.y, pmf * (n * n) as f32)
    }

    /// The density relative to uniform at barycentrics (b1, b2): that of the sub-triangle
    /// holding the point ([`sample`](Self::sample)'s).
    #[inline]
    pub fn density(&self, b1: f32, b2: f32) -> f32 {
        let n = self.divisions;
        self.slots.pmf(self.locate(b1, b2)) * (n * n) as f32
    }

    /// The slot of the sub-triangle holding barycentrics (b1, b2), points off the triangle
    /// clamped onto it.
    #[inline]
    fn locate(&self, b1: f32, b2: f32) -> usize {
        let n = self.divisions;
        let nf = n as f32;
        let (x, y) = ((b1 * nf).clamp(0.0, nf), (b2 * nf).clamp(0.0, nf));
        let i = (x as u32).min(n - 1);
        let j = (y as u32).min(n - 1 - i);
        let inverted = (x - i as f32) + (y - j as f32) >= 1.0 && i + j + 1 < n;
        slot(n, i, j, inverted)
    }

    /// The density relative to uniform at the point `p` of triangle `tri` (its barycentrics
    /// solved from the edges: a point a ray hit on the triangle, in its plane to rounding).
    #[inline]
    pub fn density_at(&self, tri: &TriangleGeom, p: Vec3) -> f32 {
        let (e1, e2, d) = (Vec3::from(tri.e1), Vec3::from(tri.e2), p - Vec3::from(tri.v0));
        let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
        let (d1, d2) = (d.dot(e1), d.dot(e2));
        let det = d11 * d22 - d12 * d12;
        if det.is_nan() || det <= 0.0 {
            return 1.0;
        }
        self.density((d22 * d1 - d12 * d2) / det, (d11 * d2 - d12 * d1) / det)
    }
}

/// A textured emissive triangle's selection weight relative to its emission's nominal colour of
/// luminance `nominal` ([`textured_weight`]; 0 where it is [`Coverage::Dark`]) and the grid its
/// points are drawn from (None: uniformly).
pub fn textured_triangle(t: &EmissionTexture, uv: &[Vec2; 3], nominal: f32) -> (f32, Option<EmissionGrid>) {
    match EmissionGrid::cover(t, uv) {
        Coverage::Dark => (0.0, None),
        Coverage::Even => (textured_weight(t, uv, nominal), None),
        Coverage::Grid(g) => (textured_weight(t, uv, nominal), Some(g)),
    }
}

/// N for a triangle whose first vertex and edges in texel units are `v0_e1_e2`, about
/// `target`: where all of them are whole texels (a quad mapped onto a whole image, a sign, a
/// display), a multiple or divisor of their common divisor g, so that the grid's lines fall on
/// texel edges and no sub-triangle is partly lit under nearest lookups (the smallest multiple
/// of g >= target, or the smallest divisor of g >= target, within [`MAX_DIVISIONS`]); else
/// `target`.
fn aligned_divisions(v0_e1_e2: [Vec2; 3], target: u32) -> u32 {
    let mut g = 0u64;
    for c in v0_e1_e2.iter().flat_map(|v| [v.x, v.y]) {
        let r = c.round();
        if !c.is_finite() || (c - r).abs() > 1e-3 || r.abs() > 1e6 {
            return target;
        }
        g = gcd(g, r.abs() as u64);
    }
    let max = u64::from(MAX_DIVISIONS);
    let target = u64::from(target);
    let n = if g == 0 {
        target
    } else if g < target {
        let m = g * target.div_ceil(g);
        if m <= max { m } else { g * (max / g).max(1) }
    } else {
        (target..=max)
            .find(|&d| g.is_multiple_of(d))
            .or_else(|| (1..=max).rev().find(|&d| g.is_multiple_of(d)))
            .unwrap_or(target)
    };
    n.clamp(1, max) as u32
}

/// Greatest common divisor (gcd(0, x) = x).
fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 { a } else { gcd(b, a % b) }
}

/// Every sub-triangle of an N-grid: (i, j, inverted).
fn sub_triangles(n: u32) -> impl Iterator<Item = (u32, u32, bool)> {
    (0..n).flat_map(move |i| {
        (0..n - i).flat_map(move |j| [(i, j, false), (i, j, true)].into_iter().filter(move |s| !s.2 || i + j + 1 < n))
    })
}

/// The slot of cell (i, j)'s upright or inverted sub-triangle: cells packed row by row (row i
/// holds the N - i cells j < N - i, from offset i N - i (i - 1) / 2), two slots each.
#[inline]
fn slot(n: u32, i: u32, j: u32, inverted: bool) -> usize {
    2 * (i * n - i * i.saturating_sub(1) / 2 + j) as usize + usize::from(inverted)
}

/// Slots of an N-grid: two for each of its N (N + 1) / 2 cells (the last cell of a row has no
/// inverted sub-triangle; its slot keeps weight 0).
fn slot_count(n: u32) -> usize {
    (n * (n + 1)) as usize
}

/// The cell (i, j) of packed cell index `c` ([`slot`]'s order): the row from the quadratic
/// offset(i) = i (2 N + 1 - i) / 2 <= c, corrected for rounding.
#[inline]
fn cell(n: u32, c: usize) -> (u32, u32) {
    let offset = |i: u32| (i * (2 * n + 1 - i) / 2) as usize;
    let b = 2.0 * n as f32 + 1.0;
    let mut i = ((b - (b * b - 8.0 * c as f32).max(0.0).sqrt()) * 0.5) as u32;
    i = i.min(n - 1);
    while i > 0 && offset(i) > c {
        i -= 1;
    }
    while i + 1 < n && offset(i + 1) <= c {
        i += 1;
    }
    (i, (c - offset(i)) as u32)
}

/// The barycentric corners (b1, b2) of cell (i, j)'s upright sub-triangle, (i, j), (i + 1, j),
/// (i, j + 1) over N, or of its inverted one, (i + 1, j + 1), (i, j + 1), (i + 1, j) over N.
#[inline]
fn corners(n: u32, i: u32, j: u32, inverted: bool) -> [Vec2; 3] {
    let s = 1.0 / n as f32;
    let (i, j) = (i as f32, j as f32);
    if inverted {
        [Vec2::new(i + 1.0, j + 1.0) * s, Vec2::new(i, j + 1.0) * s, Vec2::new(i + 1.0, j) * s]
    } else {
        [Vec2::new(i, j) * s, Vec2::new(i + 1.0, j) * s, Vec2::new(i, j + 1.0) * s]
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use quasar_importers::{SourceLocation, TextureDesc, TextureRef, TextureWrap};

    use super::*;
    use crate::core::texture::ImageTexture;

    /// A `size` x `size` texture, lit (white) where `lit(x, y)`, else black; nearest texels.
    fn texture(size: u32, lit: impl Fn(u32, u32) -> bool) -> EmissionTexture {
        let texels = (0..size * size).map(|k| if lit(k % size, k / size) { [255; 4] } else { [0, 0, 0, 255] });
        let desc = TextureDesc {
            name: "t".into(),
            width: size,
            height: size,
            texels: texels.collect(),
            wrap_u: TextureWrap::ClampToEdge,
            wrap_v: TextureWrap::ClampToEdge,
            nearest: true,
            source: SourceLocation::default(),
        };
        EmissionTexture { image: Arc::new(ImageTexture::new(&desc)), reference: TextureRef::new(0), factor: [1.0; 3] }
    }

    /// The lower-left half of the texture square: uv = barycentrics.
    const UV: [Vec2; 3] = [Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0)];

    fn halton(i: u32, base: u32) -> f32 {
        let (mut f, mut r, mut i) = (1.0f32, 0.0f32, i);
        while i > 0 {
            f /= base as f32;
            r += f * (i % base) as f32;
            i /= base;
        }
        r
    }

    /// The density integrates to 1 over the triangle; the points drawn fall in each
    /// sub-triangle as often as its density says (chi-square over the sub-triangles), and
    /// `density` at a drawn point is the density `sample` returned.
    #[test]
    fn the_grid_is_a_density_and_its_sampler_draws_it() {
        let t = texture(16, |x, y| (x / 4 + y / 4) % 2 == 0 || x == 13);
        let Coverage::Grid(g) = EmissionGrid::cover(&t, &UV) else { panic!("an uneven texture over 128 texels") };
        let n = g.divisions;
        assert_eq!(n, 32, "2 sqrt(128) = 22.6, up to a multiple of the 16-texel edges' divisor");
        // integral over the triangle (uniform points): the mean density is 1
        let m = 200_000;
        let mean = (0..m)
            .map(|k| {
                let (b1, b2) = uniform_triangle(Vec2::new(halton(k + 1, 2), halton(k + 1, 3)));
                f64::from(g.density(b1, b2))
            })
            .sum::<f64>()
            / f64::from(m);
        assert!((mean - 1.0).abs() < 2e-3, "{mean}");
        // chi-square of the drawn points over the slots
        let draws = 400_000u32;
        let mut counts = vec![0u32; slot_count(n)];
        let mut rng = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..draws {
            let u = Vec2::new(next(&mut rng), next(&mut rng));
            let (b1, b2, d) = g.sample(u);
            assert!(b1 >= -1e-6 && b2 >= -1e-6 && b1 + b2 <= 1.0 + 1e-5, "({b1}, {b2})");
            let back = g.density(b1, b2);
            assert!((back - d).abs() <= 1e-4 * d, "{back} vs {d} at ({b1}, {b2})");
            counts[g.locate(b1, b2)] += 1;
        }
        let (mut chi2, mut dof) = (0.0f64, 0usize);
        for (k, &c) in counts.iter().enumerate() {
            let expected = f64::from(draws) * f64::from(g.slots.pmf(k));
            if expected > 0.0 {
                chi2 += (f64::from(c) - expected).powi(2) / expected;
                dof += 1;
            } else {
                assert_eq!(c, 0, "slot {k} has no weight but was drawn");
            }
        }
        // the 1e-4 tail of chi-square with dof - 1 degrees of freedom (Wilson-Hilferty)
        let k = (dof - 1) as f64;
        let limit = k * (1.0 - 2.0 / (9.0 * k) + 3.719 * (2.0 / (9.0 * k)).sqrt()).powi(3);
        assert!(chi2 < limit, "chi2 {chi2} over {dof} slots, limit {limit}");
    }

    /// Packed slots: every sub-triangle has its own slot, inside the slot count, and `cell`
    /// inverts the packing.
    #[test]
    fn slots_pack_the_cells_of_the_triangle() {
        for n in [1, 2, 3, 7, 46, 64] {
            let mut seen = vec![false; slot_count(n)];
            for (i, j, inverted) in sub_triangles(n) {
                let k = slot(n, i, j, inverted);
                assert!(!seen[k], "n {n}: slot {k} twice");
                seen[k] = true;
                assert_eq!(cell(n, k / 2), (i, j), "n {n}");
            }
            assert_eq!(seen.iter().filter(|&&s| s).count(), (n * n) as usize);
        }
    }

    /// The grid snaps to whole texels where the triangle's corners sit on texel corners.
    #[test]
    fn divisions_align_with_whole_texels() {
        let v = |x: f32, y: f32| Vec2::new(x, y);
        // legs of 16 texels: multiples of 16
        assert_eq!(aligned_divisions([v(0.0, 0.0), v(16.0, 0.0), v(0.0, 16.0)], 23), 32);
        assert_eq!(aligned_divisions([v(0.0, 0.0), v(16.0, 0.0), v(0.0, 16.0)], 9), 16);
        // legs of 512 texels: the smallest divisor >= the target
        assert_eq!(aligned_divisions([v(0.0, 0.0), v(512.0, 0.0), v(512.0, 512.0)], 40), 64);
        // the common divisor of 3, 5, 12 and 18 is 1: multiples of 1
        assert_eq!(aligned_divisions([v(3.0, 5.0), v(12.0, 0.0), v(0.0, 18.0)], 20), 20);
        // 6, 12, 18: multiples of 6
        assert_eq!(aligned_divisions([v(6.0, 0.0), v(12.0, 0.0), v(0.0, 18.0)], 20), 24);
        // off the texel lattice: the target
        assert_eq!(aligned_divisions([v(0.5, 0.0), v(16.0, 0.0), v(0.0, 16.0)], 23), 23);
        assert_eq!(aligned_divisions([v(0.0, 0.0), v(16.3, 0.0), v(0.0, 16.0)], 23), 23);
    }

    fn next(s: &mut u64) -> f32 {
        *s = s.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        ((*s >> 40) as f32) / (1u64 << 24) as f32
    }

    /// A mostly black texture (one lit 4 x 4 patch of 64 x 64 texels): nearly every point drawn
    /// is lit, where uniform sampling would find light at 1 point in 128; an even texture and a triangle within a texel get no grid, and a
    /// triangle whose reach holds no lit texel is dark.
    #[test]
    fn a_mostly_black_texture_costs_nothing_where_it_is_black() {
        let t = texture(64, |x, y| (8..12).contains(&x) && (40..44).contains(&y));
        let Coverage::Grid(g) = EmissionGrid::cover(&t, &UV) else { panic!() };
        let draws = 10_000;
        let mut lit = 0;
        for k in 0..draws {
            let (b1, b2, _) = g.sample(Vec2::new(halton(k + 1, 2), halton(k + 1, 3)));
            if t.rgb(bary_uv(&UV, b1, b2))[0] > 0.0 {
                lit += 1;
            }
        }
        assert!(lit as f32 > 0.95 * draws as f32, "{lit} of {draws} points lit");
        assert!(matches!(EmissionGrid::cover(&texture(64, |_, _| true), &UV), Coverage::Even));
        let tiny = [Vec2::new(0.5, 0.5), Vec2::new(0.51, 0.5), Vec2::new(0.5, 0.51)];
        assert!(matches!(EmissionGrid::cover(&t, &tiny), Coverage::Even));
        // the upper-right half of the texture square, two texels and more from the patch
        let far = [Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 1.0)];
        assert!(matches!(EmissionGrid::cover(&t, &far), Coverage::Dark));
    }
}
