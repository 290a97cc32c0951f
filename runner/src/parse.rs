//! Numbers and points from text: what the command line and the collider path parse.

/// Parses `N` comma-separated finite numbers.
pub fn parse_floats<const N: usize>(s: &str) -> Result<[f32; N], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != N {
        return Err(format!("expected {N} comma-separated numbers, got \"{s}\""));
    }
    let mut out = [0.0; N];
    for (o, p) in out.iter_mut().zip(parts) {
        *o = p
            .parse::<f32>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("\"{p}\" is not a finite number"))?;
    }
    Ok(out)
}

/// Largest coordinate a point on the command line may have, in scene units.
pub const COORDINATE_LIMIT: f32 = 1e6;

/// Parses `N` comma-separated coordinates, each within ±[`COORDINATE_LIMIT`].
pub fn parse_coordinates<const N: usize>(s: &str) -> Result<[f32; N], String> {
    let values = parse_floats::<N>(s)?;
    match values.iter().find(|v| v.abs() > COORDINATE_LIMIT) {
        Some(v) => Err(format!(
            "coordinate {v} is outside -{COORDINATE_LIMIT}..={COORDINATE_LIMIT}"
        )),
        None => Ok(values),
    }
}

/// A parser of one finite number in `lo..=hi`.
pub fn range(lo: f32, hi: f32) -> impl Fn(&str) -> Result<f32, String> + Clone {
    move |s| {
        let [v] = parse_floats::<1>(s)?;
        if (lo..=hi).contains(&v) {
            Ok(v)
        } else {
            Err(format!("{v} is outside {lo}..={hi}"))
        }
    }
}
