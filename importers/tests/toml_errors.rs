//! Malformed and hostile TOML scenes: every error names the file and the line (and column) of the
//! offending key, value or table; nothing panics.

mod common;

use common::{BASE, assert_at, err, line_of, ok};
use quasar_importers::{ImportErrorKind, ImportOptions, import_scene};

/// BASE with `from` replaced by `to`; returns the text and the error message.
fn bad(from: &str, to: &str) -> (String, String) {
    assert!(BASE.contains(from), "{from:?} not in BASE");
    let text = BASE.replacen(from, to, 1);
    let e = err(&text, &[]);
    (text, e)
}

/// BASE with `extra` appended.
fn bad_extra(extra: &str, files: &[(&str, &str)]) -> (String, String) {
    let text = format!("{BASE}{extra}");
    let e = err(&text, files);
    (text, e)
}

#[test]
fn syntax_error_names_line_and_column() {
    let (t, e) = bad("radius = 1\n", "radius = = 1\n");
    assert_at(&e, "scene.toml", line_of(&t, "radius = = 1"), &["TOML syntax error"]);
    assert!(e.contains(&format!("scene.toml:{}:10", line_of(&t, "radius = = 1"))), "{e}");
    let (t, e) = bad("target = [0, 0, 0]\n", "target = [0, 0, 0\n");
    assert!(e.contains("scene.toml:"), "{e}");
    let _ = t;
}

#[test]
fn duplicate_material_is_a_syntax_error_at_the_second_definition() {
    let (t, e) = bad_extra("[materials.grey]\ntype = \"diffuse\"\nreflectance = 0.1\n", &[]);
    let second = t.lines().enumerate().filter(|(_, l)| l.contains("[materials.grey]")).nth(1).unwrap().0 + 1;
    assert_at(&e, "scene.toml", second, &["duplicate"]);
}

#[test]
fn unknown_keys_list_the_expected_keys_and_suggest_one() {
    let (t, e) = bad("fov_deg = 40", "fov_dg = 40");
    assert_at(
        &e,
        "scene.toml",
        line_of(&t, "fov_dg"),
        &["unknown key `fov_dg`", "`camera`", "fov_axis", "did you mean `fov_deg`?"],
    );
    let (t, e) = bad("radius = 1\n", "radius = 1\nradiuss = 2\n");
    assert_at(&e, "scene.toml", line_of(&t, "radiuss"), &["did you mean `radius`?", "subdivisions"]);
    let (t, e) = bad_extra("[rendr]\nspp = 4\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "[rendr]"), &["at the top level", "did you mean `render`?"]);
    let (t, e) = bad("reflectance = 0.5", "reflectance = 0.5\ntwo_side = true");
    assert_at(&e, "scene.toml", line_of(&t, "two_side"), &["did you mean `two_sided`?"]);
    let (t, e) = bad("spectrum = 1", "spectrum = { constnt = 1 }");
    assert_at(&e, "scene.toml", line_of(&t, "constnt"), &["did you mean `constant`?"]);
    let (_, e) = bad("fov_deg = 40", "zzzzzzzz = 40");
    assert!(!e.contains("did you mean"), "{e}");
    // a value of the wrong kind
    let (t, e) = bad("type = \"sphere\"", "type = \"sphear\"");
    assert_at(&e, "scene.toml", line_of(&t, "sphear"), &["is not one of", "did you mean `sphere`?"]);
}

#[test]
fn wrong_types_and_non_finite_numbers() {
    for (from, to, needle) in [
        ("radius = 1\n", "radius = \"big\"\n", "must be a number, got a string"),
        ("radius = 1\n", "radius = nan\n", "finite"),
        ("radius = 1\n", "radius = inf\n", "finite"),
        ("radius = 1\n", "radius = 1e39\n", "out of range"),
        ("radius = 1\n", "radius = -1\n", "must be > 0"),
        ("radius = 1\n", "radius = 0\n", "must be > 0"),
        ("center = [0, 0, 0]", "center = [0, 0]", "must have 3 numbers"),
        ("center = [0, 0, 0]", "center = [0, 0, nan]", "center[2]"),
        ("center = [0, 0, 0]", "center = 0", "must be an array of 3 numbers"),
        ("fov_deg = 40", "fov_deg = 180", "in (0, 180)"),
        ("fov_deg = 40", "fov_deg = 0", "in (0, 180)"),
        ("fov_deg = 40", "fov_axis = \"z\"", "is not one of: x, y"),
        ("reflectance = 0.5", "reflectance = -0.5", "finite and >= 0"),
        ("reflectance = 0.5", "reflectance = { rgb = [1.2, 0, 0] }", "[0, 1]"),
        ("spectrum = 1", "spectrum = { blackbody = 5 }", "blackbody"),
        ("spectrum = 1", "spectrum = { illuminant = \"D56\" }", "did you mean `D65`?"),
        ("spectrum = 1", "spectrum = \"D65\"", "{ illuminant = \"D65\" }"),
        ("spectrum = 1", "spectrum = { constant = 1, blackbody = 3000 }", "only one spectrum form"),
        ("spectrum = 1", "spectrum = {}", "needs one of"),
        ("spectrum = 1", "spectrum = { wavelengths = [400, 500] }", "missing key `values`"),
        ("spectrum = 1", "spectrum = { wavelengths = [400, 500], values = [1] }", "equally many"),
        ("material = \"grey\"", "material = \"gray\"", "unknown material `gray` (defined: grey); did you mean `grey`?"),
        ("material = \"grey\"", "material = 3", "must be a string"),
        ("material = \"grey\"", "flip_normals = \"yes\"", "boolean"),
    ] {
        let (t, e) = bad(from, to);
        let line = line_of(&t, to.lines().next().unwrap());
        assert_at(&e, "scene.toml", line, &[needle]);
    }
}

#[test]
fn spectrum_table_errors_point_at_the_entry() {
    let (t, e) = bad("spectrum = 1", "spectrum = { wavelengths = [\n  400,\n  500,\n  450,\n], values = [1, 1, 1] }");
    let line = t.lines().position(|l| l.trim() == "450,").unwrap() + 1;
    assert_at(&e, "scene.toml", line, &["strictly increasing"]);
}

#[test]
fn material_validation_is_reported_at_the_material() {
    let (t, e) = bad_extra("[materials.bad]\ntype = \"dielectric\"\nior = -1\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "[materials.bad]"), &["material `bad`", "IOR"]);
    let (t, e) = bad("reflectance = 0.5", "reflectance = 1.5");
    assert_at(&e, "scene.toml", line_of(&t, "[materials.grey]"), &["material `grey`", "[0, 1]"]);
    let (t, e) = bad_extra("[materials.bad]\ntype = \"conductor\"\nfresnel = 2\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "[materials.bad]"), &["material `bad`"]);
    let (t, e) = bad_extra("[materials.bad]\ntype = \"conductor\"\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "[materials.bad]"), &["needs `fresnel`"]);
    let (t, e) = bad_extra("[materials.bad]\ntype = \"conductor\"\nmetal = \"Gold\"\nfresnel = 0.5\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "fresnel = 0.5"), &["only one of"]);
    let (t, e) = bad_extra("[materials.bad]\ntype = \"conductor\"\nmetal = \"Alu\"\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "metal = \"Alu\""), &["unknown metal", "did you mean `Al`?"]);
    let (t, e) = bad_extra("[materials.bad]\ntype = \"conductor\"\neta = 1.5\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "[materials.bad]"), &["missing key `k`"]);
    let (t, e) = bad_extra("[materials.bad]\ntype = \"conductor\"\neta = { rgb = [1, 1, 1] }\nk = 1\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "eta = "), &["not meaningful"]);
    let (t, e) = bad_extra("[materials.bad]\ntype = \"dielectric\"\nior = \"BK8\"\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "ior = \"BK8\""), &["unknown optical material", "did you mean `BK7`?"]);
    let (t, e) = bad_extra("[materials.bad]\ntype = \"dielectric\"\nior = { cauchy = [1.5] }\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "cauchy"), &["2 numbers"]);
    let (t, e) = bad_extra("[materials.bad]\ntype = \"dielectric\"\nior = 1.5\nalpha = 0.1\nroughness = 0.2\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "roughness"), &["only one of"]);
    let (t, e) = bad_extra("[materials.bad]\ntype = \"dielectric\"\nior = 1.5\nalpha = -0.1\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "alpha = -0.1"), &[">= 0"]);
    let (t, e) = bad_extra("[materials.bad]\ntype = \"plastic\"\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "plastic"), &["diffuse, conductor, dielectric, coated, sheen"]);
    let (t, e) = bad_extra("[materials.bad]\nreflectance = 1\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "[materials.bad]"), &["missing key `type`"]);
    let (t, e) = bad_extra("[materials.bad]\nfile = \"lightguide.toml\"\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "file ="), &["does not exist", "lightguide.toml"]);
    let (t, e) = bad_extra("[materials.bad]\ntype = \"diffuse\"\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "[materials.bad]"), &["missing key `reflectance`"]);
}

/// `type = "coated"` (issue 50): its base, IOR and absorption keys are checked where they stand.
#[test]
fn coated_material_errors() {
    let coat = |body: &str| bad_extra(&format!("[materials.bad]\ntype = \"coated\"\n{body}"), &[]);
    let (t, e) = coat("ior = 1.5\n");
    assert_at(&e, "scene.toml", line_of(&t, "[materials.bad]"), &["missing key `base`"]);
    let (t, e) = coat("base = { type = \"dielectric\", ior = 1.5 }\n");
    assert_at(&e, "scene.toml", line_of(&t, "base = "), &["diffuse or conductor", "opaque tabulated"]);
    let (t, e) = coat("base = { type = \"diffuse\", reflectance = 2 }\n");
    assert_at(&e, "scene.toml", line_of(&t, "base = "), &["[0, 1]"]);
    let (t, e) = coat("ior = 0.5\nbase = { type = \"diffuse\", reflectance = 0.5 }\n");
    assert_at(&e, "scene.toml", line_of(&t, "ior = 0.5"), &["[1, 4]"]);
    let (t, e) = coat("absorption = 100\nbase = { type = \"diffuse\", reflectance = 0.5 }\n");
    assert_at(&e, "scene.toml", line_of(&t, "absorption = 100"), &["needs the coat's `thickness`"]);
    let (t, e) = coat("thickness = 0.001\nbase = { type = \"diffuse\", reflectance = 0.5 }\n");
    assert_at(&e, "scene.toml", line_of(&t, "thickness"), &["goes with `absorption`"]);
    let (t, e) = coat("base = { type = \"diffuse\", reflectance = 0.5 }\ncolour = 1\n");
    assert_at(&e, "scene.toml", line_of(&t, "colour"), &["unknown key"]);
}

/// A named absorption (issue 49 item 4) must be one with measured data.
#[test]
fn unknown_absorber_is_named_with_a_suggestion() {
    let (t, e) = bad_extra("[materials.bad]\ntype = \"dielectric\"\nior = 1.49\nabsorption = \"PMMX\"\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "absorption = \"PMMX\""), &["no measured absorption", "PMMA", "1/m"]);
    let (t, e) = bad_extra("[materials.bad]\ntype = \"dielectric\"\nior = 1.33\nabsorption = \"water\"\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "absorption = \"water\""), &["\"water\"", "polycarbonate"]);
}

#[test]
fn spectrum_csv_errors_name_the_csv_file_and_line() {
    let extra = "[materials.c]\ntype = \"diffuse\"\nreflectance = { file = \"r.csv\" }\n";
    let (_, e) = bad_extra(extra, &[("r.csv", "nm,value\n400,0.1\n500,abc\n")]);
    assert_at(&e, "r.csv", 3, &["`abc` is not a number", "included from", "scene.toml:"]);
    let (_, e) = bad_extra(extra, &[("r.csv", "400,0.1\n# c\n390,0.2\n")]);
    assert_at(&e, "r.csv", 3, &["strictly increasing"]);
    let (_, e) = bad_extra(extra, &[("r.csv", "400,0.1\n500,nan\n")]);
    assert_at(&e, "r.csv", 2, &["finite"]);
    let (_, e) = bad_extra(extra, &[("r.csv", "400,0.1,3\n")]);
    assert_at(&e, "r.csv", 1, &["got 3 fields"]);
    let (_, e) = bad_extra(extra, &[("r.csv", "# only comments\n")]);
    assert!(e.contains("r.csv: no"), "{e}");
    // missing CSV: the scene line of the `file` key
    let (t, e) = bad_extra(extra, &[]);
    assert_at(&e, "scene.toml", line_of(&t, "r.csv"), &["cannot read spectrum file `r.csv`"]);
}

#[test]
fn shape_errors() {
    let quad = |body: &str| format!("{BASE}[[shape]]\ntype = \"quad\"\nmaterial = \"grey\"\n{body}");
    let t = quad("corner = [0, 0, 0]\nedge1 = [1, 0, 0]\nedge2 = [2, 0, 0]\n");
    assert_at(&err(&t, &[]), "scene.toml", line_of(&t, "type = \"quad\"") - 1, &["not parallel"]);
    let t = quad("corner = [0, 0, 0]\nedge1 = [1, 0, 0]\n");
    assert_at(&err(&t, &[]), "scene.toml", line_of(&t, "type = \"quad\"") - 1, &["missing key `edge2`"]);
    let t = quad("corner = [0, 0, 0]\nedge1 = [1, 0, 0]\nedge2 = [0, 1, 0]\nsize = [1, 1]\n");
    assert_at(&err(&t, &[]), "scene.toml", line_of(&t, "size ="), &["not both"]);
    let t = quad("size = [1, -1]\n");
    assert_at(&err(&t, &[]), "scene.toml", line_of(&t, "size ="), &["> 0"]);
    let t = quad("size = [1, 1]\nnormal = [0, 0, 0]\n");
    assert_at(&err(&t, &[]), "scene.toml", line_of(&t, "normal ="), &["non-zero"]);
    let t = quad("corner = [3e38, 0, 0]\nedge1 = [3e38, 0, 0]\nedge2 = [0, 1, 0]\n");
    assert_at(&err(&t, &[]), "scene.toml", line_of(&t, "type = \"quad\"") - 1, &["overflow"]);
    let (t, e) = bad("radius = 1\n", "radius = 1\nsubdivisions = 100\n");
    assert_at(&e, "scene.toml", line_of(&t, "subdivisions"), &["0..=8"]);
    let (t, e) = bad("radius = 1\n", "radius = 1\nsubdivisions = 99999999999999999999999\n");
    assert!(e.contains(&format!("scene.toml:{}", line_of(&t, "subdivisions"))), "{e}");
    let (t, e) = bad("radius = 1\n", "radius = 1\ntransform = { scale = 0 }\n");
    assert_at(&e, "scene.toml", line_of(&t, "transform"), &["non-zero"]);
    let (t, e) = bad("radius = 1\n", "radius = 1\ntransform = { scale = [1e38, 1, 1], translate = [3e38, 0, 0] }\n");
    assert_at(&e, "scene.toml", line_of(&t, "type = \"sphere\"") - 1, &["overflow"]);
    let (t, e) = bad("radius = 1\n", "radius = 1\ntransform = { scale = 1e30 }\n");
    assert_at(&e, "scene.toml", line_of(&t, "transform"), &["degenerate or overflows"]);
    let (t, e) = bad(
        "radius = 1\n",
        "radius = 1\ntransform = { rotate_deg = [0, 0, 0], rotate = { axis = [0, 1, 0], angle_deg = 3 } }\n",
    );
    assert_at(&e, "scene.toml", line_of(&t, "transform"), &["only one of"]);
    let (t, e) = bad("radius = 1\n", "radius = 1\ntransform = { rotate = { axis = [0, 0, 0], angle_deg = 3 } }\n");
    assert_at(&e, "scene.toml", line_of(&t, "transform"), &["non-zero"]);
    let (t, e) = bad("radius = 1\n", "radius = 1\ntransform = { translat = [0, 0, 0] }\n");
    assert_at(&e, "scene.toml", line_of(&t, "transform"), &["did you mean `translate`?"]);
    let (t, e) = bad("material = \"grey\"\n", "");
    assert_at(&e, "scene.toml", line_of(&t, "[[shape]]"), &["missing key `material`"]);
    let (t, e) = bad("type = \"sphere\"\n", "");
    assert_at(&e, "scene.toml", line_of(&t, "[[shape]]"), &["missing key `type`", "mesh, quad, sphere, disk"]);
    let (t, e) = bad("[[shape]]", "[shape]");
    assert_at(&e, "scene.toml", line_of(&t, "[shape]"), &["[[shape]]"]);
    let (t, e) = bad_extra("[[shape]]\ntype = \"disk\"\nradius = 1\nsegments = 2\nmaterial = \"grey\"\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "segments"), &["3..="]);
    let (t, e) =
        bad_extra("[[shape]]\ntype = \"disk\"\nradius = 1\nmaterial = \"grey\"\nemission = { scale = 1 }\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "emission"), &["missing key `spectrum`"]);
    let (t, e) = bad_extra(
        "[[shape]]\ntype = \"disk\"\nradius = 1\nmaterial = \"grey\"\nemission = { spectrum = 1, scale = -2 }\n",
        &[],
    );
    assert_at(&e, "scene.toml", line_of(&t, "emission"), &[">= 0"]);
}

#[test]
fn mesh_file_errors() {
    let shape = "[[shape]]\ntype = \"mesh\"\nfile = \"m.obj\"\nmaterial = \"grey\"\n";
    let (t, e) = bad_extra(shape, &[]);
    assert_at(&e, "scene.toml", line_of(&t, "m.obj"), &["cannot find `m.obj`"]);
    let (t, e) = bad_extra(shape, &[("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 zero\nf 1 2 3\n")]);
    assert_at(&e, "m.obj", 3, &["`zero` is not a number", "(included from"]);
    assert!(e.contains(&format!("scene.toml:{}", line_of(&t, "m.obj"))), "{e}");
    let (_, e) = bad_extra(shape, &[("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n")]);
    assert_at(&e, "m.obj", 4, &["out of range"]);
    let inc = "[[include]]\nfile = \"m.fbx\"\n";
    let (t, e) = bad_extra(inc, &[("m.fbx", "")]);
    assert_at(&e, "scene.toml", line_of(&t, "m.fbx"), &["unsupported file type", ".obj"]);
    let inc = "[[include]]\nfile = \"m.obj\"\n";
    // a missing material library of an included OBJ: a warning naming the OBJ line (issue 52)
    let d = ok(&format!("{BASE}{inc}"), &[("m.obj", "mtllib nope.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")]);
    assert!(
        d.warnings.iter().any(|w| w.contains("m.obj:1: material library `nope.mtl` not found")),
        "{:?}",
        d.warnings
    );
    let inc = "[[include]]\nfile = \"m.obj\"\nmaterial = \"gery\"\n";
    let (t, e) = bad_extra(inc, &[("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")]);
    assert_at(&e, "scene.toml", line_of(&t, "gery"), &["did you mean `grey`?"]);
    let inc = "[[include]]\nfile = \"m.obj\"\nmaterial = \"grey\"\nscale = 2\n";
    let (t, e) = bad_extra(inc, &[("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")]);
    assert_at(&e, "scene.toml", line_of(&t, "scale = 2"), &["unknown key `scale`", "transform"]);
}

#[test]
fn include_cycles_are_caught() {
    let a = "[[include]]\nfile = \"b.toml\"\n";
    let b = "[[include]]\nfile = \"scene.toml\"\n";
    let e = err(a, &[("b.toml", b)]);
    assert!(e.contains("nested more than"), "{e}");
    assert!(e.contains("scene.toml:2:8") || e.contains("b.toml:2:8"), "{e}");
    let e = err("[[include]]\nfile = \"b.toml\"\nunits = \"cm\"\n", &[("b.toml", BASE)]);
    assert!(e.contains("scene.toml:3:1") && e.contains("own `units`"), "{e}");
}

#[test]
fn override_errors() {
    let (t, e) = bad_extra("[[override]]\nmatch = \"nothing*\"\nmaterial = \"grey\"\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "nothing*"), &["matches no mesh", "shape[0]:sphere"]);
    let (t, e) = bad_extra("[[override]]\nmatch = \"*\"\nmaterial = \"nope\"\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "\"nope\""), &["unknown material `nope`"]);
    let (t, e) = bad_extra("[[override]]\nmaterial = \"grey\"\n", &[]);
    assert_at(&e, "scene.toml", line_of(&t, "[[override]]"), &["missing key `match`"]);
}

#[test]
fn render_camera_and_light_errors() {
    // (appended text, text on the line the error must name, text the message must contain)
    // (method names and method parameters are the renderer's: tests/cli.rs)
    let cases: [(&str, &str, &str); 11] = [
        ("[render]\nwidth = 0\n", "width", "1..=65536"),
        ("[render]\nheight = 70000\n", "height", "1..=65536"),
        ("[render]\nwidth = 64.0\n", "width", "must be an integer"),
        ("[render]\nspp = 0\n", "spp", "spp"),
        ("[render]\ntime = -1\n", "time", "> 0"),
        ("[render]\nseed = -3\n", "seed", "seed"),
        ("[[light]]\ntype = \"point\"\n", "type = \"point\"", "missing key `position`"),
        ("[[light]]\ntype = \"spot\"\nposition = [0, 0, 0]\ntarget = [0, 0, 0]\ncone_deg = 10\n", "target", "differ"),
        (
            "[[light]]\ntype = \"spot\"\nposition = [0, 0, 0]\ndirection = [0, -1, 0]\ncone_deg = 10\nfalloff_start_deg = 20\n",
            "falloff_start_deg",
            "cone_deg = 10",
        ),
        ("[[light]]\ntype = \"directional\"\ndirection = [0, 0, 0]\n", "direction =", "non-zero"),
        ("[[light]]\ntype = \"area\"\n", "\"area\"", "point, spot, directional, luminaire, environment"),
    ];
    for (extra, line_needle, needle) in cases {
        let (t, e) = bad_extra(extra, &[]);
        let lines: Vec<&str> = t.lines().collect();
        let mut line = lines.iter().rposition(|l| l.contains(line_needle)).unwrap() + 1;
        if needle.starts_with("missing key") {
            line -= 1; // reported at the table header
        }
        assert_at(&e, "scene.toml", line, &[needle]);
    }
    let (t, e) = bad("fov_deg = 40", "fov_deg = 40\nup = [0, 0, 1]");
    assert_at(&e, "scene.toml", line_of(&t, "up = "), &["parallel"]);
    let (t, e) = bad("target = [0, 0, 0]", "target = [0, 0, 5]");
    assert_at(&e, "scene.toml", line_of(&t, "target = "), &["differ"]);
    let (_, e) = bad("position = [0, 0, 5]", "position = 3");
    assert!(e.contains("scene.toml:2:12"), "{e}");
}

#[test]
fn units_and_empty_scene() {
    let e = err("units = \"cms\"\n[[light]]\ntype = \"environment\"\n", &[]);
    assert_at(&e, "scene.toml", 1, &["m, cm, mm, in, ft", "did you mean `cm`?"]);
    let e = err("[camera]\nfov_deg = 30\n", &[]);
    assert_at(&e, "scene.toml", 1, &["empty"]);
    let e = err("", &[]);
    assert_at(&e, "scene.toml", 1, &["empty"]);
}

#[test]
fn missing_or_unreadable_scene_files() {
    let f = common::Files::new();
    let e = import_scene(&f.path("nope.toml"), &ImportOptions::default()).unwrap_err();
    assert_eq!(e.kind, ImportErrorKind::MissingFile);
    assert!(e.to_string().contains("nope.toml"), "{e}");
    let p = f.dir.path().join("bin.toml");
    std::fs::write(&p, b"[render]\nwidth = 3\n\xff\xfe\n").unwrap();
    let e = import_scene(&p, &ImportOptions::default()).unwrap_err().to_string();
    assert!(e.contains("bin.toml:3"), "{e}");
    let e = import_scene(&f.path("x.toml"), &ImportOptions { units_scale: Some(f32::NAN), ..Default::default() })
        .unwrap_err();
    assert!(e.to_string().contains("x.toml"), "{e}");
}

/// Deterministic mutation fuzzing: no input may panic.
#[test]
fn mutated_scenes_never_panic() {
    let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nusemtl a\nf 1//1 2//1 3//1\n";
    let mtl = "newmtl a\nKd 0.5 0.5 0.5\nKs 0.1 0.1 0.1\nNs 10\nKe 1 1 1\n";
    let scene = format!(
        "{BASE}[[include]]\nfile = \"m.obj\"\n[materials.c]\ntype = \"conductor\"\nmetal = \"Au\"\n\
         [[shape]]\ntype = \"quad\"\ncenter = [0, 0, 0]\nsize = [1, 1]\nmaterial = \"c\"\n\
         emission = {{ spectrum = {{ rgb = [1, 1, 1] }} }}\n[[override]]\nmatch = \"*\"\nmaterial = \"c\"\n"
    );
    let alphabet: &[u8] = b"[]{}=\",.-+0123456789e\n #/abcnfiv";
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut rnd = move |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n as u64) as usize
    };
    let f = common::Files::new();
    for round in 0..300 {
        let (name, base) = match round % 3 {
            0 => ("scene.toml", scene.as_bytes()),
            1 => ("m.obj", obj.as_bytes()),
            _ => ("m.mtl", mtl.as_bytes()),
        };
        let mut bytes = base.to_vec();
        for _ in 0..1 + rnd(4) {
            let i = rnd(bytes.len());
            match rnd(3) {
                0 => bytes[i] = alphabet[rnd(alphabet.len())],
                1 => {
                    bytes.remove(i);
                }
                _ => bytes.insert(i, alphabet[rnd(alphabet.len())]),
            }
        }
        f.write("scene.toml", &scene);
        f.write("m.obj", obj);
        f.write("m.mtl", mtl);
        std::fs::write(f.path(name), &bytes).unwrap();
        if let Err(e) = f.import("scene.toml") {
            let s = e.to_string();
            assert!(s.contains("scene.toml") || s.contains("m.obj") || s.contains("m.mtl"), "{s}");
        }
    }
}

#[test]
fn deeply_nested_values_are_an_error_not_a_stack_overflow() {
    let deep = format!("x = {}{}\n", "[".repeat(100_000), "]".repeat(100_000));
    let e = err(&deep, &[]);
    assert!(e.contains("scene.toml:1:"), "{e}");
    let deep = format!(
        "{BASE}[materials.d]\ntype = \"diffuse\"\nreflectance = {}1{}\n",
        "{ a = ".repeat(5000),
        "}".repeat(5000)
    );
    let e = err(&deep, &[]);
    assert!(e.contains("scene.toml:"), "{e}");
}

/// `[[sensor]]`: a semi-cylindrical meter needs a horizontal `facing`, and only it takes one.
#[test]
fn semi_cylindrical_sensors_need_a_horizontal_facing() {
    let meter = "[[sensor]]\nname = \"m\"\ntype = \"point\"\nposition = [0, 0, 0]\n";
    let (t, e) = bad_extra(&format!("{meter}quantity = \"semi-cylindrical\"\n"), &[]);
    assert_at(&e, "scene.toml", line_of(&t, "[[sensor]]"), &["`facing`"]);
    let (t, e) = bad_extra(&format!("{meter}quantity = \"semi-cylindrical\"\nfacing = [0, 1, 0]\n"), &[]);
    assert_at(&e, "scene.toml", line_of(&t, "facing ="), &["`facing` is vertical"]);
    let (t, e) = bad_extra(&format!("{meter}facing = [1, 0, 0]\n"), &[]);
    assert_at(&e, "scene.toml", line_of(&t, "facing ="), &["`facing` is for quantity = \"semi-cylindrical\""]);
    let (t, e) = bad_extra(&format!("{meter}quantity = \"semicylindrical\"\n"), &[]);
    assert_at(&e, "scene.toml", line_of(&t, "quantity ="), &["semi-cylindrical"]);
}

/// A luminaire's `opening` is a rectangle (`size`) or a disk (`diameter`) of positive lengths;
/// anything else is an error at its line.
#[test]
fn luminaire_openings_are_checked() {
    let ies = "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 2 1 1 2 0 0 0\n1 1 10\n0 90\n0\n100 0\n";
    let lamp = "[[light]]\ntype = \"luminaire\"\nfile = \"l.ies\"\nposition = [0, 2, 0]\n";
    for (opening, needle) in [
        ("opening = { size = [1, 0] }", "positive lengths"),
        ("opening = { diameter = -1 }", "positive length"),
        ("opening = { size = [1, 1], diameter = 1 }", "diameter"),
        ("opening = { }", "`size = [c0, c90]` or `diameter = d`"),
        ("opening = { radius = 1 }", "unknown key `radius`"),
    ] {
        let (t, e) = bad_extra(&format!("{lamp}{opening}\n"), &[("l.ies", ies)]);
        assert_at(&e, "scene.toml", line_of(&t, "opening ="), &[needle]);
    }
}
