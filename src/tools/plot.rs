//! A small raster canvas for the PNG plots of `quasar bench convergence` and `quasar bsdf
//! --plot`: lines, dots, text (tick labels, axis titles) and a legend box, drawn with the
//! bundled font of [`crate::output::text`]; written atomically. The commands also print the
//! legend as text.

use std::path::Path;

use anyhow::Result;

use crate::output::text::{Align, draw_text, text_width};

/// Colours of successive curves, with the names printed in legends.
pub const PLOT_COLOURS: [(&str, [u8; 3]); 8] = [
    ("black", [0, 0, 0]),
    ("red", [220, 30, 30]),
    ("blue", [30, 60, 220]),
    ("green", [20, 150, 40]),
    ("orange", [240, 140, 0]),
    ("purple", [140, 40, 170]),
    ("cyan", [0, 170, 190]),
    ("brown", [130, 80, 30]),
];

/// A white RGB image to draw on, in pixel coordinates (y down).
pub struct Canvas {
    img: image::RgbImage,
}

impl Canvas {
    /// A white `w` x `h` canvas.
    pub fn new(w: u32, h: u32) -> Self {
        Self { img: image::RgbImage::from_pixel(w, h, image::Rgb([255, 255, 255])) }
    }

    /// Sets one pixel (ignored outside the canvas).
    pub fn dot(&mut self, x: f64, y: f64, c: [u8; 3]) {
        if x >= 0.0 && y >= 0.0 && (x as u32) < self.img.width() && (y as u32) < self.img.height() {
            self.img.put_pixel(x as u32, y as u32, image::Rgb(c));
        }
    }

    /// A 5 x 5 square centred on (x, y).
    pub fn marker(&mut self, x: f64, y: f64, c: [u8; 3]) {
        for dy in -2..=2 {
            for dx in -2..=2 {
                self.dot(x + f64::from(dx), y + f64::from(dy), c);
            }
        }
    }

    /// A one-pixel line from `a` to `b` (one dot per pixel step).
    pub fn line(&mut self, a: (f64, f64), b: (f64, f64), c: [u8; 3]) {
        let n = ((b.0 - a.0).abs().max((b.1 - a.1).abs()) as usize).max(1);
        for i in 0..=n {
            let t = i as f64 / n as f64;
            self.dot(a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1), c);
        }
    }

    /// One line of text at size `px`, its vertical middle at `y`, anchored at `x` by `align`.
    pub fn text(&mut self, x: f64, y: f64, px: f32, text: &str, c: [u8; 3], align: Align) {
        draw_text(&mut self.img, x as f32, y as f32, px, text, c, align);
    }

    /// A legend box whose top-right corner is (`right`, `top`): per entry a short line in its
    /// colour and its label, at size `px`, on white with a grey frame.
    pub fn legend(&mut self, right: f64, top: f64, px: f32, entries: &[(String, [u8; 3])]) {
        let px64 = f64::from(px);
        let (row, swatch, pad) = (1.5 * px64, 2.0 * px64, 0.6 * px64);
        let label_w = entries.iter().map(|(l, _)| f64::from(text_width(l, px))).fold(0.0, f64::max);
        let (w, h) = (pad * 3.0 + swatch + label_w, pad * 2.0 + row * entries.len() as f64);
        let left = right - w;
        for y in top as i64..=(top + h) as i64 {
            for x in left as i64..=right as i64 {
                let edge = y == top as i64 || y == (top + h) as i64 || x == left as i64 || x == right as i64;
                self.dot(x as f64, y as f64, if edge { [160, 160, 160] } else { [255, 255, 255] });
            }
        }
        for (i, (label, c)) in entries.iter().enumerate() {
            let y = top + pad + row * (i as f64 + 0.5);
            for dy in [-1.0, 0.0, 1.0] {
                self.line((left + pad, y + dy), (left + pad + swatch, y + dy), *c);
            }
            self.text(left + 2.0 * pad + swatch, y, px, label, [0, 0, 0], Align::Left);
        }
    }

    /// Writes the canvas as PNG, atomically ([`crate::output::write_png_atomic`]).
    pub fn save(&self, path: &Path) -> Result<()> {
        Ok(crate::output::write_png_atomic(path, &self.img)?)
    }
}
