//! The built-in shaders' own span loops against the per-fragment path:
//! random triangles in perspective, random textures (every format, size,
//! filter and wrap), every perspective mode, opaque and blended, into
//! `Rgb565`, `Rgb888` and `Gray8` tiles. Each built-in is rendered once as
//! it is (its `shade_span`) and once wrapped in `PerFragment`, which keeps
//! the trait's default `shade_span` (its `fragment` at every pixel): the
//! images must be the same, pixel for pixel. The Gouraud shader, which
//! has no varyings, is also rendered with an unused varying, which keeps
//! it out of its colour-only loop: the colour must be the same.

mod support;

use embedded_graphics::pixelcolor::{Gray8, PixelColor, Rgb565, Rgb888};
use fixed::types::I16F16;
use microraster::mesh::Vec3Fx;
use microraster::prelude::*;
use microraster::scene::Draw as SceneDraw;
use microraster::shader::{Fragment, ShaderError, VertexInput};
use microraster::texture::{FromTexel, Wrap};
use proptest::prelude::*;
use support::Capture;

const W: u32 = 48;
const H: u32 = 40;

/// Shader `S` through the default, per-fragment `shade_span`.
struct PerFragment<S>(S);

impl<C, S: FragmentShader<C>> FragmentShader<C> for PerFragment<S> {
    type Varyings = S::Varyings;
    const INTERPOLATE_COLOR: bool = S::INTERPOLATE_COLOR;
    fn check(&self, draw: &SceneDraw<'_>) -> Result<(), ShaderError> {
        self.0.check(draw)
    }
    fn vertex(&self, v: &VertexInput<'_>) -> S::Varyings {
        self.0.vertex(v)
    }
    fn fragment(&self, f: &Fragment<'_, S::Varyings>) -> Option<C> {
        self.0.fragment(f)
    }
}

/// Shader `S`, which has no varyings, with one unused varying: its spans
/// take the shared opaque loop that computes varyings and colour together
/// (`run_opaque`), where `S` alone may take a colour-only loop
/// (`run_colour_shifted`, on Thumb-2 or with `MICRORASTER_COLOUR_LOOP=1`).
struct WithVarying<S>(S);

impl<C, S: FragmentShader<C, Varyings = [I16F16; 0]>> FragmentShader<C> for WithVarying<S> {
    type Varyings = [I16F16; 1];
    const INTERPOLATE_COLOR: bool = S::INTERPOLATE_COLOR;
    fn check(&self, draw: &SceneDraw<'_>) -> Result<(), ShaderError> {
        self.0.check(draw)
    }
    fn vertex(&self, _: &VertexInput<'_>) -> [I16F16; 1] {
        [I16F16::ZERO]
    }
    fn fragment(&self, f: &Fragment<'_, [I16F16; 1]>) -> Option<C> {
        self.0.fragment(&Fragment {
            draw: f.draw,
            x: f.x,
            y: f.y,
            depth: f.depth,
            color: f.color,
            varyings: [],
            texture: f.texture,
        })
    }
}

/// One random case: triangles, their attributes, a texture and the modes.
#[derive(Clone, Debug)]
struct Case {
    positions: Vec<[f32; 3]>,
    uvs: Vec<[f32; 2]>,
    normals: Vec<[f32; 3]>,
    colors: Vec<[u8; 3]>,
    /// log2 or plain sides (`pow2` chooses), format 0..4, filter, wraps.
    side: [u32; 2],
    pow2: bool,
    format: u8,
    bilinear: bool,
    wrap: [u8; 2],
    texels: Vec<u16>,
    /// Perspective mode (low two bits); bit 2 forces the fast texture.
    mode: u8,
    blend: u8,
    /// Through an orthographic camera (every vertex's `w` the same).
    ortho: bool,
}

prop_compose! {
    /// One to four triangles with their attributes, a texture and the modes.
    fn case()(n in 1usize..5)(
        positions in prop::collection::vec(
            (-1.5f32..1.5, -1.2f32..1.2, -6.0f32..-0.6).prop_map(|(x, y, z)| [x, y, z]),
            n * 3,
        ),
        uvs in prop::collection::vec((-2.0f32..3.0, -2.0f32..3.0).prop_map(|(u, v)| [u, v]), n * 3),
        normals in prop::collection::vec(
            (-1.2f32..1.2, -1.2f32..1.2, -1.2f32..1.2).prop_map(|(x, y, z)| [x, y, z]),
            n * 3,
        ),
        colors in prop::collection::vec(any::<[u8; 3]>(), n * 3),
        side in [1u32..6, 1u32..6],
        pow2 in any::<bool>(),
        format in 0u8..4,
        bilinear in any::<bool>(),
        wrap in [0u8..3, 0u8..3],
        texels in prop::collection::vec(any::<u16>(), 1024),
        mode in 0u8..8,
        blend in 0u8..3,
    ) -> Case {
        Case {
            positions, uvs, normals, colors, side, pow2, format, bilinear, wrap, texels, mode,
            blend, ortho: false,
        }
    }
}

fn fx(v: f32) -> I16F16 {
    I16F16::from_num(v)
}

fn camera(ortho: bool) -> Camera {
    let view = Mat4::look_at(
        Vec3::new(0.0, 0.0, 0.5),
        Vec3::new(0.0, 0.0, -3.0),
        Vec3::new(0.0, 1.0, 0.0),
    )
    .unwrap();
    if ortho {
        Camera::new(
            view,
            Mat4::orthographic(-1.6, 1.6, -1.3, 1.3, 0.2, 20.0).unwrap(),
        )
    } else {
        Camera::new(
            view,
            Mat4::perspective(1.2, W as f32 / H as f32, 0.2, 20.0).unwrap(),
        )
    }
}

/// Renders `c` with shader `s` into a `C` frame.
fn render<C, S>(c: &Case, s: &S) -> Vec<C>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + Default + core::fmt::Debug + 'static,
    S: FragmentShader<C>,
{
    render_as(c, s, Shading::Shader)
}

/// [`render`] with the draw's `shading` (the scene's shader `s` unused
/// unless it is [`Shading::Shader`]).
fn render_as<C, S>(c: &Case, s: &S, shading: Shading) -> Vec<C>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + Default + core::fmt::Debug + 'static,
    S: FragmentShader<C>,
{
    // Half the cases take the specialised loops' texture: `Rgb565`,
    // power-of-two sides, repeated.
    let mut c = c.clone();
    if c.mode & 4 != 0 {
        (c.format, c.pow2, c.wrap) = (0, true, [0, 0]);
    }
    let c = &c;
    let positions: Vec<Vec3Fx> = c.positions.iter().map(|p| p.map(fx)).collect();
    let uvs: Vec<[I16F16; 2]> = c.uvs.iter().map(|p| p.map(fx)).collect();
    let normals: Vec<Vec3Fx> = c.normals.iter().map(|p| p.map(fx)).collect();
    let colors: Vec<Rgb888> = c
        .colors
        .iter()
        .map(|&[r, g, b]| Rgb888::new(r, g, b))
        .collect();
    let tris: Vec<[u16; 3]> = (0..c.positions.len() as u16 / 3)
        .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
        .collect();
    let mesh = Mesh::new(&positions, &tris)
        .unwrap()
        .with_uvs(&uvs)
        .unwrap()
        .with_normals(&normals)
        .unwrap()
        .with_colors(&colors)
        .unwrap();
    let (w, h) = if c.pow2 {
        (1 << c.side[0], 1 << c.side[1])
    } else {
        (c.side[0] * 5 + 1, c.side[1] * 3 + 2)
    };
    let n = (w * h) as usize;
    let bytes: Vec<u8> = c.texels.iter().map(|&t| t as u8).collect();
    let palette: Vec<u16> = c.texels[..16].to_vec();
    let texels = match c.format {
        0 => Texels::Rgb565(&c.texels[..n]),
        1 => Texels::Gray8(&bytes[..n]),
        2 => Texels::Indexed8 {
            indices: &bytes[..n],
            palette: &c.texels[..256],
        },
        _ => {
            let nibbles: Vec<u8> = bytes.iter().map(|b| b & 0x77).collect();
            let stride = (w as usize).div_ceil(2);
            let indices = nibbles[..stride * h as usize].to_vec().leak();
            Texels::Indexed4 {
                indices,
                palette: palette.leak(),
            }
        }
    };
    let wrap = |k: u8| match k {
        0 => Wrap::Repeat,
        1 => Wrap::MirroredRepeat,
        _ => Wrap::ClampToEdge,
    };
    let texture = Texture::new(w, h, texels)
        .unwrap()
        .filter(if c.bilinear {
            Filter::Bilinear
        } else {
            Filter::Nearest
        })
        .wrap_uv(wrap(c.wrap[0]), wrap(c.wrap[1]));
    let blend = match c.blend {
        0 => Blend::Opaque,
        1 => Blend::Alpha(100),
        _ => Blend::Additive,
    };
    let draws = [Draw::new(&mesh)
        .shading(shading)
        .texture(&texture)
        .blend(blend)];
    let scene = Scene::new(camera(c.ortho), &draws).shader(s);
    let mode = [
        Perspective::Exact,
        Perspective::Quasi8,
        Perspective::Quasi16,
        Perspective::Affine,
    ][c.mode as usize & 3];
    let config = Config::new(Size::new(W, H), C::default())
        .cull(CullMode::None)
        .perspective(mode);
    let mut r: Renderer<C, 16, 16> = Renderer::new(config);
    let mut ws: Box<Workspace<64, 1024, 32>> = Box::new(Workspace::new());
    let mut frame = Capture::new(Size::new(W, H), C::default());
    r.render(&mut ws, &scene, &mut frame).unwrap();
    frame.pixels
}

/// Shader `s`'s span loop and its per-fragment path agree on `c`, in `C`.
fn agree<C, S>(c: &Case, s: S) -> Result<(), TestCaseError>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + Default + core::fmt::Debug + 'static,
    S: FragmentShader<C>,
{
    let fast = render::<C, S>(c, &s);
    let slow = render::<C, PerFragment<S>>(c, &PerFragment(s));
    same(&fast, &slow)
}

fn same<C: PartialEq>(a: &[C], b: &[C]) -> Result<(), TestCaseError> {
    let differ = a.iter().zip(b).filter(|(a, b)| a != b).count();
    prop_assert_eq!(differ, 0, "{} pixels differ", differ);
    Ok(())
}

fn every_builtin<C>(c: &Case) -> Result<(), TestCaseError>
where
    C: PixelColor + FromTexel + Into<Rgb888> + Default + core::fmt::Debug + 'static,
{
    agree::<C, _>(c, Textured)?;
    agree::<C, _>(c, TexturedLit)?;
    agree::<C, _>(c, Gouraud)?;
    same(
        &render::<C, _>(c, &Gouraud),
        &render::<C, _>(c, &WithVarying(Gouraud)),
    )?;
    agree::<C, _>(c, Flat)?;
    agree::<C, _>(c, Normals)?;
    agree::<C, _>(c, DepthShade::new(30_000, 64_000))?;
    Ok(())
}

prop_compose! {
    /// [`case`]'s triangles turned to face the camera, opaque, in exact
    /// perspective: their `w` differ by a few per cent, so most spans are
    /// long and keep `Q`'s bit count from end to end, and they take the
    /// opaque loops with the span's shift (`SHIFTED`, and the Gouraud
    /// shader's colour loop where `build.rs` selects it), which `case`'s
    /// steep triangles rarely reach.
    fn facing_case()(c in case(), zc in -4.0f32..-1.5, scale in 1.0f32..2.5) -> Case {
        let mut c = c;
        for p in &mut c.positions {
            // `p[2]` is in -6..-0.6: a tilt of at most 0.06 either way.
            *p = [p[0] * scale, p[1] * scale, zc + (p[2] + 3.3) * 0.02];
        }
        c.mode &= 4;
        c.blend = 0;
        c
    }
}

prop_compose! {
    /// [`facing_case`] with no tilt: every vertex at one depth, so `1 / w`
    /// is the same across each triangle and its spans' `Q` does not
    /// change (the exact loops' `FLAT_Q` weights, one reciprocal a span).
    fn flat_case()(c in case(), zc in -4.0f32..-1.5, scale in 1.0f32..2.5) -> Case {
        let mut c = c;
        for p in &mut c.positions {
            *p = [p[0] * scale, p[1] * scale, zc];
        }
        c.mode &= 4;
        c.blend = 0;
        c
    }
}

prop_compose! {
    /// [`facing_case`] in a quasi-perspective mode: long opaque spans of
    /// several segments, through the opaque quasi-perspective loops
    /// (`FragmentShader::shade_quasi_spans`: `TriangleSpans::each_quasi`,
    /// and `Textured`'s nearest loop of its own on power-of-two `Rgb565`
    /// textures).
    fn facing_quasi_case()(c in facing_case(), quasi16 in any::<bool>()) -> Case {
        let mut c = c;
        c.mode = if quasi16 { 2 } else { 1 };
        c
    }
}

prop_compose! {
    /// [`facing_case`] in affine mode: long opaque spans through the
    /// opaque affine loops (`FragmentShader::shade_affine_spans`, and
    /// `Textured`'s nearest loop with the sums stepped on power-of-two
    /// `Rgb565` textures).
    fn facing_affine_case()(c in facing_case()) -> Case {
        let mut c = c;
        c.mode = 3;
        c
    }
}

prop_compose! {
    /// [`case`] through an orthographic camera, in any mode, opaque or
    /// blended: every mode interpolates such a draw affinely, its opaque
    /// passes in the affine copy (`FragmentShader::shade_affine_spans`).
    fn ortho_case()(c in case()) -> Case {
        Case { ortho: true, ..c }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn orthographic_spans_match_the_per_fragment_path(c in ortho_case()) {
        every_builtin::<Rgb565>(&c)?;
        every_builtin::<Rgb888>(&c)?;
        every_builtin::<Gray8>(&c)?;
    }

    /// An opaque affine triangle's colour is the Gouraud shading's
    /// (`ColourPlanes::start`): through an orthographic camera, in any
    /// mode, the `Gouraud` shader draws what `Shading::Gouraud` draws (a
    /// blended Gouraud draw is drawn by that shader: the same too).
    #[test]
    fn affine_gouraud_shader_draws_the_gouraud_shading(c in ortho_case()) {
        fn check<C>(c: &Case) -> Result<(), TestCaseError>
        where
            C: PixelColor + From<Rgb888> + Into<Rgb888> + Default + core::fmt::Debug + 'static,
        {
            same(
                &render::<C, _>(c, &Gouraud),
                &render_as::<C, _>(c, &Gouraud, Shading::Gouraud),
            )
        }
        check::<Rgb565>(&c)?;
        check::<Rgb888>(&c)?;
        check::<Gray8>(&c)?;
    }

    #[test]
    fn span_loops_match_the_per_fragment_path(c in case()) {
        every_builtin::<Rgb565>(&c)?;
        every_builtin::<Rgb888>(&c)?;
        every_builtin::<Gray8>(&c)?;
    }

    #[test]
    fn long_opaque_spans_match_the_per_fragment_path(c in facing_case()) {
        every_builtin::<Rgb565>(&c)?;
        every_builtin::<Rgb888>(&c)?;
        every_builtin::<Gray8>(&c)?;
    }

    #[test]
    fn quasi_spans_match_the_per_fragment_path(c in facing_quasi_case()) {
        every_builtin::<Rgb565>(&c)?;
        every_builtin::<Rgb888>(&c)?;
        every_builtin::<Gray8>(&c)?;
    }

    #[test]
    fn affine_spans_match_the_per_fragment_path(c in facing_affine_case()) {
        every_builtin::<Rgb565>(&c)?;
        every_builtin::<Rgb888>(&c)?;
        every_builtin::<Gray8>(&c)?;
    }

    #[test]
    fn flat_spans_match_the_per_fragment_path(c in flat_case()) {
        every_builtin::<Rgb565>(&c)?;
        every_builtin::<Rgb888>(&c)?;
        every_builtin::<Gray8>(&c)?;
    }
}

/// Textures of one texel's width, of 2^20 texels (the most whose affine
/// spans take `Textured`'s nearest loop with the texel's index from
/// shifted sums on a 64-bit host) and of more (the general affine loop
/// there): through an orthographic camera, every built-in shader's spans
/// match its per-fragment path, pixel for pixel.
#[test]
fn affine_spans_of_narrow_and_large_textures_match_the_per_fragment_path() {
    // Fibonacci hashing: texels and colours that vary from one to the next.
    let hash = |i: usize| (i as u32).wrapping_mul(0x9e37_79b9) >> 7;
    for side in [[0, 4], [5, 0], [10, 10], [11, 10]] {
        let n = 1usize << (side[0] + side[1]);
        let case = Case {
            // Two triangles covering most of the frame, the texture
            // repeated a few times over them.
            positions: vec![
                [-1.5, -1.2, -2.0],
                [1.5, -1.2, -2.5],
                [1.4, 1.2, -3.0],
                [-1.5, -1.2, -2.0],
                [1.4, 1.2, -3.0],
                [-1.3, 1.1, -2.2],
            ],
            uvs: vec![
                [-1.3, -1.7],
                [2.6, -1.1],
                [2.9, 2.7],
                [-1.3, -1.7],
                [2.9, 2.7],
                [-1.9, 2.2],
            ],
            normals: vec![[0.2, 0.3, 1.0]; 6],
            colors: (0..6)
                .map(|i| {
                    let c = hash(i + 1);
                    [c as u8, (c >> 8) as u8, (c >> 16) as u8]
                })
                .collect(),
            side,
            pow2: true,
            format: 0,
            bilinear: false,
            wrap: [0, 0],
            texels: (0..n.max(1024)).map(|i| hash(i) as u16).collect(),
            // Affine, the specialised loops' texture.
            mode: 3 | 4,
            blend: 0,
            ortho: true,
        };
        every_builtin::<Rgb565>(&case).unwrap();
        every_builtin::<Rgb888>(&case).unwrap();
    }
}
