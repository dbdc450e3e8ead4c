//! Everything a program needs is reachable through the crate itself: the
//! `fixed` and `embedded-graphics` versions it was built with (so a user
//! cannot pick mismatched ones), the lighting, texturing and shader types in
//! the prelude, and what a sink implementation names.

use microraster::embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use microraster::fixed::types::I16F16;
use microraster::prelude::*;

/// A sink written against the crate's re-exports only.
struct CountPixels(usize);

impl<C: PixelColor> TileSink<C> for CountPixels {
    type Error = core::convert::Infallible;
    fn write_tile(&mut self, area: &Rectangle, tile: &TileView<'_, C>) -> Result<(), Self::Error> {
        assert_eq!(area.size.width as usize, tile.width());
        self.0 += tile.width() * tile.height();
        Ok(())
    }
}

#[test]
fn the_prelude_names_lights_textures_and_shaders() {
    let sun = [DirectionalLight::new(
        Vec3::new(0.0, 1.0, 1.0),
        Rgb888::new(255, 255, 255),
    )];
    let lamp = [PointLight::new(
        Vec3::new(1.0, 1.0, 1.0),
        Rgb888::new(255, 200, 100),
        3.0,
    )];
    let lighting = Lighting::new(Rgb888::new(30, 30, 30))
        .directional(&sun)
        .point(&lamp);
    let material = Material::new().shininess(8);
    let texels = [0u16; 4];
    let texture = Texture::new(2, 2, Texels::Rgb565(&texels))
        .unwrap()
        .filter(Filter::Nearest);

    let p = |x: f32, y: f32| [I16F16::from_num(x), I16F16::from_num(y), I16F16::ZERO];
    let positions = [p(-0.5, -0.5), p(0.5, -0.5), p(0.0, 0.5)];
    let uvs = [[I16F16::ZERO; 2]; 3];
    let triangles = [[0u16, 1, 2]];
    let mesh = Mesh::new(&positions, &triangles)
        .unwrap()
        .with_uvs(&uvs)
        .unwrap();
    let draws = [Draw::new(&mesh)
        .shading(Shading::Shader)
        .texture(&texture)
        .material(material)];
    let scene = Scene::new(Camera::new(Mat4::IDENTITY, Mat4::IDENTITY), &draws)
        .lighting(&lighting)
        .shader(&TexturedLit);
    let mut renderer: Renderer<Rgb565, 8, 8> =
        Renderer::new(Config::new(Size::new(16, 16), Rgb565::new(0, 0, 0)));
    let mut workspace: Workspace<8, 16, 4> = Workspace::new();
    let mut sink = CountPixels(0);
    renderer.render(&mut workspace, &scene, &mut sink).unwrap();
    assert_eq!(sink.0, 16 * 16);

    // The shader interface and the other built-in shaders, by name.
    fn shades<S: FragmentShader<Rgb565>>(_: &S) {}
    shades(&Textured);
    shades(&DepthShade::new(0, 65_535));
    shades(&Normals);
    shades(&Flat);
    shades(&Gouraud);
    shades(&Dithered(Gouraud));
    let _: fn(&VertexInput<'_>) -> [I16F16; 2] = |v| v.uv();
    let _: fn(&Fragment<'_, [I16F16; 0]>) -> [u8; 3] = |f| f.color;
}
