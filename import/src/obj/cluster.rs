//! The split of a model's triangles into clusters for per-cluster frustum
//! culling (see [the module documentation](super#clusters)).

use std::ops::Range;

use super::vector::bounds;
use super::{ClusterRange, Model};
use crate::error::ErrorKind;

impl Model {
    /// Lays the triangles and vertices out in clusters of at most `max`
    /// triangles (see [the module documentation](super#clusters)).
    ///
    /// Expects what the parser makes: groups that tile the triangles in
    /// order, indices in range, per-vertex arrays full or empty.
    pub(super) fn cluster(&mut self, max: usize) -> Result<(), ErrorKind> {
        // The generated `Cluster` holds counts as u32, and a cluster has at
        // most three vertices per triangle: this keeps both in range.
        let max = max.clamp(1, u32::MAX as usize / 3);
        let centroids: Vec<[f64; 3]> = self
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.positions[i as usize].map(f64::from));
                std::array::from_fn(|k| (a[k] + b[k] + c[k]) / 3.0)
            })
            .collect();
        // The triangles in their new order (old indices), and the clusters
        // as ranges of it, which are also the new triangle ranges.
        let mut order: Vec<usize> = Vec::with_capacity(self.triangles.len());
        let mut leaves: Vec<Range<usize>> = Vec::new();
        for g in &mut self.groups {
            let first = leaves.len();
            let start = order.len();
            order.extend(g.triangles.clone());
            split(&mut order[start..], start, &centroids, max, &mut leaves);
            g.clusters = first..leaves.len();
        }

        let old_count = self.positions.len();
        // Per old vertex: the last cluster that used it, and its index there.
        let mut owner = vec![usize::MAX; old_count];
        let mut local = vec![0u32; old_count];
        // The old vertex of each new one.
        let mut source: Vec<usize> = Vec::new();
        let mut triangles = Vec::with_capacity(order.len());
        let mut clusters = Vec::with_capacity(leaves.len());
        for (k, leaf) in leaves.into_iter().enumerate() {
            let first = source.len();
            for &t in &order[leaf.clone()] {
                triangles.push(self.triangles[t].map(|v| {
                    let v = v as usize;
                    if owner[v] != k {
                        owner[v] = k;
                        // Saturate rather than wrap: the count check below
                        // fails first.
                        local[v] = u32::try_from(source.len()).unwrap_or(u32::MAX);
                        source.push(v);
                    }
                    local[v]
                }));
            }
            clusters.push(ClusterRange {
                triangles: leaf,
                vertices: first..source.len(),
            });
        }
        let limit = self.options.index_width.max_vertices();
        if source.len() > limit {
            let used = owner.iter().filter(|&&k| k != usize::MAX).count();
            return Err(ErrorKind::TooManyVertices {
                count: source.len(),
                limit,
                duplicated: source.len() - used,
            });
        }
        self.positions = gather(&self.positions, &source);
        self.normals = gather(&self.normals, &source);
        self.uvs = gather(&self.uvs, &source);
        self.colors = gather(&self.colors, &source);
        self.triangles = triangles;
        self.clusters = clusters;
        Ok(())
    }
}

/// Splits `triangles` (indices into `centroids`, at `offset` in the new
/// order) along the longest axis of their centroids' box, the lower part
/// holding half the full clusters needed, recursively, until a part has at
/// most `max`; appends the parts' ranges to `out`, the lower part's first,
/// so that neighbours in the list are neighbours in space. `max` must be
/// at least 1.
fn split(
    triangles: &mut [usize],
    offset: usize,
    centroids: &[[f64; 3]],
    max: usize,
    out: &mut Vec<Range<usize>>,
) {
    if triangles.is_empty() {
        return;
    }
    if triangles.len() <= max {
        // The file's order: it is usually the modeller's strip order, and
        // a cluster no larger than its group stays as it was.
        triangles.sort_unstable();
        out.push(offset..offset + triangles.len());
        return;
    }
    let (lo, hi) = bounds(triangles.iter().map(|&t| centroids[t]));
    let axis = (1..3).fold(0, |a, k| if hi[k] - lo[k] > hi[a] - lo[a] { k } else { a });
    // The index breaks ties, so the order is total and the output the same
    // whatever the sort algorithm.
    triangles.sort_unstable_by(|&a, &b| {
        centroids[a][axis]
            .total_cmp(&centroids[b][axis])
            .then(a.cmp(&b))
    });
    // Cut where the lower part holds a whole number of full clusters, half
    // of them (rounded up): clusters come out full rather than halved
    // below the limit (9,216 triangles in clusters of 64 make 144
    // clusters, not 256 of 36). With k = ceil(len / max) >= 2 clusters
    // needed, the lower part holds max ceil(k / 2) < len triangles and the
    // upper part at least one.
    let k = triangles.len().div_ceil(max);
    let mid = max * k.div_ceil(2);
    let (low, high) = triangles.split_at_mut(mid);
    split(low, offset, centroids, max, out);
    split(high, offset + mid, centroids, max, out);
}

/// `values[i]` for each `i` of `source`; empty for an absent array.
fn gather<T: Copy>(values: &[T], source: &[usize]) -> Vec<T> {
    if values.is_empty() {
        return Vec::new();
    }
    source.iter().map(|&i| values[i]).collect()
}

#[cfg(test)]
mod tests {
    use std::ops::Range;
    use std::path::Path;

    use crate::obj::{parse_obj, Group, ObjOptions};

    #[test]
    fn a_group_without_triangles_gets_an_empty_run_of_clusters() {
        // The parser drops empty groups; a model built by hand may have one.
        let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 0 0\nv 6 0 0\nv 5 1 0\n\
                   g a\nf 1 2 3\nf 4 5 6\ng b\nf 3 2 1\n";
        let mut model = parse_obj(obj, Path::new("e.obj"), |_| None, &ObjOptions::default())
            .unwrap_or_else(|e| panic!("{e}"));
        let empty = |at: usize| Group {
            name: "empty".to_string(),
            material: None,
            triangles: at..at,
            clusters: 0..0,
        };
        model.groups.insert(0, empty(0));
        model.groups.insert(2, empty(2));
        model.groups.push(empty(3));
        model.cluster(1).unwrap_or_else(|e| panic!("{e}"));
        let runs: Vec<Range<usize>> = model.groups.iter().map(|g| g.clusters.clone()).collect();
        assert_eq!(runs, [0..0, 0..2, 2..2, 2..3, 3..3]);
        let triangles: Vec<Range<usize>> =
            model.groups.iter().map(|g| g.triangles.clone()).collect();
        assert_eq!(triangles, [0..0, 0..2, 2..2, 2..3, 3..3]);
        // Each cluster numbers its own copies in the order it uses them.
        assert_eq!(model.triangles, [[0, 1, 2], [3, 4, 5], [6, 7, 8]]);
        assert_eq!(
            model.positions[6..],
            [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]]
        );
        assert_eq!(model.normals.len(), 9);
    }
}
