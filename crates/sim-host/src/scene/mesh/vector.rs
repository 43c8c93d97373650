//! Small f64 vector helpers the meshes share, and vertex normals.

/// Area-weighted vertex normals: each vertex gets the normalised sum of the
/// unnormalised face normals `(b - a) x (c - a)` of the triangles that use it, so
/// large triangles count more than small ones. A vertex whose sum is zero (unused,
/// or only in degenerate triangles) gets `(0, 1, 0)`.
///
/// # Panics
///
/// If a triangle indexes past the end of `positions`.
pub fn area_weighted_normals(positions: &[[f64; 3]], triangles: &[[u32; 3]]) -> Vec<[f64; 3]> {
    let mut sums = vec![[0.0; 3]; positions.len()];
    for tri in triangles {
        let n = face_normal(positions, tri);
        for &i in tri {
            sums[i as usize] = add(sums[i as usize], n);
        }
    }
    sums.into_iter()
        .map(|s| normalize(s).unwrap_or([0.0, 1.0, 0.0]))
        .collect()
}

pub(crate) fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `a / |a|`, or `None` if `a` is zero.
pub(crate) fn normalize(a: [f64; 3]) -> Option<[f64; 3]> {
    let len = dot(a, a).sqrt();
    if len > 0.0 && len.is_finite() {
        return Some(scale(a, 1.0 / len));
    }
    // The squared length overflowed or underflowed (huge or tiny finite
    // components): divide by the largest component first. Infinite or NaN
    // components have no direction.
    if !a.iter().all(|c| c.is_finite()) {
        return None;
    }
    let m = a.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    if m == 0.0 {
        return None;
    }
    let b = a.map(|c| c / m);
    let len = dot(b, b).sqrt();
    Some(b.map(|c| c / len))
}

/// Unnormalised normal `(b - a) x (c - a)` of a triangle: twice its area in length.
pub(crate) fn face_normal(positions: &[[f64; 3]], tri: &[u32; 3]) -> [f64; 3] {
    let [a, b, c] = tri.map(|i| positions[i as usize]);
    cross(sub(b, a), sub(c, a))
}

/// Moves and scales `positions` in place so that their bounding box is centred at
/// the origin and its largest half-extent is 1.
pub(crate) fn fit_unit_box(positions: &mut [[f64; 3]]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in positions.iter() {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let centre = scale(add(lo, hi), 0.5);
    let half = (0..3).map(|k| (hi[k] - lo[k]) * 0.5).fold(0.0, f64::max);
    if half > 0.0 {
        for p in positions.iter_mut() {
            *p = scale(sub(*p, centre), 1.0 / half);
        }
    }
}
