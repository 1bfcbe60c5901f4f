//! The `quasar` command line: renders write an EXR; bad input gives an error naming file and
//! line, a non-zero exit code, and leaves no output file behind (nor touches an existing one).

mod common;

use std::path::Path;
use std::process::Command;

use common::write_scene;

fn quasar() -> Command {
    Command::new(env!("CARGO_BIN_EXE_quasar"))
}

const GOOD: &str = r#"
[render]
width = 8
height = 6
spp = 2
[camera]
position = [0, 0, 3]
target = [0, 0, 0]
fov_deg = 40
[materials.grey]
type = "diffuse"
reflectance = 0.5
[[shape]]
type = "sphere"
center = [0, 0, 0]
radius = 1
material = "grey"
[[light]]
type = "environment"
spectrum = { illuminant = "D65" }
scale = 1
"#;

#[test]
fn render_writes_an_exr() {
    let s = write_scene(GOOD, &[]);
    let out = s.dir.path().join("good.exr");
    let st = quasar().args(["render", "--quiet", "--seed", "1"]).arg(&s.path).arg("-o").arg(&out).status().unwrap();
    assert!(st.success());
    let img = quasar::output::read_exr(&out).unwrap();
    assert_eq!((img.width, img.height), (8, 6));
}

fn expect_failure(scene: &common::TempScene, needle: &str) {
    expect_failure_with(scene, &[needle]);
}

/// A render of `scene` fails with every one of `needles` in its message, writing nothing.
fn expect_failure_with(scene: &common::TempScene, needles: &[&str]) {
    let out = scene.dir.path().join("out.exr");
    let o = quasar().args(["render", "--quiet"]).arg(&scene.path).arg("-o").arg(&out).output().unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "expected failure, stderr: {stderr}");
    for needle in needles {
        assert!(stderr.contains(needle), "stderr should contain {needle:?}: {stderr}");
    }
    assert!(!out.exists(), "no output may be written on failure");
    // an existing output is left untouched
    std::fs::write(&out, b"previous").unwrap();
    let o = quasar().args(["render", "--quiet"]).arg(&scene.path).arg("-o").arg(&out).output().unwrap();
    assert!(!o.status.success());
    assert_eq!(std::fs::read(&out).unwrap(), b"previous");
}

#[test]
fn malformed_toml_names_file_and_line() {
    let bad = GOOD.replace("radius = 1\n", "radius = = 1\n");
    let line = bad.lines().position(|l| l.contains("radius = = 1")).unwrap() + 1;
    let s = write_scene(&bad, &[]);
    expect_failure(&s, &format!("scene.toml:{line}"));
}

#[test]
fn unknown_key_names_file_and_line() {
    let bad = GOOD.replace("radius = 1\n", "radius = 1\nradiuss = 2\n");
    let line = bad.lines().position(|l| l.starts_with("radiuss")).unwrap() + 1;
    let s = write_scene(&bad, &[]);
    expect_failure(&s, &format!("scene.toml:{line}"));
}

/// The `[render]` table's method and method parameters are validated by the method table when
/// the render starts: errors name the file and line; a command-line flag the method does not
/// read is refused, naming the methods it applies to.
#[test]
fn render_table_errors_name_file_and_line() {
    let cases = [
        ("method = \"path\"", "method =", "unknown method 'path'"),
        ("method = \"quasi\"\ncone_deg = 120", "cone_deg", "cone_deg"),
        ("method = \"vismap\"\nphotons_per_iteration = 0", "photons_per_iteration", "photons_per_iteration"),
        ("method = \"quasi\"\nradius = -1", "radius", "positive length"),
        ("conedeg = 10", "conedeg", "did you mean `cone_deg`?"),
    ];
    for (keys, line_needle, needle) in cases {
        let bad = GOOD.replace("spp = 2\n", &format!("spp = 2\n{keys}\n"));
        let line = bad.lines().position(|l| l.starts_with(line_needle)).unwrap() + 1;
        let s = write_scene(&bad, &[]);
        expect_failure_with(&s, &[&format!("scene.toml:{line}"), needle]);
    }
    // a scene-file key another method reads is not an error (a scene for `quasi` renders with
    // `pt`); the same key as a flag is
    let s = write_scene(&GOOD.replace("spp = 2\n", "spp = 2\ncone_deg = 10\n"), &[]);
    let out = s.dir.path().join("pt.exr");
    let st = quasar().args(["render", "--quiet", "--method", "pt"]).arg(&s.path).arg("-o").arg(&out).status().unwrap();
    assert!(st.success());
    let o = quasar().args(["render", "--quiet", "--method", "pt", "--cone", "10"]).arg(&s.path).output().unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && stderr.contains("does not apply to pt") && stderr.contains("quasi"), "{stderr}");
}

#[test]
fn malformed_obj_names_file_and_line() {
    let scene =
        GOOD.replace("type = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n", "type = \"mesh\"\nfile = \"tri.obj\"\n");
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 zero\nf 1 2 3\n";
    let s = write_scene(&scene, &[("tri.obj", obj)]);
    expect_failure(&s, "tri.obj:3");
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n";
    let s = write_scene(&scene, &[("tri.obj", obj)]);
    expect_failure(&s, "tri.obj:4");
}

#[test]
fn missing_scene_file_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nope.toml");
    let o = quasar().args(["render", "--quiet"]).arg(&missing).output().unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("nope.toml"));
}

/// SIGINT during a render stops it and writes a valid EXR of what was done, marked partial,
/// with exit code 3 (not 0: scripts retry); the same for a bidirectional method (after the
/// current iteration).
#[test]
fn interrupted_render_writes_a_valid_partial_exr() {
    let s = write_scene(GOOD, &[]);
    for method in ["pt", "vismap"] {
        let out = s.dir.path().join(format!("partial-{method}.exr"));
        let mut child = quasar()
            .args(["render", "--quiet", "--width", "64", "--height", "48", "--method", method, "--spp", "1000000"])
            .arg(&s.path)
            .arg("-o")
            .arg(&out)
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(1500));
        // SAFETY: plain kill(2) on our own child process
        let rc = unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGINT) };
        assert_eq!(rc, 0);
        let status = child.wait().unwrap();
        assert_eq!(status.code(), Some(3), "{method}: exit {status:?}");
        let img = quasar::output::read_exr(&out).unwrap();
        assert_eq!(img.meta("partial"), Some("true"), "{method}");
        let spp: u32 = img.meta("spp").unwrap().parse().unwrap();
        assert!(spp < 1_000_000, "{method}: {spp}");
        assert!(img.channels.iter().filter(|c| c.name != "depth.Z").all(|c| c.values.iter().all(|v| v.is_finite())));
        assert!(img.channel("spp.Y").unwrap().iter().all(|&n| n >= spp as f32));
    }
}

/// `--shard K/N` on the command line and `quasar merge` give one EXR with the full sample count;
/// merging onto an input and rendering onto the scene file are refused.
#[test]
fn shard_and_merge_commands() {
    let s = write_scene(GOOD, &[]);
    let shard = |k: u32| {
        let out = s.dir.path().join(format!("s{k}.exr"));
        let st = quasar()
            .args(["render", "--quiet", "--spp", "6", "--shard", &format!("{k}/3")])
            .arg(&s.path)
            .arg("-o")
            .arg(&out)
            .status()
            .unwrap();
        assert!(st.success());
        out
    };
    let parts: Vec<_> = (0..3).map(shard).collect();
    let merged = s.dir.path().join("merged.exr");
    let st = quasar().arg("merge").args(&parts).arg("-o").arg(&merged).status().unwrap();
    assert!(st.success());
    let img = quasar::output::read_exr(&merged).unwrap();
    assert_eq!(img.meta("spp"), Some("6"));
    assert!(img.channel("spp.Y").unwrap().iter().all(|&n| n == 6.0));
    let o = quasar().arg("merge").args(&parts).arg("-o").arg(&parts[0]).output().unwrap();
    assert!(!o.status.success());
    let o = quasar().args(["render", "--quiet", "--shard", "3/3"]).arg(&s.path).output().unwrap();
    assert!(!o.status.success());
    let o = quasar().args(["render", "--quiet"]).arg(&s.path).arg("-o").arg(&s.path).output().unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("overwrite the scene"));
    assert!(std::fs::read_to_string(&s.path).unwrap().contains("[render]"));
}

#[test]
fn bsdf_command_reports_plots_converts_and_refuses() {
    let lib = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("materials/library");
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("lobe.png");
    let out = quasar().arg("bsdf").arg(lib.join("glass-plate-top.toml")).arg("--plot").arg(&png).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    for needle in
        ["directional albedo, front face", "directional albedo, back face", "kappa", "energy: max albedo", "OK"]
    {
        assert!(text.contains(needle), "report lacks {needle:?}:\n{text}");
    }
    let img = image::open(&png).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (720, 720));
    assert!(img.pixels().any(|p| p.0 == [220, 30, 30]), "the 30 degree curve is drawn");
    // drawn text: the title (top left) and the legend box (top right, outside the rim circle)
    let dark = |x0: u32, x1: u32, y0: u32, y1: u32| {
        (y0..y1).flat_map(|y| (x0..x1).map(move |x| (x, y))).filter(|&(x, y)| img.get_pixel(x, y).0[0] < 100).count()
    };
    assert!(dark(0, 250, 0, 22) > 60, "the plot's title");
    assert!(dark(610, 715, 6, 90) > 60, "the legend's labels");

    // A table that scatters more than it receives: the report shows it and the exit code fails.
    let hot = dir.path().join("hot.toml");
    std::fs::write(
        &hot,
        "format = \"quasar-bsdf\"\nunits = \"1/sr\"\nwavelengths_nm = [550]\n[incidence]\ntheta_deg = [0]\n\
         [front.brdf]\ngrid = \"absolute\"\ntheta_deg = [0, 90]\nvalues = [1, 1]\n",
    )
    .unwrap();
    let out = quasar().arg("bsdf").arg(&hot).output().unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stdout).contains("FAILS"));
    assert!(String::from_utf8_lossy(&out.stderr).contains("energy check"));

    // Conversion of a Zemax file, then the report on the result.
    let zemax = dir.path().join("film.bsdf");
    let mut z =
        String::from("Source Measured\nSymmetry PlaneSymmetrical\nSpectralContent Monochrome\nScatterType BTDF\n");
    z += "SampleRotation 1\n0\nAngleOfIncidence 2\n0 40\nScatterAzimuth 3\n0 90 180\nScatterRadial 3\n0 10 30\n";
    z += "Monochrome\nDataBegin\nTIS 0.5\n0.9 0.5 0.05\n0.9 0.5 0.05\n0.9 0.5 0.05\nTIS 0.5\n0.8 0.4 0.04\n0.8 0.4 0.04\n0.8 0.4 0.04\nDataEnd\n";
    std::fs::write(&zemax, z).unwrap();
    let toml = dir.path().join("film.toml");
    let st = quasar().args(["bsdf", "convert"]).arg(&zemax).arg("-o").arg(&toml).status().unwrap();
    assert!(st.success());
    let text = std::fs::read_to_string(&toml).unwrap();
    assert!(text.contains("[front.btdf]") && text.contains("grid = \"specular\"") && text.contains("converted_from"));
    let out = quasar().arg("bsdf").arg(&toml).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // A broken .bsdf file: error naming it, nothing written.
    std::fs::write(&zemax, "Source Measured\nSymmetry Round\n").unwrap();
    let bad = dir.path().join("bad.toml");
    let out = quasar().args(["bsdf", "convert"]).arg(&zemax).arg("-o").arg(&bad).output().unwrap();
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("film.bsdf:"));
    assert!(!bad.exists());
}

/// A glTF with one lit triangle whose buffer is `uri` (returned with the buffer bytes), using an
/// extension quasar does not support (a warning).
fn gltf_with_buffer(uri: &str) -> (String, Vec<u8>) {
    use quasar_importers::gltf::writer::{BinStorage, GltfWriter, Prim};
    let mut w = GltfWriter::new();
    w.use_extension("KHR_lights_punctual", false);
    w.use_extension("KHR_materials_iridescence", false);
    let position = w.positions(&[[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]]);
    let m = w.mesh("tri", &[Prim { position, ..Default::default() }]);
    GltfWriter::push(&mut w.lights, r#"{"type":"point","intensity":1000}"#);
    let a = GltfWriter::push(&mut w.nodes, &format!(r#"{{"mesh":{m}}}"#));
    let b =
        GltfWriter::push(&mut w.nodes, r#"{"translation":[0,0,2],"extensions":{"KHR_lights_punctual":{"light":0}}}"#);
    w.roots.extend([a, b]);
    w.to_gltf(&BinStorage::External(uri.into()))
}

#[test]
fn gltf_paths_outside_the_folder_need_the_flag_and_warnings_are_printed() {
    let dir = tempfile::tempdir().unwrap();
    let (json, bin) = gltf_with_buffer("../data.bin");
    std::fs::create_dir(dir.path().join("model")).unwrap();
    std::fs::write(dir.path().join("data.bin"), bin).unwrap();
    let scene = dir.path().join("model/m.gltf");
    std::fs::write(&scene, json).unwrap();
    let out = dir.path().join("m.exr");
    let args = ["render", "--quiet", "--width", "8", "--height", "6", "--spp", "1", "--method", "pt"];
    let o = quasar().args(args).arg(&scene).arg("-o").arg(&out).output().unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{stderr}");
    assert!(stderr.contains("m.gltf: /buffers/0/uri: URI `../data.bin` leaves the glTF file's folder"), "{stderr}");
    assert!(!out.exists());
    let o = quasar().args(args).arg("--allow-external-paths").arg(&scene).arg("-o").arg(&out).output().unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    assert!(stderr.contains("warning: ") && stderr.contains("KHR_materials_iridescence"), "{stderr}");
    assert!(quasar::output::read_exr(&out).unwrap().channel(quasar::film::LUMINANCE).unwrap().iter().any(|&y| y > 0.0));
    // --units scales the scene: info reports the bounding sphere in metres
    let info = |units: &str| {
        let o = quasar().args(["info", "--allow-external-paths", "--units", units]).arg(&scene).output().unwrap();
        assert!(o.status.success());
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let radius = |text: String| -> f64 {
        let r = text.split("radius ").nth(1).and_then(|t| t.split_whitespace().next()).unwrap();
        r.parse().unwrap()
    };
    let (m, mm) = (radius(info("m")), radius(info("mm")));
    assert!((m - 2f64.sqrt()).abs() < 1e-5, "{m}");
    assert!((mm / m - 1e-3).abs() < 1e-8, "{mm}");
    let o = quasar().args(["info", "--units", "furlong"]).arg(&scene).output().unwrap();
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("expected m, cm, mm"));
}

/// `quasar render --quiet SCENE -o OUT ARGS...`: its exit status and standard error.
fn render_cli<S: AsRef<std::ffi::OsStr>>(
    scene: &Path,
    out: &Path,
    args: impl IntoIterator<Item = S>,
) -> (std::process::ExitStatus, String) {
    let o = quasar().args(["render", "--quiet"]).arg(scene).arg("-o").arg(out).args(args).output().unwrap();
    (o.status, String::from_utf8_lossy(&o.stderr).into_owned())
}

/// Out-of-range numbers on the command line are refused before anything is rendered, with the
/// accepted range (issue 18): `--spp 0` rendered one sample, `--exposure nan` a black preview,
/// `--threads 100000` aborted on the stack guard page.
#[test]
fn bad_numbers_on_the_command_line_are_refused() {
    let s = write_scene(GOOD, &[]);
    let out = s.dir.path().join("out.exr");
    for (args, needle) in [
        (&["--spp", "0"][..], "--spp"),
        (&["--exposure", "nan"][..], "finite"),
        (&["--time", "0"][..], "positive"),
        (&["--target-error", "0"][..], "positive"),
        (&["--threads", "100000"][..], "per core"),
        (&["--isa", "avx9"][..], "x86-64-v3"),
    ] {
        let (status, stderr) = render_cli(&s.path, &out, args);
        assert_eq!(status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
        assert!(!out.exists(), "{args:?} wrote an image");
    }
    // 0 threads means all cores
    let (status, stderr) = render_cli(&s.path, &out, ["--threads", "0"]);
    assert!(status.success(), "{stderr}");
}

/// `--isa baseline` runs the portable kernels and says so in the header; `auto` runs the best
/// the CPU has.
#[test]
fn the_instruction_set_of_the_kernels_is_chosen_on_the_command_line_and_recorded() {
    let s = write_scene(GOOD, &[]);
    let out = s.dir.path().join("out.exr");
    for (arg, want) in [("baseline", "baseline"), ("auto", quasar::core::isa::Isa::best().name())] {
        let (status, stderr) = render_cli(&s.path, &out, ["--isa", arg]);
        assert!(status.success(), "{stderr}");
        let img = quasar::output::read_exr(&out).unwrap();
        assert!(img.metadata.iter().any(|(k, v)| k == "isa" && v == want), "--isa {arg}: {:?}", img.metadata);
    }
}

/// Spectral bins outside the sampled range, too many or none, and a range without bins, are
/// refused before anything is rendered, naming the accepted values.
#[test]
fn bad_spectral_bins_are_refused() {
    let s = write_scene(GOOD, &[]);
    let out = s.dir.path().join("out.exr");
    for (args, code, needle) in [
        (&["--spectral-bins", "4", "--spectral-range", "300:700"][..], 1, "inside the sampled range 360:830 nm"),
        (&["--spectral-bins", "0"][..], 1, "give 1 to 940"),
        (&["--spectral-bins", "4", "--spectral-range", "700:400"][..], 2, "MIN < MAX"),
        (&["--spectral-range", "400:700"][..], 2, "--spectral-bins"),
    ] {
        let (status, stderr) = render_cli(&s.path, &out, args);
        assert_eq!(status.code(), Some(code), "{args:?}: {stderr}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
        assert!(!out.exists(), "{args:?} wrote an image");
    }
}

/// An image larger than the machine's memory is refused before anything large is allocated, with
/// the estimate and the memory available (issue 18: 16384 x 16384 aborted on a 32 GB
/// allocation). 65536 x 4096 with `vismap` needs about 700 GiB, more than any CI machine has.
#[test]
fn renders_too_large_for_the_memory_are_refused_with_the_figure() {
    let s = write_scene(GOOD, &[]);
    let out = s.dir.path().join("huge.exr");
    let (status, stderr) =
        render_cli(&s.path, &out, ["--method", "vismap", "--width", "65536", "--height", "4096", "--spp", "1"]);
    assert_eq!(status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("65536x4096") && stderr.contains("GiB of memory") && stderr.contains("available"),
        "{stderr}"
    );
    assert!(!out.exists());
}

/// A reader that goes away (`quasar info scene.toml | head -1`) ends `quasar` by SIGPIPE, as it
/// does `cat`, not by a panic (exit 101) (issue 18).
#[cfg(unix)]
#[test]
fn a_closed_pipe_is_not_a_panic() {
    use std::os::unix::process::ExitStatusExt;
    use std::process::Stdio;
    let s = write_scene(GOOD, &[]);
    let mut child = quasar().arg("info").arg(&s.path).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    drop(child.stdout.take()); // the only reader closes before anything is written
    let o = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(o.status.signal(), Some(libc::SIGPIPE), "{:?} {stderr}", o.status);
}

/// An output into a directory that does not exist is refused before the render, naming the
/// directory (it failed after the render, naming an internal temporary file), for the EXR and
/// for the preview (which failed after the EXR had been written).
#[test]
fn missing_output_directories_are_refused_before_rendering() {
    let s = write_scene(GOOD, &[]);
    let missing = s.dir.path().join("no-such-dir");
    let exr = s.dir.path().join("out.exr");
    for (out, preview) in [(missing.join("a.exr"), None), (exr.clone(), Some(missing.join("a.png")))] {
        let preview_args = preview.iter().flat_map(|p| [std::ffi::OsStr::new("--preview"), p.as_os_str()]);
        let (status, stderr) = render_cli(&s.path, &out, preview_args);
        assert!(!status.success(), "{stderr}");
        assert!(stderr.contains("no-such-dir") && stderr.contains("does not exist"), "{stderr}");
        assert!(!out.exists() && !exr.exists(), "nothing may be written");
    }
    // --preview onto the scene names the preview
    let (status, stderr) = render_cli(&s.path, &exr, [std::ffi::OsStr::new("--preview"), s.path.as_os_str()]);
    assert!(
        !status.success() && stderr.contains(&format!("{}: the output would overwrite", s.path.display())),
        "{stderr}"
    );
}

/// What an output path names is checked before the render (issue 52): `-o /dev/null` is
/// written through and stays a device (the landed writer renamed a regular file over it), an
/// image path with another extension than the format written is refused (`-o x.png` wrote EXR
/// bytes, `--preview x.jpg` a PNG), and so is a folder (it failed only after the render).
#[test]
fn outputs_are_checked_for_kind_and_extension_before_rendering() {
    let s = write_scene(GOOD, &[]);
    let exr = s.dir.path().join("out.exr");
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let is_device = || std::fs::symlink_metadata("/dev/null").is_ok_and(|m| m.file_type().is_char_device());
        if is_device() {
            let (status, stderr) = render_cli(&s.path, Path::new("/dev/null"), ["--seed", "1"]);
            assert!(status.success(), "{stderr}");
            assert!(is_device(), "/dev/null must stay a device");
        }
    }
    let png = s.dir.path().join("out.png");
    let (status, stderr) = render_cli(&s.path, &png, ["--seed", "1"]);
    assert!(!status.success() && stderr.contains("give it a .exr path"), "{stderr}");
    assert!(!png.exists());
    let jpg = s.dir.path().join("out.jpg");
    let (status, stderr) = render_cli(&s.path, &exr, [std::ffi::OsStr::new("--preview"), jpg.as_os_str()]);
    assert!(!status.success() && stderr.contains("give it a .png path"), "{stderr}");
    assert!(!jpg.exists() && !exr.exists());
    let folder = s.dir.path().join("folder.exr");
    std::fs::create_dir(&folder).unwrap();
    let (status, stderr) = render_cli(&s.path, &folder, ["--spp", "100000000"]);
    assert!(!status.success() && stderr.contains("is a folder"), "{stderr}");
    // upper-case extensions are the same format
    let upper = s.dir.path().join("OUT.EXR");
    let (status, stderr) = render_cli(&s.path, &upper, ["--seed", "1"]);
    assert!(status.success() && upper.exists(), "{stderr}");
}

/// The command line's frictions of issue 52: `--method foo` is a command-line error (exit 2,
/// as every other bad argument; it was 1), `--camera NAME` picks a file's camera by name (and
/// an unknown name lists the cameras), and `render --help` names every format of the importer
/// table (it omitted USD) and shows the common options before the rare ones.
#[test]
fn method_camera_and_help_on_the_command_line() {
    let s = write_scene(GOOD, &[]);
    let out = s.dir.path().join("out.exr");
    let (status, stderr) = render_cli(&s.path, &out, ["--method", "foo"]);
    assert_eq!(status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("unknown method `foo`") && stderr.contains("adaptive+quasi"), "{stderr}");
    let (status, stderr) = render_cli(&s.path, &out, ["--camera", "Side"]);
    assert!(!status.success() && stderr.contains("no camera named `Side`"), "{stderr}");
    assert!(!out.exists());
    let gltf = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/gltf-showcase/showcase.gltf");
    let (status, stderr) = render_cli(&gltf, &out, ["--camera", "Top", "--spp", "1", "--width", "8", "--height", "6"]);
    assert!(status.success(), "{stderr}");
    let o = quasar().args(["render", "--help"]).output().unwrap();
    let help = String::from_utf8_lossy(&o.stdout);
    for ext in quasar_importers::supported_extensions() {
        assert!(help.contains(&format!(".{ext}")), "render --help omits .{ext}: {help}");
    }
    let at = |flag: &str| help.find(flag).unwrap_or_else(|| panic!("{flag} missing"));
    assert!(at("--output") < at("--units") && at("--spp") < at("--allow-external-paths"), "{help}");
}

/// Without a terminal (a log file, a batch job) a render prints plain progress lines with the
/// unit of the work done (issue 52: nothing was shown, and the bar said "N done").
#[test]
fn progress_lines_in_logs() {
    let s = write_scene(GOOD, &[]);
    let out = s.dir.path().join("out.exr");
    for (method, unit) in [("pt", "samples per pixel done"), ("vismap", "iterations done")] {
        let o = quasar()
            .args(["render", "--method", method, "--spp", "4"])
            .arg(&s.path)
            .arg("-o")
            .arg(&out)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{stderr}");
        let line = stderr.lines().find(|l| l.starts_with("progress: ")).unwrap_or_else(|| panic!("{stderr}"));
        assert!(line.contains(unit) && line.contains("% after"), "{line}");
    }
}

/// `quasar info` states every light's intensity or flux (issue 52: it listed only the types).
#[test]
fn info_shows_the_lights_in_photometric_units() {
    let gltf = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/gltf-showcase/showcase.gltf");
    let o = quasar().arg("info").arg(&gltf).output().unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for needle in
        ["point light at", " cd, ", "spot light at", "directional light towards", " lx ", "emissive mesh", " lm ("]
    {
        assert!(text.contains(needle), "{needle:?} missing: {text}");
    }
    // a USD stage: bounds in metres, the prims drawn and skipped, the time code (issue 51)
    let usd = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/usd/cornell-box.usda");
    let o = quasar().arg("info").arg(&usd).output().unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    for needle in ["bounds: ", " m (size ", "USD prims: ", "USD prims skipped", "USD time code: "] {
        assert!(text.contains(needle), "{needle:?} missing: {text}");
    }
}

/// `--spectral-bins` writes its bins into `<stem>.spectral.exr`; the image keeps the standard
/// layers (issue 52: with 47 bins in one `S0` layer Blender refused the whole file).
#[test]
fn spectral_bins_go_to_a_file_of_their_own() {
    let s = write_scene(GOOD, &[]);
    let out = s.dir.path().join("out.exr");
    let (status, stderr) = render_cli(&s.path, &out, ["--spectral-bins", "47", "--seed", "1"]);
    assert!(status.success(), "{stderr}");
    let is_bin = |n: &str| quasar::film::SpectralBins::is_channel(n);
    let main = quasar::output::read_exr(&out).unwrap();
    assert!(!main.channels.iter().any(|c| is_bin(&c.name)) && main.channel("R").is_some());
    let side = quasar::output::read_exr(&s.dir.path().join("out.spectral.exr")).unwrap();
    assert_eq!(side.channels.iter().filter(|c| is_bin(&c.name)).count(), 47);
    let (status, stderr) = render_cli(&s.path, Path::new("/dev/null"), ["--spectral-bins", "4"]);
    assert!(!status.success() && stderr.contains("give -o a file path"), "{stderr}");
}

/// A `--target-error` that `--time` cuts short is reported on stderr and in the header
/// (`target_error_reached`), and a reached one says so (issue 18).
#[test]
fn a_missed_target_error_is_reported() {
    let s = write_scene(GOOD, &[]);
    let out = s.dir.path().join("te.exr");
    for (target, reached) in [("1e-9", "false"), ("0.9", "true")] {
        let (status, stderr) = render_cli(&s.path, &out, ["--target-error", target, "--time", "0.5"]);
        assert!(status.success(), "{stderr}");
        assert_eq!(stderr.contains("not reached"), reached == "false", "{stderr}");
        let img = quasar::output::read_exr(&out).unwrap();
        assert_eq!(img.meta("target_error_reached"), Some(reached), "{target}");
    }
}

/// `--resume` with a smaller `--spp` than the checkpoint holds says so instead of silently
/// writing the checkpoint's image (issue 18).
#[test]
fn resuming_with_fewer_samples_than_the_checkpoint_warns() {
    let s = write_scene(GOOD, &[]);
    let (ckpt, out) = (s.dir.path().join("c.ckpt"), s.dir.path().join("c.exr"));
    let (status, stderr) =
        render_cli(&s.path, &out, ["--spp".as_ref(), "8".as_ref(), "--checkpoint".as_ref(), ckpt.as_os_str()]);
    assert!(status.success(), "{stderr}");
    let (status, stderr) =
        render_cli(&s.path, &out, ["--spp".as_ref(), "4".as_ref(), "--resume".as_ref(), ckpt.as_os_str()]);
    assert!(status.success() && stderr.contains("already holds 8") && stderr.contains("more than the 4"), "{stderr}");
}

/// A scene without lights is lit by the default white environment with a warning naming the
/// scene; with `--default-light none`, or when the image is all black, the render warns of the
/// black image instead of writing it silently (issue 18).
#[test]
fn black_renders_are_reported() {
    let no_light = GOOD.split("[[light]]").next().unwrap().to_string();
    let light_inside = no_light.clone() + "[[light]]\ntype = \"point\"\nposition = [0, 0, 0]\nscale = 1\n";
    let cases: [(&str, &[&str], &str); 3] = [
        (&no_light, &[], "it is lit by a uniform white environment"),
        (&no_light, &["--default-light", "none"], "has no light (no emissive"),
        (&light_inside, &[], "the image is black"),
    ];
    for (text, args, needle) in cases {
        let s = write_scene(text, &[]);
        let out = s.dir.path().join("black.exr");
        let (status, stderr) = render_cli(&s.path, &out, args);
        assert!(status.success() && stderr.contains(needle), "{stderr}");
        assert!(stderr.contains(&s.path.display().to_string()), "{stderr}");
        let lit =
            quasar::output::read_exr(&out).unwrap().channel(quasar::film::LUMINANCE).unwrap().iter().any(|&y| y > 0.0);
        assert_eq!(lit, args.is_empty() && text == no_light, "{needle}");
    }
    // `--default-light env` lights a scene that has a light of its own too (issue 52: it did
    // nothing there, silently)
    let s = write_scene(&light_inside, &[]);
    let out = s.dir.path().join("env.exr");
    let (status, stderr) = render_cli(&s.path, &out, ["--default-light", "env"]);
    assert!(status.success() && stderr.contains("--default-light env adds"), "{stderr}");
    assert!(!stderr.contains("the image is black"), "{stderr}");
    assert!(quasar::output::read_exr(&out).unwrap().channel(quasar::film::LUMINANCE).unwrap().iter().any(|&y| y > 0.0));
    let s = write_scene(GOOD, &[]);
    let (_, stderr) = render_cli(&s.path, &s.dir.path().join("lit.exr"), [] as [&str; 0]);
    assert!(!stderr.contains("black") && !stderr.contains("sees none"), "{stderr}");
    // a camera turned away from the geometry, under a lit sky: not black, but it sees nothing
    let away = write_scene(&GOOD.replace("target = [0, 0, 0]", "target = [0, 0, 6]"), &[]);
    let (status, stderr) = render_cli(&away.path, &away.dir.path().join("away.exr"), [] as [&str; 0]);
    assert!(status.success() && stderr.contains("the camera sees none of the scene's geometry"), "{stderr}");
}
