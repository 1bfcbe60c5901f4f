//! The test of the convergence test: the block z-test passes two independent renders of the
//! same scene and fails when 1% is added to one region of one of them.

mod common;

use common::{bidir_ov, pt_ov, render_file};
use quasar::film::Quantity;
use quasar::tools::ztest::{Estimate, ZTest};

/// `e` with the pixels of the `size` x `size` region at (`x0`, `y0`) made `factor` times brighter
/// (their samples scaled: the value by `factor`, its variance by `factor`^2).
fn biased(e: &Estimate, x0: usize, y0: usize, size: usize, factor: f64) -> Estimate {
    let mut b = e.clone();
    for y in y0..y0 + size {
        for x in x0..x0 + size {
            b.values[y * e.width + x] *= factor;
            b.pixel_var[y * e.width + x] *= factor * factor;
        }
    }
    for (&s, v) in b.block_var.iter_mut() {
        let cols = e.width.div_ceil(s);
        for (i, var) in v.iter_mut().enumerate() {
            let (bx, by) = (i % cols, i / cols);
            if bx * s >= x0 && (bx + 1) * s <= x0 + size && by * s >= y0 && (by + 1) * s <= y0 + size {
                *var *= factor * factor;
            }
        }
    }
    b
}

fn check(label: &str, image: &Estimate, reference: &Estimate) {
    let q = image.width / 2;
    let test = ZTest::default();
    let clean = test.run(image, reference).unwrap();
    eprintln!("{label}, unbiased: {clean}");
    assert!(!clean.failed(), "{label}: independent renders of one scene fail the z-test");
    // 1% in a quarter of the image (its top right block of half the image's side)
    let injected = test.run(&biased(image, q, 0, q, 1.01), reference).unwrap();
    eprintln!("{label}, 1% injected: {injected}");
    assert!(injected.failed(), "{label}: a 1% bias in a quarter of the image passes the z-test");
}

/// pt renders of the closed furnace (independent pixels: block errors from `stderr.Y`).
#[test]
fn the_z_test_catches_a_one_percent_regional_bias_in_pt() {
    let scene = common::furnace_scene(0.5, 1.0, 32);
    let e =
        |seed| Estimate::from_film(&render_file(&scene.path, &pt_ov(32, 32, 1024, seed)).result.film, Quantity::Beauty);
    check("furnace pt", &e(1), &e(2));
}

/// A bidirectional render (correlated pixels: block errors from the iterations' batch
/// statistics) against pt.
#[test]
fn the_z_test_catches_a_one_percent_regional_bias_in_vismap() {
    let scene = common::furnace_scene(0.5, 1.0, 16);
    let reference = render_file(&scene.path, &pt_ov(16, 16, 4096, 1));
    let img = render_file(&scene.path, &bidir_ov(16, 16, "vismap", 4096, 256, 2));
    let e = |o: &quasar::render::job::JobOutput| Estimate::from_film(&o.result.film, Quantity::Beauty);
    check("furnace vismap", &e(&img), &e(&reference));
}
