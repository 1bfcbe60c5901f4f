//! quasar's IES and EULUMDAT readers against an independent one: `lidrs` 0.2.3 (MIT), on the two
//! files it ships (`scenes/photometry/lidrs/`, see SOURCE.md there): the LM-63-2002 standard's
//! type C example with `TILT=INCLUDE`, and a measured EULUMDAT file of a real luminaire. lidrs
//! unfolds the files' symmetry into full planes of raw file values; quasar keeps the symmetry
//! and applies the multipliers: at every angle of every unfolded plane, quasar's intensity must be
//! lidrs's value times the file's multipliers (IES: candela multiplier x ballast factor;
//! EULUMDAT: lamp flux / 1000 x conversion factor).

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use lidrs::io::eulumdat::EulumdatFile;
use lidrs::io::ies::IesFile;
use lidrs::photweb::Plane;
use quasar_importers::photometry::{eulumdat, ies};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/photometry/lidrs").join(name)
}

/// Checks `web` against lidrs's unfolded `planes` times `scale` at every tabulated angle and
/// returns the number of values compared.
fn check_planes(web: &quasar_importers::photometry::PhotometricWeb, planes: &[Plane], scale: f64, what: &str) -> usize {
    let mut n = 0;
    for p in planes {
        let c = p.angle().to_degrees();
        assert_eq!(p.angles().len(), p.intensities().len(), "{what}");
        for (g, i) in p.angles().iter().zip(p.intensities()) {
            let ours = web.intensity_at(c as f32, g.to_degrees() as f32) as f64;
            let theirs = i * scale;
            assert!(
                (ours - theirs).abs() <= 1e-5 * theirs.abs().max(1.0),
                "{what}: C {c} gamma {}: quasar {ours} cd, lidrs {theirs} cd",
                g.to_degrees()
            );
            n += 1;
        }
    }
    n
}

/// The integral of lidrs's unfolded planes over the sphere (trapezoid rule in gamma, each plane
/// weighted by its share of the circle): an independent quadrature of the same table.
fn planes_flux(planes: &[Plane]) -> f64 {
    let cs: Vec<f64> = planes.iter().map(|p| p.angle()).collect();
    let mut sum = 0.0;
    for (k, p) in planes.iter().enumerate() {
        let prev = if k == 0 { cs[cs.len() - 1] - 2.0 * PI } else { cs[k - 1] };
        let next = if k + 1 == cs.len() { cs[0] + 2.0 * PI } else { cs[k + 1] };
        let width = if planes.len() == 1 { 2.0 * PI } else { 0.5 * (next - prev) };
        let (g, i) = (p.angles(), p.intensities());
        let mut plane = 0.0;
        for j in 1..g.len() {
            plane += 0.5 * (i[j - 1] * g[j - 1].sin() + i[j] * g[j].sin()) * (g[j] - g[j - 1]);
        }
        sum += plane * width;
    }
    sum
}

#[test]
fn the_lm63_2002_example_reads_as_lidrs_reads_it() {
    let path = fixture("iesna2002_example_typec.ies");
    let ours = ies::read_ies(&path).unwrap();
    let theirs = IesFile::parse_file(&path).unwrap();
    let web = &ours.web;
    // lidrs 0.2.3 keeps the IES header fields private: the file's own (line 22: 1 lamp of
    // 50000 lm, candela multiplier 1; line 23: ballast factor 1.0)
    assert_eq!(web.lamp_lumens, Some(50000.0));
    let scale = 1.0;
    assert_eq!(web.multiplier, 1.0);
    let planes = theirs.get_planes();
    // 0-90 unfolded into the full circle: 0, 45, ..., 315 (lidrs keeps 0 and 360 once)
    assert!(planes.len() >= 8, "{} planes", planes.len());
    let first = &planes[0];
    let gammas: Vec<f32> = first.angles().iter().map(|g| g.to_degrees() as f32).collect();
    assert!(gammas.iter().zip(&web.vertical_deg).all(|(a, b)| (a - b).abs() < 1e-4), "{gammas:?}");
    let n = check_planes(web, &planes, scale, "LM-63-2002 example");
    let tilt = ours.tilt.as_ref().expect("TILT=INCLUDE");
    assert_eq!(tilt.angles_deg.len(), 13);
    assert_eq!((tilt.factor(0.0), tilt.factor(90.0)), (1.0, 0.98));
    eprintln!("LM-63-2002 example: {n} candela values agree");
}

#[test]
fn a_measured_eulumdat_file_reads_as_lidrs_reads_it() {
    let path = fixture("example.ldt");
    let ours = eulumdat::read_ldt(&path).unwrap();
    let theirs = EulumdatFile::parse_file(&path).unwrap();
    let web = &ours.web;
    // lidrs 0.2.3 keeps the header fields private: the file's own (line 4: 20 C planes; line
    // 23: LORL 100%; line 24: conversion factor 1.0; line 29: one lamp set of 5134 lm)
    assert_eq!(web.lamp_lumens, Some(5134.0));
    assert_eq!(ours.light_output_ratio, 1.0);
    let scale = 5134.0 / 1000.0 * 1.0;
    assert!((web.multiplier as f64 - scale).abs() < 1e-6, "multiplier {}", web.multiplier);
    let planes = theirs.get_planes();
    assert_eq!(planes.len(), 20);
    let n = check_planes(web, &planes, scale, "EULUMDAT example");
    // the table's flux by quasar's quadrature (0.25 degree midpoint rule on the bilinear
    // interpolation) and by the trapezoid rule on lidrs's planes, and the file's luminaire lumens
    let (q, l) = (web.flux(), planes_flux(&planes) * scale);
    let stated = web.luminaire_lumens.unwrap() as f64;
    eprintln!(
        "EULUMDAT example: {n} values agree; flux {q:.1} lm (quasar), {l:.1} lm (lidrs planes), {stated} lm stated"
    );
    assert!((q - l).abs() < 0.005 * l, "flux {q} vs {l}");
    assert!((q - stated).abs() < 0.01 * stated, "flux {q} vs the file's {stated} lm");
}
