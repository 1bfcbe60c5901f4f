//! Writing a large single-mesh stage for benchmarks and tests: a `Mesh` with `points`,
//! polygon `faceVertexCounts`/`faceVertexIndices`, vertex `normals` and `primvars:st`, as
//! `.usda` text or as a `.usdc` crate file (openusd's `CrateWriter`, from the text parsed by
//! openusd). Not an exporter of scenes: Pixar's USD 26.11 reads no prims from openusd 0.6.0's
//! crate files (its path table is decoded differently), so they serve quasar's own benchmarks only;
//! the text is read by both.

use std::fmt::Write as _;
use std::path::Path;

/// A polygon mesh to write: positions, one normal and one st per point, and polygons as
/// counts and point indices (USD's `faceVertexCounts` / `faceVertexIndices`).
pub struct PolygonMesh<'a> {
    /// Point positions (stage units, metres here).
    pub points: &'a [[f32; 3]],
    /// One normal per point (`interpolation = "vertex"`).
    pub normals: &'a [[f32; 3]],
    /// One texture coordinate per point (`primvars:st`, vertex).
    pub st: &'a [[f32; 2]],
    /// Points per polygon.
    pub face_counts: &'a [u32],
    /// Point indices, the polygons one after the other.
    pub face_indices: &'a [u32],
}

/// The `.usda` text of a Y-up stage in metres holding `mesh` as `/World/<name>`.
pub fn mesh_stage_text(name: &str, mesh: &PolygonMesh<'_>) -> String {
    let mut s = String::with_capacity(48 * mesh.points.len() + 12 * mesh.face_indices.len());
    s += "#usda 1.0\n(\n    defaultPrim = \"World\"\n    metersPerUnit = 1\n    upAxis = \"Y\"\n)\n\n";
    s += "def Xform \"World\"\n{\n";
    let _ = writeln!(s, "    def Mesh \"{name}\"\n    {{");
    s += "        uniform token subdivisionScheme = \"none\"\n";
    let list = |s: &mut String, decl: &str, items: &mut dyn Iterator<Item = String>| {
        let _ = write!(s, "        {decl} = [");
        for (i, it) in items.enumerate() {
            if i > 0 {
                s.push_str(", ");
            }
            s.push_str(&it);
        }
        s.push_str("]\n");
    };
    let v3 = |p: &[f32; 3]| format!("({}, {}, {})", p[0], p[1], p[2]);
    list(&mut s, "int[] faceVertexCounts", &mut mesh.face_counts.iter().map(u32::to_string));
    list(&mut s, "int[] faceVertexIndices", &mut mesh.face_indices.iter().map(u32::to_string));
    list(&mut s, "point3f[] points", &mut mesh.points.iter().map(v3));
    list(&mut s, "normal3f[] normals", &mut mesh.normals.iter().map(v3));
    s += "        uniform token normals:interpolation = \"vertex\"\n";
    list(&mut s, "texCoord2f[] primvars:st", &mut mesh.st.iter().map(|t| format!("({}, {})", t[0], t[1])));
    s += "        uniform token primvars:st:interpolation = \"vertex\"\n";
    s += "    }\n}\n";
    s
}

/// Writes `mesh` as a `.usdc` crate file at `path` (the stage of [`mesh_stage_text`]).
pub fn write_mesh_usdc(path: &Path, name: &str, mesh: &PolygonMesh<'_>) -> Result<(), String> {
    let text = mesh_stage_text(name, mesh);
    let data = openusd::usda::parse(&text).map_err(|e| format!("openusd could not parse the stage: {e}"))?;
    drop(text);
    openusd::usdc::CrateWriter::write_to_file(&data, path)
        .map_err(|e| format!("{}: openusd could not write the crate file: {e}", path.display()))
}
