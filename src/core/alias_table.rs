//! Walker's alias method (Vose's construction, "A linear algorithm for generating random numbers
//! with a given distribution", 1991; pbrt-v4 `AliasTable`, section A.1): a discrete
//! distribution sampled in constant time, whatever the number of items. The light choice of
//! every next-event estimate and photon uses it, where a scene with thousands of emissive
//! triangles would otherwise binary-search a CDF per sample.

/// One item's column of the table: the item itself with probability `keep`, else `alias`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Column {
    keep: f32,
    alias: u32,
}

/// A discrete distribution over items with non-negative weights: n columns of height 1/n, each
/// split between its own item (a share `keep`) and one other item (`alias`), so that item i's
/// probability p_i = (keep_i + sum over the columns j aliased to i of (1 - keep_j)) / n.
#[derive(Clone, Debug, Default)]
pub struct AliasTable {
    columns: Vec<Column>,
    /// p_i = w_i / sum of the weights; all 0 when the sum is 0.
    pmf: Vec<f32>,
}

impl AliasTable {
    /// Builds the table of `weights` (non-finite or negative weights count as 0). Vose's
    /// construction: columns under height 1 (scaled weight n p_i < 1) are each filled from one
    /// column above it, in f64, so that the probabilities the table realises match `pmf` to
    /// f32 rounding.
    pub fn new(weights: &[f64]) -> Self {
        let w: Vec<f64> = weights.iter().map(|&w| if w.is_finite() && w > 0.0 { w } else { 0.0 }).collect();
        let total: f64 = w.iter().sum();
        let n = w.len();
        if !(total > 0.0 && total.is_finite()) {
            return Self { columns: vec![Column { keep: 0.0, alias: 0 }; n], pmf: vec![0.0; n] };
        }
        let pmf: Vec<f32> = w.iter().map(|&w| (w / total) as f32).collect();
        let mut scaled: Vec<f64> = w.iter().map(|&w| w / total * n as f64).collect();
        let mut columns = vec![Column { keep: 1.0, alias: 0 }; n];
        let (mut small, mut large): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| scaled[i] < 1.0);
        while let (Some(&s), Some(&l)) = (small.last(), large.last()) {
            small.pop();
            columns[s] = Column { keep: scaled[s] as f32, alias: l as u32 };
            scaled[l] -= 1.0 - scaled[s];
            if scaled[l] < 1.0 {
                large.pop();
                small.push(l);
            }
        }
        // what is left holds 1 up to rounding: each such column keeps its own item, except a
        // column of a zero-weight item (possible only through rounding), which is handed whole
        // to the heaviest item so that an item of probability 0 is never chosen
        let heaviest = (0..n).max_by(|&a, &b| w[a].total_cmp(&w[b])).unwrap_or(0) as u32;
        for i in small.into_iter().chain(large) {
            columns[i] =
                if w[i] > 0.0 { Column { keep: 1.0, alias: i as u32 } } else { Column { keep: 0.0, alias: heaviest } };
        }
        Self { columns, pmf }
    }

    /// Number of items.
    pub fn len(&self) -> usize {
        self.columns.len()
    }

    /// True with no items.
    pub fn is_empty(&self) -> bool {
        self.columns.is_empty()
    }

    /// Picks an item with probability p_i from one uniform 64-bit integer `r`: with
    /// x = r n / 2^64, its column floor(x), then the column's item where the fraction of x
    /// within the column is below `keep`, else its alias. The column takes the high bits of the
    /// 128-bit product and the fraction the next 24, so both stay exact to 2^-24 for any
    /// number of items (a 24-bit uniform float would leave a million columns 4 bits for the
    /// fraction). Returns (item, p_item); None when every weight is 0.
    #[inline]
    pub fn sample(&self, r: u64) -> Option<(usize, f32)> {
        let n = self.columns.len();
        if n == 0 {
            return None;
        }
        let x = r as u128 * n as u128;
        let i = (x >> 64) as usize;
        let fraction = ((x as u64) >> 40) as f32 * (1.0 / 16_777_216.0);
        let column = self.columns[i];
        let item = if fraction < column.keep { i } else { column.alias as usize };
        let p = self.pmf[item];
        if p > 0.0 { Some((item, p)) } else { None }
    }

    /// Probability of item `i` (0 outside the table).
    #[inline]
    pub fn pmf(&self, i: usize) -> f32 {
        self.pmf.get(i).copied().unwrap_or(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The probability of each item that the columns realise, computed from the table itself.
    fn realised(t: &AliasTable) -> Vec<f64> {
        let n = t.columns.len() as f64;
        let mut p = vec![0.0; t.columns.len()];
        for (i, c) in t.columns.iter().enumerate() {
            p[i] += c.keep as f64 / n;
            p[c.alias as usize] += (1.0 - c.keep as f64) / n;
        }
        p
    }

    #[test]
    fn the_columns_realise_the_weights() {
        let cases: Vec<Vec<f64>> = vec![
            vec![1.0],
            vec![1.0, 3.0],
            vec![0.0, 5.0, 0.0, 1e-9, 2.0],
            vec![f64::NAN, 1.0, -2.0, f64::INFINITY, 4.0],
            (0..1000).map(|i| ((i * 7919) % 101) as f64 + if i % 3 == 0 { 0.0 } else { 0.5 }).collect(),
            (0..64).map(|i| 2f64.powi(i % 40)).collect(),
        ];
        for w in cases {
            let t = AliasTable::new(&w);
            let finite: Vec<f64> = w.iter().map(|&v| if v.is_finite() && v > 0.0 { v } else { 0.0 }).collect();
            let total: f64 = finite.iter().sum();
            for (i, (&p, &wi)) in realised(&t).iter().zip(&finite).enumerate() {
                let want = wi / total;
                assert!(
                    (p - want).abs() <= 1e-6 * want.max(1.0 / w.len() as f64),
                    "item {i} of {}: {p} vs {want}",
                    w.len()
                );
                assert!((t.pmf(i) as f64 - want).abs() <= want * 1e-6, "pmf of item {i}");
                if wi == 0.0 {
                    assert_eq!(p, 0.0, "item {i} has no weight but can be chosen");
                }
            }
        }
    }

    #[test]
    fn sampling_matches_the_pmf_chi_square() {
        // 20 items of uneven weights (two of them zero), 400 k random 64-bit numbers (PCG's
        // LCG step, high half twice): Pearson's chi-square of the counts against n p_i
        let w: Vec<f64> = (0..20).map(|i| if i % 7 == 3 { 0.0 } else { 1.0 + ((i * 37) % 11) as f64 }).collect();
        let t = AliasTable::new(&w);
        let n = 400_000usize;
        let mut counts = vec![0u64; w.len()];
        let mut state = 0x853c_49e6_748f_ea9bu64;
        for _ in 0..n {
            let mut r = 0u64;
            for _ in 0..2 {
                state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
                r = (r << 32) | (state >> 32);
            }
            let (i, p) = t.sample(r).expect("positive weights");
            assert_eq!(p, t.pmf(i));
            counts[i] += 1;
        }
        let mut chi2 = 0.0;
        let mut dof = 0;
        for (i, &c) in counts.iter().enumerate() {
            let e = t.pmf(i) as f64 * n as f64;
            if e == 0.0 {
                assert_eq!(c, 0, "item {i} of weight 0 was chosen");
                continue;
            }
            chi2 += (c as f64 - e).powi(2) / e;
            dof += 1;
        }
        // 17 degrees of freedom: the 0.999 quantile is 40.8
        assert!(chi2 < 40.8, "chi-square {chi2} over {} items", dof);
    }

    #[test]
    fn a_wrong_table_fails_the_chi_square() {
        // the test above must catch a wrong table: 2% of the total probability moved from item 0
        // to item 1 (8% of its column), counted on an even grid of 64-bit numbers
        let w = vec![1.0; 4];
        let mut t = AliasTable::new(&w);
        t.columns[0] = Column { keep: 0.92, alias: 1 };
        let n = 400_000usize;
        let mut counts = [0u64; 4];
        for k in 0..n {
            let r = ((k as u128 * 2 + 1) << 63) / n as u128;
            counts[t.sample(r as u64).unwrap().0] += 1;
        }
        let chi2: f64 = counts.iter().map(|&c| (c as f64 - n as f64 / 4.0).powi(2) / (n as f64 / 4.0)).sum();
        assert!(chi2 > 40.8, "chi-square {chi2}");
    }

    #[test]
    fn no_weight_no_sample() {
        assert!(AliasTable::new(&[]).sample(1 << 63).is_none());
        let t = AliasTable::new(&[0.0, f64::NAN, -1.0]);
        for r in [0, u64::MAX / 3, u64::MAX] {
            assert!(t.sample(r).is_none());
        }
        assert_eq!(t.pmf(1), 0.0);
        let one = AliasTable::new(&[0.0, 2.0, 0.0]);
        for r in [0, 1 << 62, u64::MAX / 2, u64::MAX - 1, u64::MAX] {
            assert_eq!(one.sample(r), Some((1, 1.0)));
        }
    }
}
