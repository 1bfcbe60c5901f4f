//! Tone-mapped 8-bit sRGB PNG previews of the beauty channels.

use std::path::Path;

/// sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1].
fn srgb_encode(v: f32) -> f32 {
    if v <= 0.003_130_8 { 12.92 * v } else { 1.055 * v.powf(1.0 / 2.4) - 0.055 }
}

/// Writes linear sRGB `r, g, b` (row-major) as a PNG: exposure scaling by 2^`exposure`, clipping
/// to [0, 1] and the sRGB transfer curve (Blender's "Standard" view transform). Non-finite values
/// become 0. Atomic like the EXR writer.
pub fn write_preview_png(path: &Path, width: u32, height: u32, rgb: [&[f32]; 3], exposure: f32) -> Result<(), String> {
    let scale = 2f32.powf(exposure);
    let mut buf = Vec::with_capacity(width as usize * height as usize * 3);
    for i in 0..(width as usize * height as usize) {
        for c in rgb {
            let v = c[i] * scale;
            let v = if v.is_finite() { v.clamp(0.0, 1.0) } else { 0.0 };
            buf.push((srgb_encode(v) * 255.0 + 0.5) as u8);
        }
    }
    let img = image::RgbImage::from_raw(width, height, buf).ok_or("preview buffer size mismatch")?;
    super::write_png_atomic(path, &img).map_err(|e| e.to_string())
}
