//! The tile loop's shader path: a [`Shading::Shader`] draw's pairs drawn
//! through the shader the draw picks from the scene's set (a `match` on
//! its index, each shader with its own monomorphized loops), one pair at
//! a time ([`TileJob::with_shader`], [`TileJob::shaded`]) or an opaque
//! draw's run of pairs with the shader picked once
//! ([`TileJob::shader_runs`]). A triangle's varyings and clip `w` are not
//! kept by the vertex stage: they are evaluated again here, and a clipped
//! triangle's pieces get theirs interpolated at their corners.

use super::*;

impl<C, F, const TW: usize, const TH: usize> TileJob<'_, '_, C, F, TW, TH>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
    F: ShaderSet<C>,
{
    /// Draws triangle `idx` of the cursor's draw, a [`Shading::Shader`]
    /// draw, with the scene's shader that the draw picks, blended by
    /// `blend` (and then never writing depth). Each shader of the set has
    /// its own [`shaded`](Self::shaded) and span loop; picking one is a
    /// `match` on the index.
    #[inline(always)]
    pub(super) fn with_shader<P: Features>(
        &mut self,
        cur: &DrawCursor<'_>,
        idx: [u32; 3],
        any: u8,
        blend: Blend,
    ) -> u32 {
        let index = self.frame.draws[cur.draw].shader as usize;
        let set = self.to.shaders.set;
        let visit = WithShader::<'_, '_, '_, '_, C, F, P, TW, TH> {
            job: self,
            cur,
            idx,
            any,
            blend,
            features: core::marker::PhantomData,
        };
        // `begin` checked that every shader draw's index is in the set.
        set.visit(index, visit).unwrap_or(0)
    }

    /// [`general`](Self::general)'s run of pairs from global triangle `t`
    /// of the cursor's draw, an opaque [`Shading::Shader`] draw without
    /// lines: the draw's shader picked once for the run (see
    /// [`shader_run`](Self::shader_run)). Returns the count of pixels
    /// shaded and the entry after the run.
    #[inline(always)]
    pub(super) fn shader_runs<P: Features>(
        &mut self,
        cur: &DrawCursor<'_>,
        t: usize,
        list: &mut TileList<'_, '_, P>,
    ) -> (u32, Option<usize>) {
        let index = self.frame.draws[cur.draw].shader as usize;
        let set = self.to.shaders.set;
        let run = ShaderRun {
            job: self,
            cur,
            t,
            list,
        };
        // `begin` checked that every shader draw's index is in the set;
        // were it not, the pair would draw nothing, as `with_shader`'s.
        match set.visit(index, run) {
            Some(r) => r,
            None => (0, list.next()),
        }
    }

    /// Draws the pairs of a run of an opaque shader draw without lines,
    /// from global triangle `t` of the cursor's draw, while the entries of
    /// `list` belong to that draw, through shader pass `pass`: what
    /// [`shaded`](Self::shaded) does for each, with the draw's state, its
    /// set-up and the pass read or built once a run rather than once a
    /// pair (with `general`'s tests of the draw's kind and the shader's
    /// `match`: x86-64 `demo-textured-lit` 6,938,805 -> 6,660,917, about
    /// 107 a pair). A triangle that must be clipped goes to `shaded`.
    /// Returns the count of pixels shaded and the entry after the run.
    #[inline(never)]
    fn shader_run<G: FragmentShader<C>, P: Features>(
        &mut self,
        cur: &DrawCursor<'_>,
        mut t: usize,
        list: &mut TileList<'_, '_, P>,
        pass: ShaderPass<'_, C, G, TW, TH>,
    ) -> (u32, Option<usize>) {
        let shader = pass.shader;
        let frame = self.frame;
        let draw = &frame.draws[cur.draw];
        // The mesh and the vertices copied, so that their lengths are
        // read once a run, not again after each pair's calls (the mesh not
        // copied: M3 7,238,609, M4F 7,178,270). The cursor's vertices are
        // the draw's slice of the mesh's vertex count, and the copy's
        // positions are cut to their length (`Mesh::cut`): LLVM then knows
        // that an index of the vertices is one of the positions and drops
        // `clip_w`'s three bounds checks a pair, with no test of the two
        // counts and no fallback for counts that differ, which never
        // happens (where the counts were tested, once a run on x86-64 and
        // ARMv6-M with a cold copy of the loop drawing pair by pair, with
        // each pair's clip test on the Cortex-M3 and M4F: textured frame
        // x86-64 6,413,237 -> 6,412,731, M3 7,190,948 -> 7,185,926, M4F
        // 7,159,111 -> 7,147,533, but ARMv6-M 23,052,879 -> 23,065,447,
        // its loop's registers moved; the vertices sliced to the
        // positions' count instead: ARMv6-M 23,078,731).
        let verts = cur.verts;
        let (mesh, texture) = (draw.mesh.cut(verts.len()), draw.texture);
        let mesh = &mesh;
        // The draw's set-up, looked up once a run (and again after a
        // clipped triangle, whose path may build it in the cache), and
        // copied: LLVM then keeps only what `clip_w` reads of it (the
        // matrix's `w` column, no copy of the rest) as values of the run,
        // in registers or on its stack, where each pair reloaded them
        // from the cache after the pair's calls before (textured frame
        // x86-64 6,412,731 -> 6,408,329, M3 7,185,926 -> 7,181,556, M4F
        // 7,147,533 -> 7,145,591, ARMv6-M 23,065,447 -> 22,998,493).
        let mut setup = frame.setup(cur.draw, self.cache).copied();
        let pass = pass.constant_w(setup.is_some_and(|s| s.constant_w()));
        let mut n = 0;
        loop {
            let [i0, i1, i2] = cur.indices(t);
            let sv = [
                &verts[i0 as usize],
                &verts[i1 as usize],
                &verts[i2 as usize],
            ];
            let any = sv[0].outcode() | sv[1].outcode() | sv[2].outcode();
            if any & MUST_CLIP != 0 {
                n += self.shaded(cur, [i0, i1, i2], any, pass);
                setup = frame.setup(cur.draw, self.cache).copied();
            } else if let Some(setup) = &setup {
                // `fill_shaded`, with the varyings and `w` only for a pair
                // whose walk found spans (363 of this frame's 2,597 pairs
                // have none).
                let to = &mut self.to;
                let count = (pass.find)(&sv, to.rect, &mut to.found);
                if let Some(found) = drawn(&to.found, count, &mut to.rows) {
                    let vertex = |i: u32| {
                        shader.vertex(&VertexInput {
                            draw: cur.draw,
                            index: i as usize,
                            mesh,
                        })
                    };
                    // The varyings evaluated before `w`, not in the
                    // struct's order: LLVM then keeps fewer of the pair's
                    // values on the stack (M3 textured frame 7,273,975 ->
                    // 7,255,463, x86-64 6,458,510 -> 6,440,539).
                    let var = [vertex(i0), vertex(i1), vertex(i2)];
                    let tri = ShaderTriangle {
                        draw: cur.draw,
                        corners: Corners(sv),
                        w: [
                            setup.clip_w(mesh, i0 as usize),
                            setup.clip_w(mesh, i1 as usize),
                            setup.clip_w(mesh, i2 as usize),
                        ],
                        var,
                    };
                    n += (pass.shade)(to.tile, to.rect, &tri, found, shader, texture, pass.out);
                }
            }
            match list.next() {
                // A shader draw has no common path (`fast` is empty).
                Some(u) if u < cur.end => t = u,
                after => return (n, after),
            }
        }
    }

    /// Draws triangle `idx` of the cursor's draw, a [`Shading::Shader`] draw,
    /// through the frame's fragment shader: its varyings from the shader's
    /// vertex function and its `w` from the draw's transform, both evaluated
    /// again (the vertex buffer keeps neither), or, for a triangle that must
    /// be clipped, its pieces with varyings interpolated at their corners.
    #[inline(never)]
    pub(super) fn shaded<G: FragmentShader<C>>(
        &mut self,
        cur: &DrawCursor<'_>,
        idx: [u32; 3],
        any: u8,
        pass: ShaderPass<'_, C, G, TW, TH>,
    ) -> u32 {
        let shader = pass.shader;
        let frame = self.frame;
        let draw = &frame.draws[cur.draw];
        let mesh = draw.mesh;
        // (A draw without a set-up, whose vertices failed, draws nothing.)
        let Some(setup) = frame.setup(cur.draw, self.cache) else {
            return 0;
        };
        let pass = pass.constant_w(setup.constant_w());
        // Written out rather than `idx.map`: the map was left out of line,
        // a call per triangle and tile.
        let vertex = |i: u32| {
            shader.vertex(&VertexInput {
                draw: cur.draw,
                index: i as usize,
                mesh,
            })
        };
        let var = [vertex(idx[0]), vertex(idx[1]), vertex(idx[2])];
        let sv = [
            &cur.verts[idx[0] as usize],
            &cur.verts[idx[1] as usize],
            &cur.verts[idx[2] as usize],
        ];
        let flat = sv[0].color();
        if any & MUST_CLIP != 0 {
            let mut n = 0;
            let to = &mut self.to;
            frame.clipped_pieces(cur.draw, idx, any, flat, self.cache, &mut |piece, _| {
                let mut pv = piece.sv;
                // Flat colour stays the provoking vertex's, as on other paths.
                if !G::INTERPOLATE_COLOR {
                    pv[0].set_color(flat);
                }
                let tri = ShaderTriangle {
                    draw: cur.draw,
                    corners: Corners([&pv[0], &pv[1], &pv[2]]),
                    w: piece.w,
                    var: piece.bary.map(|b| lerp_varyings(&var, b)),
                };
                n += fill_shaded(to, &tri, draw.texture, &pass);
            });
            return n;
        }
        let tri = ShaderTriangle {
            draw: cur.draw,
            corners: Corners(sv),
            w: [
                setup.clip_w(mesh, idx[0] as usize),
                setup.clip_w(mesh, idx[1] as usize),
                setup.clip_w(mesh, idx[2] as usize),
            ],
            var,
        };
        fill_shaded(&mut self.to, &tri, draw.texture, &pass)
    }
}

/// [`TileJob::with_shader`]'s visit of the scene's shaders: draws the
/// triangle with the one the draw picks.
struct WithShader<'v, 'c, 'j, 'f, C, F, P, const TW: usize, const TH: usize>
where
    C: PixelColor + From<Rgb888> + 'static,
    F: ShaderSet<C>,
{
    job: &'v mut TileJob<'j, 'f, C, F, TW, TH>,
    cur: &'v DrawCursor<'c>,
    idx: [u32; 3],
    any: u8,
    blend: Blend,
    features: core::marker::PhantomData<P>,
}

impl<C, F, P, const TW: usize, const TH: usize> VisitShader<C>
    for WithShader<'_, '_, '_, '_, C, F, P, TW, TH>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
    F: ShaderSet<C>,
    P: Features,
{
    type Output = u32;
    #[inline(always)]
    fn visit<G: FragmentShader<C>>(self, shader: &G) -> u32 {
        let shade = self.job.to.shaders.custom::<G, P>(self.blend);
        let mut pass = self.job.to.shaders.pass(shader, shade, self.blend);
        if self.blend != Blend::Opaque {
            pass = pass.with(no_write(self.blend));
        }
        self.job.shaded(self.cur, self.idx, self.any, pass)
    }
}

/// [`TileJob::shader_runs`]' visit of the scene's shaders: draws the run
/// with the one the draw picks.
struct ShaderRun<'v, 'c, 'j, 'f, 'l, 'a, C, F, P, const TW: usize, const TH: usize>
where
    C: PixelColor + From<Rgb888> + 'static,
    F: ShaderSet<C>,
{
    job: &'v mut TileJob<'j, 'f, C, F, TW, TH>,
    cur: &'v DrawCursor<'c>,
    t: usize,
    list: &'v mut TileList<'l, 'a, P>,
}

impl<C, F, P, const TW: usize, const TH: usize> VisitShader<C>
    for ShaderRun<'_, '_, '_, '_, '_, '_, C, F, P, TW, TH>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
    F: ShaderSet<C>,
    P: Features,
{
    type Output = (u32, Option<usize>);
    #[inline(always)]
    fn visit<G: FragmentShader<C>>(self, shader: &G) -> Self::Output {
        let shade = self.job.to.shaders.custom::<G, P>(Blend::Opaque);
        let pass = self.job.to.shaders.pass(shader, shade, Blend::Opaque);
        self.job.shader_run(self.cur, self.t, self.list, pass)
    }
}

/// The varyings at barycentric weights `b` (of vertices 1 and 2,
/// [`BARY_ONE`] being 1) of a triangle whose vertices have `var`,
/// rounded to nearest.
fn lerp_varyings<V: Varyings>(var: &[V; 3], b: [i32; 2]) -> V {
    let mut out = V::zeroed();
    let [a0, a1, a2] = [var[0].as_slice(), var[1].as_slice(), var[2].as_slice()];
    for (k, o) in out.as_mut_slice().iter_mut().enumerate() {
        let base = a0[k].to_bits() as i128;
        let d1 = a1[k].to_bits() as i128 - base;
        let d2 = a2[k].to_bits() as i128 - base;
        let sum = d1 * b[0] as i128 + d2 * b[1] as i128 + (BARY_ONE as i128 >> 1);
        *o = I16F16::from_bits((base + (sum >> 30)) as i32);
    }
    out
}
