//! The examples' one-call PNG writer (`examples/common/png_file.rs`, on the
//! library's `FrameBuffer`): the file holds exactly the rendered frame.

#[path = "../examples/common/mod.rs"]
mod common;
mod support;

use common::*;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use microraster::prelude::*;

#[test]
fn render_png_writes_the_frame_that_a_draw_target_gets() {
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    let size = Size::new(96, 72);
    let d = draws(&knot, &cube, 0.4, Shading::Gouraud);
    let scene = Scene::new(camera(size.width, size.height), &d).light(light());
    let mut renderer: Renderer<Rgb565, 32, 32> = Renderer::new(Config::new(size, DEMO_CLEAR));
    let mut workspace = Box::new(Workspace::<2048, 4096, 16>::new());

    let mut expected = support::Capture::new(size, DEMO_CLEAR);
    renderer
        .render(&mut workspace, &scene, &mut expected)
        .unwrap();

    let dir = std::env::temp_dir().join(format!("microraster-png-{}", std::process::id()));
    let path = dir.join("nested").join("frame.png");
    let stats = render_png(&mut renderer, &mut workspace, &scene, &path).unwrap();
    assert!(stats.pixels_shaded > 100, "{stats:?}");
    let (read_size, pixels) = support::read_png(&path).expect("a PNG was written");
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(read_size, size);
    let want: Vec<Rgb888> = expected.to_rgb();
    assert_eq!(pixels, want);
}

#[test]
fn an_unwritable_path_is_a_one_line_error() {
    let pixels = [Rgb565::new(1, 2, 3); 4];
    let e = write_png(
        std::path::Path::new("/proc/microraster/none.png"),
        Size::new(2, 2),
        &pixels,
    )
    .unwrap_err();
    assert!(
        e.starts_with("cannot write /proc/microraster/none.png"),
        "{e}"
    );
    assert!(!e.contains('\n'), "{e}");
}
