//! Links the firmware with esp-hal's `linkall.x` (the ESP32-C3's memory map
//! and runtime, which esp-hal's build script puts on the search path),
//! whatever directory cargo runs from: the argument is given here rather
//! than in `.cargo/config.toml`, which cargo reads only from its working
//! directory upwards, never from a `--manifest-path`.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rustc-link-arg-bins=-Tlinkall.x");
}
