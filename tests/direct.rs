//! `direct` (the method added as one file plus one table row): its emission and direct layers are
//! `pt`'s in expectation — through the glass plate's specular chains too — and it has no
//! indirect light, which the z-test of its beauty against `pt`'s must notice.

mod common;

use common::{assert_converges, layer, pt_ov, render_file, shipped, z_test_from};
use quasar::film::Quantity;

#[test]
fn direct_is_the_emission_and_direct_layers_of_pt() {
    for (scene, w, h) in [("cornell-box/cornell-box.toml", 32, 32), ("glass-plate/glass-plate.toml", 40, 30)] {
        let path = shipped(scene);
        let reference = render_file(&path, &pt_ov(w, h, 256, 11));
        let mut ov = pt_ov(w, h, 256, 12);
        ov.method = Some("direct".into());
        let direct = render_file(&path, &ov);
        assert_eq!(direct.image.meta("method"), Some("direct"));
        assert_converges(&format!("direct on {scene}"), &direct, &reference, &[layer("emission"), layer("direct")]);
        for l in ["indirect", "caustic"] {
            let v = common::layer_luminance(&direct.image, l);
            assert!(v.iter().all(|&y| y == 0.0), "{scene}: direct writes no {l} light");
        }
        // the beauty lacks pt's indirect light: the z-test must see it
        let beauty = z_test_from(4, &format!("direct beauty on {scene}"), &direct, &reference, &[Quantity::Beauty]);
        assert!(beauty[0].failed(), "{scene}: the missing indirect light went unnoticed");
    }
}
