//! The frame-buffer sink: the same picture as any other sink, placed tile
//! by tile into the caller's slice, and typed errors for a buffer of the
//! wrong length and for tiles outside it.

mod support;

use embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
use fixed::types::I16F16;
use microraster::prelude::*;
use microraster::sink::{FrameBuffer, FrameBufferError};

fn triangle() -> ([[I16F16; 3]; 3], [[u16; 3]; 1]) {
    let p = |x: f32, y: f32| [I16F16::from_num(x), I16F16::from_num(y), I16F16::ZERO];
    ([p(-0.9, -0.7), p(0.8, -0.9), p(0.1, 0.9)], [[0, 1, 2]])
}

/// Renders the triangle into `sink` at `size`, in 16x8 tiles (so that the
/// frames below have partial tiles at the right and the bottom).
fn render<S: TileSink<Rgb565>>(
    size: Size,
    sink: &mut S,
) -> Result<FrameStats, RenderError<S::Error>> {
    let (positions, triangles) = triangle();
    let mesh = Mesh::new(&positions, &triangles).unwrap();
    let draws = [Draw::new(&mesh).color(Rgb888::new(250, 120, 30))];
    let scene = Scene::new(Camera::new(Mat4::IDENTITY, Mat4::IDENTITY), &draws);
    let mut renderer: Renderer<Rgb565, 16, 8> =
        Renderer::new(Config::new(size, Rgb565::new(2, 4, 8)));
    let mut workspace: Workspace<8, 64, 64> = Workspace::new();
    renderer.render(&mut workspace, &scene, sink)
}

#[test]
fn places_every_tile_like_a_draw_target() {
    let size = Size::new(37, 21);
    let mut expected = support::Capture::new(size, Rgb565::WHITE);
    render(size, &mut expected).unwrap();

    let mut pixels = [Rgb565::WHITE; 37 * 21];
    let mut frame = FrameBuffer::new(&mut pixels, size).unwrap();
    let stats = render(size, &mut frame).unwrap();
    assert_eq!(stats.drawn, 1);
    assert_eq!(frame.size(), size);
    assert_eq!(
        frame.pixel(18, 10),
        expected.pixels.get(10 * 37 + 18).copied()
    );
    assert_eq!(frame.pixel(37, 0), None);
    assert_eq!(pixels[..], expected.pixels[..]);
}

#[test]
fn a_buffer_of_the_wrong_length_is_an_error() {
    let mut pixels = [Rgb565::BLACK; 100];
    let e = FrameBuffer::new(&mut pixels, Size::new(10, 11)).unwrap_err();
    assert_eq!(
        e,
        FrameBufferError::WrongLength {
            size: Size::new(10, 11),
            len: 100
        }
    );
    assert_eq!(
        e.to_string(),
        "a 10x11 frame needs 110 pixels and the buffer holds 100"
    );
}

#[test]
fn tiles_outside_the_buffer_are_an_error() {
    // The renderer's frame is larger than the buffer.
    let mut pixels = [Rgb565::BLACK; 20 * 10];
    let mut frame = FrameBuffer::new(&mut pixels, Size::new(20, 10)).unwrap();
    let e = render(Size::new(24, 10), &mut frame).unwrap_err();
    let RenderError::Sink(e) = e else {
        panic!("expected the sink's error, got {e:?}")
    };
    assert_eq!(
        e,
        FrameBufferError::TileOutside {
            area: Rectangle::new(Point::new(16, 0), Size::new(8, 8)),
            size: Size::new(20, 10),
        }
    );
    assert_eq!(
        e.to_string(),
        "the 8x8 tile at (16, 0) reaches outside the 20x10 frame buffer"
    );
}
