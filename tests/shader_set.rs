//! Several fragment shaders in one scene, picked per draw: each draw is
//! coloured by its own shader, exactly as when it is drawn alone with that
//! shader, and `Fragment::draw` tells a shared shader which draw it shades.

mod support;

use embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
use fixed::types::I16F16;
use microraster::prelude::*;
use microraster::shader::{Fragment, VertexInput};
use microraster::texture::Texels;
use support::Capture;

const SIZE: Size = Size::new(96, 64);

/// A checkerboard from the texture coordinates: 4 squares per unit.
struct Checker;

impl FragmentShader<Rgb565> for Checker {
    type Varyings = [I16F16; 2];
    const INTERPOLATE_COLOR: bool = false;
    fn vertex(&self, v: &VertexInput<'_>) -> [I16F16; 2] {
        v.uv()
    }
    fn fragment(&self, f: &Fragment<'_, [I16F16; 2]>) -> Option<Rgb565> {
        let [u, v] = f.varyings;
        let odd = ((u.to_bits() >> 14) ^ (v.to_bits() >> 14)) & 1 == 1;
        Some(if odd { Rgb565::YELLOW } else { Rgb565::BLUE })
    }
}

/// One colour per draw, from `Fragment::draw`.
struct ByDraw;

impl ByDraw {
    const COLORS: [Rgb565; 6] = [
        Rgb565::RED,
        Rgb565::GREEN,
        Rgb565::CYAN,
        Rgb565::MAGENTA,
        Rgb565::WHITE,
        Rgb565::new(31, 32, 0),
    ];
}

impl FragmentShader<Rgb565> for ByDraw {
    type Varyings = [I16F16; 0];
    const INTERPOLATE_COLOR: bool = false;
    fn vertex(&self, _: &VertexInput<'_>) -> [I16F16; 0] {
        []
    }
    fn fragment(&self, f: &Fragment<'_, [I16F16; 0]>) -> Option<Rgb565> {
        Some(Self::COLORS[f.draw % Self::COLORS.len()])
    }
}

fn fx(v: f32) -> I16F16 {
    I16F16::from_num(v)
}

/// A unit quad's corners and texture coordinates.
const POSITIONS: [[f32; 3]; 4] = [
    [-0.5, -0.5, 0.0],
    [0.5, -0.5, 0.0],
    [0.5, 0.5, 0.0],
    [-0.5, 0.5, 0.0],
];
const TRIANGLES: [[u16; 3]; 2] = [[0, 1, 2], [0, 2, 3]];

/// Placed at column `k` of 3 and row `r` of 2 in normalised device
/// coordinates (the camera is the identity).
fn at(k: usize, r: usize) -> Mat4 {
    Mat4::translation(Vec3::new(-0.66 + 0.66 * k as f32, 0.5 - r as f32, 0.0))
        * Mat4::scale(Vec3::new(0.6, 0.9, 1.0))
}

fn render<S: ShaderSet<Rgb565>>(scene: &Scene<'_, S>) -> Capture<Rgb565> {
    let mut r: Renderer<Rgb565, 16, 16> = Renderer::new(Config::new(SIZE, Rgb565::BLACK));
    let mut ws: Box<Workspace<64, 256, 16>> = Box::default();
    let mut cap = Capture::new(SIZE, Rgb565::BLACK);
    r.render(&mut ws, scene, &mut cap)
        .expect("the scene renders");
    cap
}

#[test]
fn each_draw_is_coloured_by_the_shader_it_picks() {
    let pos = POSITIONS.map(|p| p.map(fx));
    let uvs = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]].map(|p: [f32; 2]| p.map(fx));
    let colors = [
        Rgb888::new(255, 0, 0),
        Rgb888::new(0, 255, 0),
        Rgb888::new(0, 0, 255),
        Rgb888::new(255, 255, 0),
    ];
    let mesh = Mesh::new(&pos, &TRIANGLES)
        .unwrap()
        .with_uvs(&uvs)
        .unwrap()
        .with_colors(&colors)
        .unwrap();
    let texels: Vec<u16> = (0..64u16).map(|i| i.wrapping_mul(0x0841) | 0x1f).collect();
    let tex = Texture::new(8, 8, Texels::Rgb565(&texels)).unwrap();
    let camera = Camera::new(Mat4::IDENTITY, Mat4::IDENTITY);
    // Two custom shaders and two built-ins, picked per draw; one Gouraud
    // draw without a shader, and one more draw of the shared shader.
    let draws = [
        Draw::new(&mesh).transform(at(0, 0)).shader(0),
        Draw::new(&mesh).transform(at(1, 0)).shader(1),
        Draw::new(&mesh).transform(at(2, 0)).shader(2).texture(&tex),
        Draw::new(&mesh).transform(at(0, 1)).shader(3),
        Draw::new(&mesh).transform(at(1, 1)),
        Draw::new(&mesh).transform(at(2, 1)).shader(1),
    ];
    let set = (Checker, ByDraw, Textured, Gouraud);
    let all = render(&Scene::new(camera, &draws).shaders(set));

    // Each draw alone, with its shader as the scene's only one (index 0).
    let alone = |k: usize, draw: &Draw<'_>| -> Capture<Rgb565> {
        if draw.shading != Shading::Shader {
            return render(&Scene::new(camera, &[*draw]));
        }
        let d = [draw.shader(0)];
        match draw.shader {
            0 => render(&Scene::new(camera, &d).shader(&Checker)),
            1 => render(&Scene::new(camera, &d).shader(&ByDraw)),
            2 => render(&Scene::new(camera, &d).shader(&Textured)),
            3 => render(&Scene::new(camera, &d).shader(&Gouraud)),
            _ => unreachable!("draw {k} picks a shader the set has"),
        }
    };
    let mut covered = 0;
    for (k, draw) in draws.iter().enumerate() {
        let one = alone(k, draw);
        let by_draw = draw.shading == Shading::Shader && draw.shader == 1;
        let mut mine = 0;
        for y in 0..SIZE.height {
            for x in 0..SIZE.width {
                let mut c = one.get(x, y);
                // ByDraw alone sees draw 0; in the scene, draw k.
                if by_draw && c == ByDraw::COLORS[0] {
                    c = ByDraw::COLORS[k];
                }
                if c != Rgb565::BLACK {
                    mine += 1;
                    assert_eq!(all.get(x, y), c, "draw {k} at ({x}, {y})");
                }
            }
        }
        assert!(mine > 100, "draw {k} covers {mine} pixels");
        covered += mine;
    }
    // The quads do not overlap, and nothing else is drawn.
    let lit = all.pixels.iter().filter(|&&c| c != Rgb565::BLACK).count();
    assert_eq!(lit, covered);
    // The shared shader told its two draws apart.
    let find = |c: Rgb565| all.pixels.iter().filter(|&&p| p == c).count();
    assert!(find(ByDraw::COLORS[1]) > 100);
    assert!(find(ByDraw::COLORS[5]) > 100);
}

#[test]
fn shaders_by_reference_and_transparent_draws_pick_theirs_too() {
    let pos = POSITIONS.map(|p| p.map(fx));
    let mesh = Mesh::new(&pos, &TRIANGLES).unwrap();
    let camera = Camera::new(Mat4::IDENTITY, Mat4::IDENTITY);
    let (by_draw, flat) = (ByDraw, Flat);
    let draws = [
        Draw::new(&mesh).transform(at(0, 0)).shader(1),
        Draw::new(&mesh)
            .transform(at(1, 0))
            .color(Rgb888::new(0, 0, 255))
            .shader(0)
            .blend(Blend::Additive),
        Draw::new(&mesh)
            .transform(at(2, 0))
            .shader(1)
            .blend(Blend::Additive),
    ];
    let all = render(&Scene::new(camera, &draws).shaders((&flat, &by_draw)));
    let mid = |k: usize| all.get(16 + 32 * k as u32, SIZE.height / 4);
    assert_eq!(mid(0), ByDraw::COLORS[0]);
    assert_eq!(mid(1), Rgb565::BLUE, "flat blue added to black");
    assert_eq!(mid(2), ByDraw::COLORS[2], "cyan added to black");
}
