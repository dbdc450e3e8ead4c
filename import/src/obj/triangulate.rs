//! Triangulation of a face's polygon by ear clipping.

/// Polygons with more corners than this are fan-triangulated: ear clipping
/// costs up to the cube of the corner count.
pub const EAR_CLIPPING_MAX_CORNERS: usize = 256;

/// Splits a polygon into triangles, as indices into `points`, keeping its
/// winding.
///
/// A triangle is returned as is. A larger polygon is projected onto the
/// plane of its dominant axis (from Newell's normal) and ear-clipped there,
/// so convex and concave simple polygons are split exactly, into
/// `points.len() - 2` triangles. Polygons with no area, self-intersecting
/// ones where no ear is left, and ones with more than
/// [`EAR_CLIPPING_MAX_CORNERS`] corners fall back to a fan around the
/// first remaining corner; any degenerate triangles that gives are dropped
/// by the importer. Never panics.
///
/// ```
/// use microraster_import::triangulate;
/// // An L shape: a fan from corner 0 would cover the notch.
/// let l = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0],
///          [1.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 2.0, 0.0]];
/// assert_eq!(triangulate(&l).len(), 4);
/// ```
pub fn triangulate(points: &[[f64; 3]]) -> Vec<[usize; 3]> {
    let n = points.len();
    if n < 3 {
        return Vec::new();
    }
    if n == 3 {
        return vec![[0, 1, 2]];
    }
    let fan = |rest: &[usize]| -> Vec<[usize; 3]> {
        (1..rest.len().saturating_sub(1))
            .map(|i| [rest[0], rest[i], rest[i + 1]])
            .collect()
    };
    let all: Vec<usize> = (0..n).collect();
    if n > EAR_CLIPPING_MAX_CORNERS {
        return fan(&all);
    }
    // Newell's normal, and the plane of its largest component.
    let mut normal = [0.0f64; 3];
    for i in 0..n {
        let a = points[i];
        let b = points[(i + 1) % n];
        normal[0] += (a[1] - b[1]) * (a[2] + b[2]);
        normal[1] += (a[2] - b[2]) * (a[0] + b[0]);
        normal[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    let axis = (0..3)
        .max_by(|&a, &b| normal[a].abs().total_cmp(&normal[b].abs()))
        .unwrap_or(2);
    if normal[axis] == 0.0 || !normal[axis].is_finite() {
        return fan(&all);
    }
    // Project so that the polygon winds counter-clockwise in 2D.
    let (u, v) = match axis {
        0 => (1, 2),
        1 => (2, 0),
        _ => (0, 1),
    };
    let flip = normal[axis] < 0.0;
    let p2: Vec<[f64; 2]> = points
        .iter()
        .map(|p| if flip { [p[v], p[u]] } else { [p[u], p[v]] })
        .collect();
    let turn = |a: usize, b: usize, c: usize| -> f64 {
        let (a, b, c) = (p2[a], p2[b], p2[c]);
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    };
    let mut remaining = all;
    let mut out = Vec::with_capacity(n - 2);
    // Starting at corner 1 makes a convex polygon's triangles those of the
    // fan around corner 0: (0, 1, 2), (0, 2, 3), ...
    let mut start = 1;
    while remaining.len() > 3 {
        let m = remaining.len();
        let ear = (0..m).map(|k| (start + k) % m).find(|&i| {
            let (a, b, c) = (
                remaining[(i + m - 1) % m],
                remaining[i],
                remaining[(i + 1) % m],
            );
            if turn(a, b, c) <= 0.0 {
                return false;
            }
            remaining.iter().all(|&q| {
                if q == a || q == b || q == c {
                    return true;
                }
                let pq = p2[q];
                if pq == p2[a] || pq == p2[b] || pq == p2[c] {
                    return true;
                }
                // Outside (strictly) of at least one edge.
                turn(a, b, q) < 0.0 || turn(b, c, q) < 0.0 || turn(c, a, q) < 0.0
            })
        });
        match ear {
            Some(i) => {
                out.push([
                    remaining[(i + m - 1) % m],
                    remaining[i],
                    remaining[(i + 1) % m],
                ]);
                remaining.remove(i);
                start = i % remaining.len();
            }
            None => {
                out.extend(fan(&remaining));
                return out;
            }
        }
    }
    out.push([remaining[0], remaining[1], remaining[2]]);
    out
}
