//! Numbers and points as the text reports (`quasar info`) print them: short, trimmed, with
//! the digits that matter.

/// A number with at most 4 significant digits after trimming (`0.5`, `480.4`, `1.5e-05`).
pub fn num(v: f32) -> String {
    if v == 0.0 || (1e-3..1e5).contains(&v.abs()) {
        let digits = (3 - v.abs().max(1e-3).log10().floor() as i32).clamp(0, 6) as usize;
        let t = format!("{v:.digits$}");
        if t.contains('.') { t.trim_end_matches('0').trim_end_matches('.').to_string() } else { t }
    } else {
        format!("{v:.3e}")
    }
}

/// A point as `(x, y, z)` with [`num`]'s digits.
pub fn vec3(v: glam::Vec3) -> String {
    format!("({}, {}, {})", num(v.x), num(v.y), num(v.z))
}
