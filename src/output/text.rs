//! Text in PNG figures (legends, axis labels): glyphs of the bundled Liberation Sans
//! (SIL OFL 1.1, `assets/fonts/`) rasterised by `ab_glyph` and blended by coverage,
//! pixel = (1 - c) pixel + c colour.

use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, PxScale, ScaleFont, point};

static FONT_BYTES: &[u8] = include_bytes!("../../assets/fonts/LiberationSans-Regular.ttf");

fn font() -> &'static FontRef<'static> {
    static FONT: OnceLock<FontRef<'static>> = OnceLock::new();
    FONT.get_or_init(|| FontRef::try_from_slice(FONT_BYTES).expect("the bundled font parses"))
}

/// Where a text's anchor point lies horizontally.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Align {
    /// The anchor is the text's left end.
    Left,
    /// The anchor is the text's middle.
    Centre,
    /// The anchor is the text's right end.
    Right,
}

/// Advance width of `text` at a font size of `px` pixels (kerning included).
pub fn text_width(text: &str, px: f32) -> f32 {
    let f = font().as_scaled(PxScale::from(px));
    let mut w = 0.0;
    let mut prev = None;
    for ch in text.chars() {
        let id = f.glyph_id(ch);
        if let Some(p) = prev {
            w += f.kern(p, id);
        }
        w += f.h_advance(id);
        prev = Some(id);
    }
    w
}

/// Draws one line of `text` at size `px` with its vertical middle (half the cap height above
/// the baseline) at `y` and its anchor at `x`; pixels outside the image are skipped.
pub fn draw_text(img: &mut image::RgbImage, x: f32, y: f32, px: f32, text: &str, colour: [u8; 3], align: Align) {
    let f = font().as_scaled(PxScale::from(px));
    let w = text_width(text, px);
    let mut pen = match align {
        Align::Left => x,
        Align::Centre => x - w / 2.0,
        Align::Right => x - w,
    };
    let baseline = y + 0.36 * px;
    let mut prev = None;
    for ch in text.chars() {
        let id = f.glyph_id(ch);
        if let Some(p) = prev {
            pen += f.kern(p, id);
        }
        let glyph = id.with_scale_and_position(PxScale::from(px), point(pen, baseline));
        pen += f.h_advance(id);
        prev = Some(id);
        let Some(outline) = font().outline_glyph(glyph) else { continue };
        let b = outline.px_bounds();
        outline.draw(|gx, gy, c| {
            let (px_x, px_y) = (b.min.x as i64 + i64::from(gx), b.min.y as i64 + i64::from(gy));
            if px_x < 0 || px_y < 0 || px_x >= i64::from(img.width()) || px_y >= i64::from(img.height()) {
                return;
            }
            let p = img.get_pixel_mut(px_x as u32, px_y as u32);
            let c = c.clamp(0.0, 1.0);
            for (dst, &src) in p.0.iter_mut().zip(colour.iter()) {
                *dst = (f32::from(*dst) * (1.0 - c) + f32::from(src) * c).round() as u8;
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_darkens_pixels_where_it_is_drawn_and_nowhere_else() {
        let mut img = image::RgbImage::from_pixel(120, 40, image::Rgb([255, 255, 255]));
        draw_text(&mut img, 10.0, 20.0, 16.0, "1000 lx", [0, 0, 0], Align::Left);
        let dark: Vec<(u32, u32)> =
            img.enumerate_pixels().filter(|(_, _, p)| p.0[0] < 128).map(|(x, y, _)| (x, y)).collect();
        assert!(dark.len() > 40, "{} dark pixels", dark.len());
        let w = text_width("1000 lx", 16.0);
        assert!(w > 40.0 && w < 70.0, "width {w}");
        for (x, y) in dark {
            assert!((9..=(11 + w as u32)).contains(&x) && (8..=32).contains(&y), "ink at ({x}, {y})");
        }
    }

    #[test]
    fn right_aligned_text_ends_at_the_anchor() {
        let mut img = image::RgbImage::from_pixel(100, 30, image::Rgb([255, 255, 255]));
        draw_text(&mut img, 80.0, 15.0, 14.0, "42", [0, 0, 0], Align::Right);
        let max_x = img.enumerate_pixels().filter(|(_, _, p)| p.0[0] < 200).map(|(x, _, _)| x).max().unwrap();
        assert!((74..=81).contains(&max_x), "last ink column {max_x}");
    }
}
