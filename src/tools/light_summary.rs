//! The lights of a scene in a lighting engineer's units, for `quasar info`: every light's
//! photometric quantity (intensity in cd, illuminance in lx, luminance in cd/m²) and its
//! luminous flux in lm, from the radiometric description (docs/photometry.md: a quantity of
//! luminance Y is `LUMINANCE_PER_Y` = 683 lm/W x the integral of ybar times Y photometric units).

use std::f32::consts::PI;

use quasar_importers::photometric::LUMINANCE_PER_Y;
use quasar_importers::{LightDesc, LuminousOpening, SceneDesc};

use super::report_format::{num, vec3};

/// One line per light of `desc` (emissive meshes included), in scene order.
pub fn light_lines(desc: &SceneDesc) -> Vec<String> {
    let mut lines: Vec<String> = desc.lights.iter().map(light_line).collect();
    for m in &desc.meshes {
        let Some(e) = m.emission.as_ref().filter(|e| e.scale > 0.0) else { continue };
        let luminance = photometric(e.scale, &e.spectrum);
        let area = m.area() as f32;
        let sides = if e.two_sided { 2.0 } else { 1.0 };
        lines.push(format!(
            "emissive mesh {}: luminance {} cd/m², {} m², {} lm ({}, Lambertian)",
            m.name,
            num(luminance),
            num(area),
            num(sides * PI * luminance * area),
            if e.two_sided { "both faces" } else { "one face" }
        ));
    }
    lines
}

/// The photometric quantity of `scale` x `spectrum` (cd, lx or cd/m², as the radiometric one is
/// an intensity, irradiance or radiance): 683 lm/W x the integral of ybar times its luminance Y.
fn photometric(scale: f32, spectrum: &quasar_materials::spectrum::Spectrum) -> f32 {
    scale * spectrum.luminance() * LUMINANCE_PER_Y
}

/// The line of one light.
fn light_line(l: &LightDesc) -> String {
    match l {
        LightDesc::Point { position, spectrum, scale } => {
            let i = photometric(*scale, spectrum);
            format!("point light at {}: {} cd, {} lm", vec3(*position), num(i), num(4.0 * PI * i))
        }
        LightDesc::Spot { position, direction, cone_deg, falloff_start_deg, spectrum, scale } => {
            let i = photometric(*scale, spectrum);
            // full inside the falloff start, a smoothstep in cos theta (mean 1/2) out to the cone
            let (cs, cc) = (falloff_start_deg.to_radians().cos(), cone_deg.to_radians().cos());
            let flux = 2.0 * PI * i * (1.0 - 0.5 * (cs + cc));
            format!(
                "spot light at {} towards {}: {} cd on the axis, cone {}° (full to {}°), {} lm",
                vec3(*position),
                vec3(*direction),
                num(i),
                num(*cone_deg),
                num(*falloff_start_deg),
                num(flux)
            )
        }
        LightDesc::Directional { direction, spectrum, scale } => {
            let e = photometric(*scale, spectrum);
            format!("directional light towards {}: {} lx on a surface facing it", vec3(*direction), num(e))
        }
        LightDesc::Luminaire { position, frame, web, scale, spectrum, opening } => {
            let factor = photometric(*scale, spectrum);
            let stated = web.lamp_lumens.map_or("absolute photometry".to_string(), |l| format!("lamp {} lm", num(l)));
            format!(
                "luminaire: {} ({}) at {}, nadir towards {}: {} lm ({stated}), peak {} cd, x {}, {}",
                web.file.display(),
                if web.label.is_empty() { "no label" } else { &web.label },
                vec3(*position),
                vec3(glam::Vec3::ZERO - frame.z_axis),
                num(web.flux() as f32 * factor),
                num(web.max_candela() * factor),
                num(factor),
                match opening {
                    LuminousOpening::Point => "a point (far field)".to_string(),
                    LuminousOpening::Rect { c0, c90 } => format!("opening {} x {} m (C0 x C90)", num(*c0), num(*c90)),
                    LuminousOpening::Disk { diameter } => format!("opening a disk of {} m", num(*diameter)),
                }
            )
        }
        LightDesc::Environment { spectrum, scale, map } => match map {
            None => {
                let l = photometric(*scale, spectrum);
                format!(
                    "environment: {} cd/m² from every direction ({} lx on an open horizontal plane)",
                    num(l),
                    num(PI * l)
                )
            }
            Some(m) => format!("environment: lat-long map {}x{}, x {}", m.width, m.height, num(*scale)),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use quasar_materials::spectrum::Spectrum;

    /// Closed forms: a point light's flux is 4 pi I, a spot's with the cone of its falloff
    /// 2 pi I (1 - (cos a + cos b) / 2), a one-sided Lambertian square's pi L A.
    #[test]
    fn lights_in_photometric_units() {
        let white = Spectrum::Constant(1.0);
        let per = |q: f32| q / LUMINANCE_PER_Y;
        let mut desc = SceneDesc::default();
        desc.lights.push(LightDesc::Point { position: glam::Vec3::ZERO, spectrum: white.clone(), scale: per(100.0) });
        desc.lights.push(LightDesc::Spot {
            position: glam::Vec3::ZERO,
            direction: -glam::Vec3::Y,
            cone_deg: 60.0,
            falloff_start_deg: 60.0,
            spectrum: white.clone(),
            scale: per(100.0),
        });
        desc.lights.push(LightDesc::Directional {
            direction: -glam::Vec3::Y,
            spectrum: white.clone(),
            scale: per(5000.0),
        });
        desc.meshes.push(quasar_importers::MeshDesc {
            name: "panel".into(),
            positions: vec![glam::Vec3::ZERO, glam::Vec3::X, glam::Vec3::new(1.0, 0.0, 1.0), glam::Vec3::Z],
            indices: vec![[0, 1, 2], [0, 2, 3]],
            normals: None,
            uvs: None,
            colors: None,
            material: 0,
            emission: Some(quasar_importers::EmissionDesc {
                spectrum: white,
                scale: per(1000.0),
                two_sided: false,
                texture: None,
            }),
            source: Default::default(),
        });
        let lines = light_lines(&desc);
        assert!(lines[0].contains(": 100 cd, 1257 lm"), "{}", lines[0]);
        assert!(lines[1].contains("100 cd on the axis") && lines[1].ends_with(", 314.2 lm"), "{}", lines[1]);
        assert!(lines[2].contains("5000 lx"), "{}", lines[2]);
        assert!(lines[3].contains("1000 cd/m², 1 m², 3142 lm (one face"), "{}", lines[3]);
    }
}
