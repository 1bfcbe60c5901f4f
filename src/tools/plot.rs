//! A tiny raster canvas for the text-free PNG plots of `quasar bench convergence` and
//! `quasar bsdf --plot` (lines, dots, atomic PNG writes); legends are printed beside them.

use std::path::Path;

use anyhow::Result;

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

    /// Writes the canvas as PNG, atomically ([`crate::output::write_png_atomic`]).
    pub fn save(&self, path: &Path) -> Result<()> {
        Ok(crate::output::write_png_atomic(path, &self.img)?)
    }
}
