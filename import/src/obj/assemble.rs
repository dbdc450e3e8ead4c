//! The model made from what the parser gathered: unique vertices, the fit
//! into 16.16, bounds, normals (given or computed), texture coordinates,
//! colours and the warnings about them.

use std::collections::HashMap;

use super::model::{to_fixed_saturating, unit_to_u8};
use super::parser::{clip, Corner, Parser, NONE};
use super::vector::{add, bounds, cross, length, normalize, sub};
use super::{to_fixed, Aabb, Fit, Group, Material, Model, Sphere};
use crate::error::{escape_controls, ErrorKind, ImportError};

impl Parser<'_> {
    pub(super) fn finish(self) -> Result<Model, ImportError> {
        let whole = |kind| ImportError::new(self.path, None, kind);
        if self.triangle_count == 0 {
            return Err(whole(ErrorKind::NoTriangles {
                degenerate: self.degenerate,
            }));
        }
        let mut warnings = self.warnings;

        // Unique vertices, numbered in the order triangles first use them.
        let mut index: HashMap<Corner, u32> = HashMap::new();
        let mut corners: Vec<Corner> = Vec::new();
        let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(self.triangle_count);
        let mut groups = Vec::with_capacity(self.groups.len());
        let mut undefined: Vec<String> = Vec::new();
        for g in &self.groups {
            let start = triangles.len();
            for tri in &g.triangles {
                triangles.push(tri.map(|c| {
                    *index.entry(c).or_insert_with(|| {
                        corners.push(c);
                        // At most 3 * max_triangles corners; saturate rather
                        // than wrap (the count check below fails first).
                        u32::try_from(corners.len() - 1).unwrap_or(u32::MAX)
                    })
                }));
            }
            let material = g.material.as_ref().map(|name| {
                self.materials.get(name).cloned().unwrap_or_else(|| {
                    if !undefined.contains(name) {
                        undefined.push(name.clone());
                    }
                    Material {
                        name: name.clone(),
                        diffuse: [1.0; 3],
                        texture: None,
                    }
                })
            });
            groups.push(Group {
                name: g.name.clone(),
                material,
                triangles: start..triangles.len(),
                clusters: 0..0,
            });
        }
        for name in undefined {
            warnings.push(format!(
                "material `{}` is not defined; it is white",
                escape_controls(&name)
            ));
        }
        let limit = self.options.index_width.max_vertices();
        if corners.len() > limit {
            return Err(whole(ErrorKind::TooManyVertices {
                count: corners.len(),
                limit,
                duplicated: 0,
            }));
        }

        let source_pos = |c: &Corner| self.positions[c[0] as usize].map(f64::from);

        // Fit into 16.16.
        let (min, max) = bounds(corners.iter().map(source_pos));
        let center: [f64; 3] = std::array::from_fn(|k| (min[k] + max[k]) / 2.0);
        let radius = corners
            .iter()
            .map(|c| length(sub(source_pos(c), center)))
            .fold(0.0, f64::max);
        let largest = (0..3)
            .map(|k| min[k].abs().max(max[k].abs()))
            .fold(0.0, f64::max);
        let fit_applied = match self.options.fit {
            Fit::Auto if largest <= 1024.0 && radius >= 1.0 / 64.0 => Fit::Keep,
            Fit::Auto => Fit::Unit,
            f => f,
        };
        let (offset, scale) =
            if fit_applied == Fit::Unit && radius > 0.0 && (1.0 / radius).is_finite() {
                (center.map(|c| -c), 1.0 / radius)
            } else {
                ([0.0; 3], 1.0)
            };
        if fit_applied == Fit::Keep {
            for value in [min, max].iter().flatten() {
                if to_fixed(*value).is_none() {
                    return Err(whole(ErrorKind::OutOfFixedRange {
                        what: "position",
                        value: *value,
                    }));
                }
            }
        }
        let positions: Vec<[f32; 3]> = corners
            .iter()
            .map(|c| {
                let p = source_pos(c);
                std::array::from_fn(|k| ((p[k] + offset[k]) * scale) as f32)
            })
            .collect();
        // Triangles that 16.16 rounding flattens (far smaller than the
        // model): kept, but worth knowing about.
        let fixed: Vec<[i128; 3]> = positions
            .iter()
            .map(|p| p.map(|c| to_fixed_saturating(c) as i128))
            .collect();
        let collapsed = triangles
            .iter()
            .filter(|t| {
                let [a, b, c] = t.map(|i| fixed[i as usize]);
                let (u, v) = (
                    [0, 1, 2].map(|k| b[k] - a[k]),
                    [0, 1, 2].map(|k| c[k] - a[k]),
                );
                u[1] * v[2] == u[2] * v[1]
                    && u[2] * v[0] == u[0] * v[2]
                    && u[0] * v[1] == u[1] * v[0]
            })
            .count();
        if collapsed > 0 {
            warnings.push(format!(
                "{collapsed} triangle(s) have no area at 16.16 resolution \
                 (too small for the model's size)"
            ));
        }
        let (min, max) = bounds(positions.iter().map(|p| p.map(f64::from)));
        let center: [f64; 3] = std::array::from_fn(|k| (min[k] + max[k]) / 2.0);
        let radius = positions
            .iter()
            .map(|p| length(sub(p.map(f64::from), center)))
            .fold(0.0, f64::max);

        // Normals.
        let given = |c: &Corner| -> Option<[f64; 3]> {
            let n = self.normals.get(c[2] as usize)?.map(f64::from);
            normalize(n)
        };
        let all_given = corners.iter().all(|c| given(c).is_some());
        let any_given = corners.iter().any(|c| c[2] != NONE);
        let normals: Vec<[f32; 3]> = if all_given {
            corners
                .iter()
                .map(|c| given(c).unwrap_or([0.0, 0.0, 1.0]).map(|x| x as f32))
                .collect()
        } else if self.options.compute_normals {
            let mut sums = vec![[0.0f64; 3]; self.positions.len()];
            let mut first: Vec<Option<[f64; 3]>> = vec![None; self.positions.len()];
            for tri in &triangles {
                let [a, b, c] = tri.map(|i| source_pos(&corners[i as usize]));
                let n = cross(sub(b, a), sub(c, a));
                for &i in tri {
                    let v = corners[i as usize][0] as usize;
                    sums[v] = add(sums[v], n);
                    first[v].get_or_insert(n);
                }
            }
            corners
                .iter()
                .map(|c| {
                    let v = c[0] as usize;
                    given(c)
                        .or_else(|| normalize(sums[v]))
                        .or_else(|| first[v].and_then(normalize))
                        .unwrap_or([0.0, 0.0, 1.0])
                        .map(|x| x as f32)
                })
                .collect()
        } else {
            if any_given {
                warnings.push(
                    "some vertices have no usable `vn` and normal computation is off; normals dropped"
                        .to_string(),
                );
            }
            Vec::new()
        };

        // Texture coordinates.
        let missing_uv = corners.iter().filter(|c| c[1] == NONE).count();
        let uvs: Vec<[f32; 2]> = if missing_uv == corners.len() {
            Vec::new()
        } else {
            if missing_uv > 0 {
                warnings.push(format!(
                    "{missing_uv} vertices have no `vt`; their texture coordinates are (0, 0)"
                ));
            }
            corners
                .iter()
                .map(|c| {
                    self.texcoords
                        .get(c[1] as usize)
                        .copied()
                        .unwrap_or([0.0; 2])
                })
                .collect()
        };

        // Colours.
        let color = |c: &Corner| self.colors.get(c[0] as usize).copied().flatten();
        let missing_color = corners.iter().filter(|c| color(c).is_none()).count();
        let colors: Vec<[u8; 3]> = if missing_color == corners.len() {
            Vec::new()
        } else {
            if missing_color > 0 {
                warnings.push(format!(
                    "{missing_color} vertices have no colour; they are white"
                ));
            }
            corners
                .iter()
                .map(|c| color(c).unwrap_or([1.0; 3]).map(unit_to_u8))
                .collect()
        };

        if self.degenerate > 0 {
            warnings.push(format!(
                "dropped {} degenerate triangle(s) (no area)",
                self.degenerate
            ));
        }
        for (keyword, count) in &self.ignored {
            warnings.push(format!(
                "ignored {count} `{}` statement(s)",
                escape_controls(&clip(keyword))
            ));
        }

        let mut model = Model {
            source: self.path.to_path_buf(),
            options: self.options.clone(),
            fit_applied,
            positions,
            normals,
            uvs,
            colors,
            triangles,
            groups,
            clusters: Vec::new(),
            bounds: Aabb {
                min: min.map(|x| x as f32),
                max: max.map(|x| x as f32),
            },
            sphere: Sphere {
                center: center.map(|x| x as f32),
                radius: radius as f32,
            },
            offset,
            scale,
            degenerate: self.degenerate,
            files: self.files,
            warnings,
        };
        // Last, on the final arrays: the layout changes, the data does not.
        if self.options.cluster_triangles > 0 {
            model
                .cluster(self.options.cluster_triangles)
                .map_err(whole)?;
        }
        Ok(model)
    }
}
