//! Reading USD attribute values of any precision (half, float, double; scalars, vectors,
//! arrays) into the f32/glam types the importer works in, naming the prim and attribute when a
//! value has the wrong type.

use std::cell::Cell;

use glam::{DQuat, Vec2, Vec3};
use openusd::sdf::Value;
use openusd::usd::{Prim, TimeCode};

/// A problem with one attribute: `(attribute name, what is wrong)`.
pub(super) type AttrError = (String, String);

thread_local! {
    /// The time code every attribute of the stage being imported on this thread is read at
    /// (`--time-code`; None: the earliest time sample).
    static TIME: Cell<Option<f64>> = const { Cell::new(None) };
}

/// Reads the stage's attributes at time code `t` (None: the earliest sample) until dropped.
pub(super) struct TimeScope(Option<f64>);

impl TimeScope {
    /// Sets the time code of this thread's attribute reads.
    pub(super) fn new(t: Option<f64>) -> Self {
        Self(TIME.with(|c| c.replace(t)))
    }
}

impl Drop for TimeScope {
    fn drop(&mut self) {
        TIME.with(|c| c.set(self.0));
    }
}

/// The time code attribute values are read at ([`TimeScope`]).
pub(super) fn time() -> TimeCode {
    TIME.with(Cell::get).map_or(TimeCode::EARLIEST, TimeCode::new)
}

/// The composed value of `prim`'s attribute `name` at the import's time code ([`time`]: the
/// earliest time sample unless `--time-code` is given, held or interpolated as USD does), or its
/// default when it has no time samples; None when nothing authored it.
pub(super) fn raw(prim: &Prim, name: &str) -> Result<Option<Value>, AttrError> {
    let attr = prim.attribute(name);
    let v = attr.get_at::<Value>(time()).map_err(|e| (name.to_string(), format!("{e:#}")))?;
    Ok(match v {
        Some(v) => Some(v),
        None => attr.get::<Value>().map_err(|e| (name.to_string(), format!("{e:#}")))?,
    })
}

fn wrong(name: &str, want: &str, v: &Value) -> AttrError {
    let got = format!("{v:?}");
    let got: String = got.chars().take(60).collect();
    (name.to_string(), format!("expected {want}, got {got}"))
}

/// A scalar number (`float`, `double`, `half`, or any integer: a whole number written as an
/// integer literal, as Python and `usdcat` write `10` in time samples, which openusd reads as
/// `Int64` where Pixar's USD reads the attribute's declared float).
pub(super) fn scalar(prim: &Prim, name: &str) -> Result<Option<f64>, AttrError> {
    Ok(match raw(prim, name)? {
        None => None,
        Some(Value::Float(f)) => Some(f64::from(f)),
        Some(Value::Double(d)) => Some(d),
        Some(Value::Half(h)) => Some(f64::from(f32::from(h))),
        Some(Value::Int(i)) => Some(f64::from(i)),
        Some(Value::Int64(i)) => Some(i as f64),
        Some(Value::Uint(i)) => Some(f64::from(i)),
        Some(Value::Uint64(i)) => Some(i as f64),
        Some(Value::Uchar(i)) => Some(f64::from(i)),
        Some(v) => return Err(wrong(name, "a number", &v)),
    })
}

/// A boolean.
pub(super) fn boolean(prim: &Prim, name: &str) -> Result<Option<bool>, AttrError> {
    Ok(match raw(prim, name)? {
        None => None,
        Some(Value::Bool(b)) => Some(b),
        Some(v) => return Err(wrong(name, "a bool", &v)),
    })
}

/// A token or string.
pub(super) fn token(prim: &Prim, name: &str) -> Result<Option<String>, AttrError> {
    Ok(match raw(prim, name)? {
        None => None,
        Some(Value::Token(t)) => Some(t.as_str().to_string()),
        Some(Value::String(s)) => Some(s),
        Some(v) => return Err(wrong(name, "a token", &v)),
    })
}

/// A 3-vector (`float3`, `double3`, `half3`, `color3f`, `point3f`, ...).
pub(super) fn vec3(prim: &Prim, name: &str) -> Result<Option<Vec3>, AttrError> {
    Ok(match raw(prim, name)? {
        None => None,
        Some(v) => Some(vec3_of(&v).ok_or_else(|| wrong(name, "a 3-vector", &v))?),
    })
}

fn vec3_of(v: &Value) -> Option<Vec3> {
    Some(match v {
        Value::Vec3f(a) => Vec3::new(a[0], a[1], a[2]),
        Value::Vec3d(a) => Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32),
        Value::Vec3h(a) => Vec3::new(f32::from(a[0]), f32::from(a[1]), f32::from(a[2])),
        // whole numbers written as integers (time samples `{0: (1, 2, 3)}`)
        Value::Vec3i(a) => Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32),
        _ => return None,
    })
}

/// An array of 3-vectors (`point3f[]`, `normal3f[]`, `double3[]`, ...).
pub(super) fn vec3_array(prim: &Prim, name: &str) -> Result<Option<Vec<Vec3>>, AttrError> {
    Ok(match raw(prim, name)? {
        None => None,
        Some(Value::Vec3fVec(a)) => Some(a.iter().map(|v| Vec3::new(v[0], v[1], v[2])).collect()),
        Some(Value::Vec3dVec(a)) => Some(a.iter().map(|v| Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32)).collect()),
        Some(Value::Vec3hVec(a)) => {
            Some(a.iter().map(|v| Vec3::new(f32::from(v[0]), f32::from(v[1]), f32::from(v[2]))).collect())
        }
        Some(v) => return Err(wrong(name, "an array of 3-vectors", &v)),
    })
}

/// An array of 2-vectors (`texCoord2f[]`, `float2[]`, ...).
pub(super) fn vec2_array(prim: &Prim, name: &str) -> Result<Option<Vec<Vec2>>, AttrError> {
    Ok(match raw(prim, name)? {
        None => None,
        Some(Value::Vec2fVec(a)) => Some(a.iter().map(|v| Vec2::new(v[0], v[1])).collect()),
        Some(Value::Vec2dVec(a)) => Some(a.iter().map(|v| Vec2::new(v[0] as f32, v[1] as f32)).collect()),
        Some(Value::Vec2hVec(a)) => Some(a.iter().map(|v| Vec2::new(f32::from(v[0]), f32::from(v[1]))).collect()),
        Some(v) => return Err(wrong(name, "an array of 2-vectors", &v)),
    })
}

/// An array of unit quaternions (`quath[]`, `quatf[]`, `quatd[]`).
pub(super) fn quat_array(prim: &Prim, name: &str) -> Result<Option<Vec<DQuat>>, AttrError> {
    let q = |w: f64, x: f64, y: f64, z: f64| DQuat::from_xyzw(x, y, z, w);
    Ok(match raw(prim, name)? {
        None => None,
        Some(Value::QuathVec(a)) => {
            Some(a.iter().map(|v| q(f64::from(v.w), f64::from(v.x), f64::from(v.y), f64::from(v.z))).collect())
        }
        Some(Value::QuatfVec(a)) => {
            Some(a.iter().map(|v| q(f64::from(v.w), f64::from(v.x), f64::from(v.y), f64::from(v.z))).collect())
        }
        Some(Value::QuatdVec(a)) => Some(a.iter().map(|v| q(v.w, v.x, v.y, v.z)).collect()),
        Some(v) => return Err(wrong(name, "an array of quaternions", &v)),
    })
}

/// An array of 64-bit integers (`int64[]`, or `int[]`).
pub(super) fn int64_array(prim: &Prim, name: &str) -> Result<Option<Vec<i64>>, AttrError> {
    Ok(match raw(prim, name)? {
        None => None,
        Some(Value::Int64Vec(a)) => Some(a),
        Some(Value::IntVec(a)) => Some(a.into_iter().map(i64::from).collect()),
        Some(v) => return Err(wrong(name, "an int64 array", &v)),
    })
}

/// An array of integers (`int[]`).
pub(super) fn int_array(prim: &Prim, name: &str) -> Result<Option<Vec<i32>>, AttrError> {
    Ok(match raw(prim, name)? {
        None => None,
        Some(Value::IntVec(a)) => Some(a),
        Some(v) => return Err(wrong(name, "an int array", &v)),
    })
}

/// The `interpolation` metadata of a primvar-like attribute (`vertex` when unauthored).
pub(super) fn interpolation(prim: &Prim, name: &str) -> String {
    prim.attribute(name)
        .get_metadata::<Value>("interpolation")
        .ok()
        .flatten()
        .and_then(|v| match v {
            Value::Token(t) => Some(t.as_str().to_string()),
            Value::String(s) => Some(s),
            _ => None,
        })
        .unwrap_or_else(|| "vertex".to_string())
}

/// Checks the names in `prim`'s `xformOpOrder`: `!resetXformStack!`, or `xformOp:TYPE[:SUFFIX]`
/// with an optional `!invert!` prefix and identifier characters only (openusd 0.6.0 spins on
/// op names with spaces or line breaks in them, found by the fuzzer), at most 1000 ops.
pub(super) fn check_op_order(prim: &Prim) -> Result<(), AttrError> {
    const NAME: &str = "xformOpOrder";
    let ops = match prim.attribute(NAME).get::<Value>().map_err(|e| (NAME.to_string(), format!("{e:#}")))? {
        None => return Ok(()),
        Some(Value::TokenVec(ops)) => ops,
        Some(v) => return Err(wrong(NAME, "a token array", &v)),
    };
    if ops.len() > 1000 {
        return Err((NAME.to_string(), format!("{} ops are more than 1000", ops.len())));
    }
    for op in &ops {
        let op = op.as_str();
        let name = op.strip_prefix("!invert!").unwrap_or(op);
        let ok = op == "!resetXformStack!"
            || (name.strip_prefix("xformOp:").is_some_and(|t| !t.is_empty())
                && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == ':'));
        if !ok {
            let shown: String = op.chars().take(60).collect();
            return Err((NAME.to_string(), format!("`{}` is not a transform op name", shown.escape_debug())));
        }
    }
    Ok(())
}

/// The file an asset path names: the path the resolver found, else the authored path relative to
/// the stage file's folder.
pub(super) fn asset_file(asset: &openusd::sdf::AssetPath, stage_file: &std::path::Path) -> std::path::PathBuf {
    match asset.resolved_path() {
        Some(r) if !r.is_empty() => std::path::PathBuf::from(r),
        _ => stage_file.parent().unwrap_or(std::path::Path::new(".")).join(asset.asset_path()),
    }
}
