//! False-colour maps of a photometric quantity (luminance in cd/m², illuminance in lx) with a
//! drawn legend: a colour bar, tick values and the quantity's name and unit (docs/photometry.md
//! "False colour"). The colour ramp is viridis (perceptually uniform, readable in greyscale);
//! values below the range take the lowest colour, above it the highest.

use crate::output::text::{Align, draw_text, text_width};

/// How values map to the colour ramp.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColourScale {
    /// t = (v - min) / (max - min).
    Linear,
    /// t = log10(v / min) / log10(max / min).
    Log,
}

impl ColourScale {
    /// Parses `linear` or `log`.
    pub fn from_name(name: &str) -> Result<Self, String> {
        match name {
            "linear" | "lin" => Ok(Self::Linear),
            "log" => Ok(Self::Log),
            _ => Err(format!("unknown scale `{name}` (linear, log)")),
        }
    }
}

/// The viridis ramp at t = 0, 1/8, ..., 1 (sRGB).
const VIRIDIS: [[f32; 3]; 9] = [
    [68.0, 1.0, 84.0],
    [71.0, 44.0, 122.0],
    [59.0, 81.0, 139.0],
    [44.0, 113.0, 142.0],
    [33.0, 144.0, 141.0],
    [39.0, 173.0, 129.0],
    [92.0, 200.0, 99.0],
    [170.0, 220.0, 50.0],
    [253.0, 231.0, 37.0],
];

/// The ramp's colour at `t` in [0, 1] (piecewise-linear between the stops).
pub fn ramp(t: f64) -> [u8; 3] {
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
    let x = t * 8.0;
    let i = (x.floor() as usize).min(7);
    let f = (x - i as f64) as f32;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    [0, 1, 2].map(|k| (a[k] + f * (b[k] - a[k])).round() as u8)
}

/// A value range, its scale and the legend title (quantity and unit).
#[derive(Clone, Debug, PartialEq)]
pub struct FalseColour {
    /// Value at the bottom of the ramp (> 0 on a log scale).
    pub min: f64,
    /// Value at the top of the ramp (> min).
    pub max: f64,
    /// Linear or logarithmic.
    pub scale: ColourScale,
    /// Legend title, e.g. `illuminance (lx)`.
    pub title: String,
}

/// The smallest of 1, 2, 5 x 10^k at or above `v` (> 0).
fn nice_ceil(v: f64) -> f64 {
    let p = 10f64.powf(v.log10().floor());
    [1.0, 2.0, 5.0, 10.0].into_iter().map(|m| m * p).find(|&c| c >= v * (1.0 - 1e-12)).unwrap_or(10.0 * p)
}

impl FalseColour {
    /// A range fitted to `values` (non-finite ones ignored): linear from 0 to the maximum rounded
    /// up to 1, 2 or 5 x 10^k; log from the power of ten at or below the 1st percentile of the
    /// positive values (at most four decades down) to the power of ten at or above the maximum.
    pub fn fit(values: &[f32], scale: ColourScale, title: &str) -> Self {
        let mut v: Vec<f64> = values.iter().map(|&x| f64::from(x)).filter(|x| x.is_finite() && *x > 0.0).collect();
        v.sort_by(f64::total_cmp);
        let top = v.last().copied().unwrap_or(1.0);
        let (min, max) = match scale {
            ColourScale::Linear => (0.0, nice_ceil(top)),
            ColourScale::Log => {
                let hi = 10f64.powf(top.log10().ceil());
                let p1 = v.get(v.len() / 100).copied().unwrap_or(hi / 10.0);
                let lo = 10f64.powf(p1.log10().floor()).max(hi / 1e4).min(hi / 10.0);
                (lo, hi)
            }
        };
        Self { min, max, scale, title: title.to_string() }
    }

    /// Checks that the range can be drawn (finite, min < max, min > 0 on a log scale).
    pub fn validate(&self) -> Result<(), String> {
        if !(self.min.is_finite() && self.max.is_finite() && self.min < self.max) {
            return Err(format!("false-colour range {}..{} is empty", self.min, self.max));
        }
        if self.scale == ColourScale::Log && self.min <= 0.0 {
            return Err(format!("a log false-colour range must start above 0, not at {}", self.min));
        }
        Ok(())
    }

    /// The position of `v` on the ramp, in [0, 1] (clamped; non-finite -> 0).
    pub fn t(&self, v: f64) -> f64 {
        let t = match self.scale {
            ColourScale::Linear => (v - self.min) / (self.max - self.min),
            ColourScale::Log if v > 0.0 => (v / self.min).log10() / (self.max / self.min).log10(),
            ColourScale::Log => 0.0,
        };
        if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 }
    }

    /// Tick values of the legend: on a log scale the powers of ten (and 2 and 5 x 10^k when the
    /// range spans at most two decades), linearly a 1-2-5 step giving 4 to 10 ticks.
    pub fn ticks(&self) -> Vec<f64> {
        let mut out = Vec::new();
        match self.scale {
            ColourScale::Log => {
                let few = self.max / self.min <= 100.0 * (1.0 + 1e-9);
                let (d0, d1) = (self.min.log10().floor() as i32, self.max.log10().ceil() as i32);
                for d in d0..=d1 {
                    for m in if few { &[1.0, 2.0, 5.0][..] } else { &[1.0][..] } {
                        let v = m * 10f64.powi(d);
                        if v >= self.min * (1.0 - 1e-9) && v <= self.max * (1.0 + 1e-9) {
                            out.push(v);
                        }
                    }
                }
            }
            ColourScale::Linear => {
                let step = nice_ceil((self.max - self.min) / 8.0);
                let mut v = (self.min / step).ceil() * step;
                while v <= self.max + 1e-9 * step {
                    out.push(v);
                    v += step;
                }
            }
        }
        out
    }

    /// A `w` x `h` map of `values` (row-major, top row first) followed by the legend panel to
    /// its right; maps smaller than 320 pixels are enlarged by pixel repetition so that the
    /// legend stays readable.
    pub fn image(&self, values: &[f32], w: usize, h: usize) -> image::RgbImage {
        assert_eq!(values.len(), w * h, "false-colour values do not fill the map");
        let k = (320usize.div_ceil(w.max(h).max(1))).max(1) as u32;
        let (mw, mh) = (w as u32 * k, h as u32 * k);
        let px = (mh as f32 / 24.0).clamp(12.0, 18.0);
        let panel = (11.0 * px).max(text_width(&self.title, px) + 1.2 * px).ceil() as u32;
        let total_h = mh.max(320);
        // a map lower than the legend is centred vertically beside it
        let y0 = (total_h - mh) / 2;
        let mut img = image::RgbImage::from_pixel(mw + panel, total_h, image::Rgb([255, 255, 255]));
        for y in 0..mh {
            for x in 0..mw {
                let v = values[(y / k) as usize * w + (x / k) as usize];
                img.put_pixel(x, y0 + y, image::Rgb(ramp(self.t(f64::from(v)))));
            }
        }
        let (bar_x, bar_w) = (mw + (1.2 * px) as u32, (1.2 * px) as u32);
        let (top, bottom) = ((2.4 * px) as u32, total_h - (1.2 * px) as u32);
        for y in top..bottom {
            let t = f64::from(bottom - 1 - y) / f64::from(bottom - 1 - top);
            for x in bar_x..bar_x + bar_w {
                img.put_pixel(x, y, image::Rgb(ramp(t)));
            }
        }
        draw_text(&mut img, mw as f32 + 0.6 * px, 1.0 * px, px, &self.title, [0, 0, 0], Align::Left);
        for v in self.ticks() {
            let y = bottom as f32 - 1.0 - self.t(v) as f32 * (bottom - 1 - top) as f32;
            for x in bar_x + bar_w..bar_x + bar_w + (0.4 * px) as u32 {
                img.put_pixel(x, y.round() as u32, image::Rgb([0, 0, 0]));
            }
            let label = tick_label(v);
            draw_text(&mut img, (bar_x + bar_w) as f32 + 0.6 * px, y, px, &label, [0, 0, 0], Align::Left);
        }
        img
    }
}

/// A tick value as short text: plain decimals from 0.001 to 99 999, otherwise `1e6` style.
pub fn tick_label(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (1e-3..1e5).contains(&a) {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        let e = a.log10().floor() as i32;
        let m = v / 10f64.powi(e);
        if (m.round() - m).abs() < 1e-9 { format!("{}e{e}", m.round()) } else { format!("{m:.1}e{e}") }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_ends_are_viridis_and_monotone_in_lightness() {
        assert_eq!(ramp(0.0), [68, 1, 84]);
        assert_eq!(ramp(1.0), [253, 231, 37]);
        assert_eq!(ramp(f64::NAN), ramp(0.0));
        let luma = |c: [u8; 3]| 0.2126 * f64::from(c[0]) + 0.7152 * f64::from(c[1]) + 0.0722 * f64::from(c[2]);
        for i in 0..100 {
            assert!(luma(ramp(f64::from(i + 1) / 100.0)) > luma(ramp(f64::from(i) / 100.0)));
        }
    }

    #[test]
    fn fitted_ranges_and_ticks() {
        let lin = FalseColour::fit(&[0.0, 120.0, 564.0, f32::NAN], ColourScale::Linear, "E (lx)");
        assert_eq!((lin.min, lin.max), (0.0, 1000.0));
        assert_eq!(lin.ticks(), vec![0.0, 200.0, 400.0, 600.0, 800.0, 1000.0]);
        let log = FalseColour::fit(&[3.0, 40.0, 2500.0], ColourScale::Log, "L (cd/m²)");
        assert_eq!((log.min, log.max), (1.0, 10000.0));
        assert_eq!(log.ticks(), vec![1.0, 10.0, 100.0, 1000.0, 10000.0]);
        assert!((log.t(100.0) - 0.5).abs() < 1e-12);
        assert_eq!(log.t(0.0), 0.0);
        assert_eq!(log.t(1e9), 1.0);
        let narrow = FalseColour { min: 1.0, max: 100.0, scale: ColourScale::Log, title: String::new() };
        assert_eq!(narrow.ticks(), vec![1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0]);
        assert!(FalseColour { min: 0.0, ..narrow.clone() }.validate().is_err());
        assert!(FalseColour { min: 5.0, max: 5.0, ..narrow }.validate().is_err());
    }

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(tick_label(0.0), "0");
        assert_eq!(tick_label(0.01), "0.01");
        assert_eq!(tick_label(1000.0), "1000");
        assert_eq!(tick_label(250.0), "250");
        assert_eq!(tick_label(1e6), "1e6");
        assert_eq!(tick_label(2.5e-5), "2.5e-5");
    }

    #[test]
    fn the_map_shows_the_values_and_the_legend_has_text() {
        let fc = FalseColour { min: 0.0, max: 10.0, scale: ColourScale::Linear, title: "E (lx)".into() };
        let img = fc.image(&[0.0, 10.0, 5.0, 20.0], 2, 2);
        assert_eq!(img.height(), 320);
        assert_eq!(img.get_pixel(10, 10).0, ramp(0.0));
        assert_eq!(img.get_pixel(170, 10).0, ramp(1.0));
        assert_eq!(img.get_pixel(10, 170).0, ramp(0.5));
        assert_eq!(img.get_pixel(170, 170).0, ramp(1.0), "above the range clamps to the top");
        let ink = img.enumerate_pixels().filter(|(x, _, p)| *x >= 320 && p.0.iter().all(|&c| c < 100)).count();
        assert!(ink > 200, "legend text and ticks: {ink} dark pixels");
    }
}
