//! The procedural meshes: integer trigonometry against `f64`, and knots that
//! are closed, outward-facing and built the same at compile time and at run
//! time.

use fixed::types::I16F16;
use microraster::shapes::{sin_cos_turns, torus_knot, torus_knot_data, torus_knot_size, MeshData};

#[test]
fn integer_sin_cos_match_f64() {
    let mut worst = 0.0f64;
    for k in 0..=40_000u64 {
        let turns = (k * (u32::MAX as u64) / 40_000) as u32;
        let a = turns as f64 / 4_294_967_296.0 * std::f64::consts::TAU;
        let (s, c) = sin_cos_turns(turns);
        let (s, c) = (
            s as f64 / (1u64 << 30) as f64,
            c as f64 / (1u64 << 30) as f64,
        );
        worst = worst.max((s - a.sin()).abs()).max((c - a.cos()).abs());
    }
    // Well below the 2^-16 step of the 16.16 results.
    assert!(worst < 2e-7, "worst error {worst}");
}

static KNOT: MeshData<256, 512> = match torus_knot_data(3, 2, 1.5, 0.4, 32, 8) {
    Ok(m) => m,
    Err(_) => panic!("valid parameters"),
};

#[test]
fn compile_time_knot_equals_run_time_knot() {
    let (nv, nt) = torus_knot_size(32, 8);
    let mut p = vec![[I16F16::ZERO; 3]; nv];
    let mut n = vec![[I16F16::ZERO; 3]; nv];
    let mut t = vec![[0u16; 3]; nt];
    torus_knot(3, 2, 1.5, 0.4, 32, 8, &mut p, &mut n, &mut t).unwrap();
    assert_eq!(p, KNOT.positions);
    assert_eq!(n, KNOT.normals);
    assert_eq!(t, KNOT.triangles);
    assert!(KNOT.mesh().is_ok());
}

#[test]
fn knot_normals_are_unit_and_point_away_from_the_curve() {
    for (p, n) in KNOT.positions.iter().zip(&KNOT.normals) {
        let n = n.map(|v| v.to_num::<f64>());
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        assert!((len - 1.0).abs() < 1e-4, "{len}");
        // The tube radius is 0.4: stepping back along the normal by it
        // lands on the knot's curve, whose points lie within radius 1.5.
        let c = [0, 1, 2].map(|k| p[k].to_num::<f64>() - 0.4 * n[k]);
        let r = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
        assert!(r <= 1.5 + 1e-3, "{r}");
    }
}

#[test]
fn sizes_must_match_the_resolution() {
    assert!(torus_knot_data::<256, 500>(3, 2, 1.5, 0.4, 32, 8).is_err());
    assert!(torus_knot_data::<255, 512>(3, 2, 1.5, 0.4, 32, 8).is_err());
    assert!(torus_knot_data::<256, 512>(3, 2, f32::NAN, 0.4, 32, 8).is_err());
    assert!(torus_knot_data::<256, 512>(3, 2, 1.5, -0.4, 32, 8).is_err());
}
