//! The render kernels compiled for x86-64-v3 compute the portable build's image bit for bit
//! (src/core/isa.rs): shipped scenes with narrow, rough, tabulated and diffuse BSDFs, with the
//! per-pixel methods and the bidirectional ones.

mod common;

use common::{bidir_ov, pt_ov, render_file, shipped};
use quasar::core::isa::Isa;
use quasar::output::ExrImage;
use quasar::render::job::JobOverrides;

#[test]
fn x86_64_v3_kernels_give_the_baseline_image_bit_for_bit_with_every_kind_of_method() {
    if !Isa::X86_64V3.available() {
        eprintln!("skipped: this CPU lacks x86-64-v3, so only the baseline kernels can run here");
        return;
    }
    let scenes = [
        "glass-plate/glass-plate.toml",
        "glossy-room/glossy-room.toml",
        "lightguide/lightguide.toml",
        "cornell-box/cornell-box.toml",
    ];
    for scene in scenes {
        for method in ["pt", "direct", "vismap", "adaptive+quasi"] {
            let render = |isa| {
                let ov = match method {
                    "pt" | "direct" => JobOverrides { method: Some(method.into()), ..pt_ov(40, 30, 4, 7) },
                    _ => bidir_ov(40, 30, method, 3, 4000, 7),
                };
                render_file(&shipped(scene), &JobOverrides { isa: Some(isa), ..ov }).image
            };
            let (base, v3) = (render(Isa::Baseline), render(Isa::X86_64V3));
            let isa_of = |img: &ExrImage| {
                img.metadata.iter().find(|(k, _)| k == "isa").map(|(_, v)| v.clone()).unwrap_or_default()
            };
            assert_eq!((isa_of(&base).as_str(), isa_of(&v3).as_str()), ("baseline", "x86-64-v3"));
            assert_eq!(base.channels.len(), v3.channels.len());
            for (a, b) in base.channels.iter().zip(&v3.channels) {
                assert_eq!(a.name, b.name);
                let differing = a.values.iter().zip(&b.values).filter(|(x, y)| x.to_bits() != y.to_bits()).count();
                assert_eq!(differing, 0, "{scene} {method}: {} differs in {differing} pixels", a.name);
            }
            let sum: f64 = base.channels[0].values.iter().map(|&v| v as f64).sum();
            assert!(sum > 0.0, "{scene} {method}: a black image compares equal trivially");
        }
    }
}
