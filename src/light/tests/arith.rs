//! The fixed-point arithmetic of lighting (`light::arith`): square roots,
//! reciprocal square roots, powers, attenuation and fog against exact or
//! `f64` references.

use super::*;

#[test]
fn isqrt_is_exact() {
    for x in 0..1u64 << 20 {
        let r = isqrt(x);
        assert!(r * r <= x && (r + 1) * (r + 1) > x, "{x}");
    }
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    for _ in 0..200_000 {
        let x = rng.next() >> (rng.next() % 64);
        let r = isqrt(x) as u128;
        assert!(r * r <= x as u128 && (r + 1) * (r + 1) > x as u128, "{x}");
    }
    for k in 1..=u32::MAX as u64 >> 16 {
        let k = k << 16 | 0xffff;
        assert_eq!(isqrt(k * k), k);
        assert_eq!(isqrt(k * k - 1), k - 1);
    }
    assert_eq!(isqrt(u64::MAX), u32::MAX as u64);
}

#[test]
fn rsqrt_table_is_exactly_rounded() {
    for (k, row) in RSQRT.iter().enumerate() {
        for (i, &e) in row.iter().enumerate() {
            let m = (1 << k) as f64 * (1.0 + i as f64 / 128.0);
            let exact = 65536.0 / m.sqrt();
            let v = e as f64 + 32768.0;
            assert!((v - exact).abs() <= 0.5, "{k} {i}: {v} {exact}");
        }
    }
}

/// Over the whole domain `[2^30, 2^32)` at a fine stride, both
/// octaves' ends, and at random.
#[test]
fn rsqrt_error_is_bounded() {
    let mut worst = 0.0f64;
    let mut worst_rel = 0.0f64;
    let mut check = |s: u32| {
        let r = rsqrt(s) as f64;
        let exact = 2f64.powi(31) / (s as f64).sqrt();
        worst = worst.max((r - exact).abs());
        worst_rel = worst_rel.max((r / exact - 1.0).abs());
    };
    let mut s = 1u64 << 30;
    while s < 1 << 32 {
        check(s as u32);
        s += 1021;
    }
    for s in [1u32 << 30, (1 << 31) - 1, 1 << 31, u32::MAX] {
        check(s);
    }
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for _ in 0..1_000_000 {
        check((rng.next() as u32) | 1 << 30);
    }
    println!("rsqrt: {worst} units, {worst_rel} relative");
    assert!(worst <= 1.25, "{worst}");
}

#[test]
fn div255_is_exact() {
    // The final correction, over every remainder it can see.
    for r in 0..1100u32 {
        assert_eq!((r + 1 + (r >> 8)) >> 8, r / 255, "{r}");
    }
    for x in 0..1u32 << 24 {
        assert_eq!(div255(x), x / 255, "{x}");
    }
    let mut rng = Rng(0x1234_5678_9abc_def1);
    for _ in 0..1_000_000 {
        let x = rng.next() as u32;
        assert_eq!(div255(x), x / 255, "{x}");
    }
    for x in (u32::MAX - 70_000)..=u32::MAX {
        assert_eq!(div255(x), x / 255, "{x}");
    }
}

#[test]
fn normalize_finds_direction_and_length() {
    let mut rng = Rng(0x0dd_ba11_cafe_f00d);
    let mut worst_dir = 0.0f64;
    let mut worst_len = 0.0f64;
    for _ in 0..200_000 {
        let mag = rng.log(1.0, 2f64.powi(61));
        let d = rng.dir();
        let v = d.map(|c| (c * mag).round() as i64);
        let Some(u) = normalize(v) else {
            assert_eq!(v, [0; 3]);
            continue;
        };
        let exact = v.map(|c| c as f64);
        let len = dot(exact, exact).sqrt();
        let e = norm(exact).unwrap();
        for (&d, e) in u.dir.iter().zip(e) {
            worst_dir = worst_dir.max((d as f64 / 65536.0 - e).abs());
        }
        let l = u.len as f64 * 2f64.powi(u.exp);
        worst_len = worst_len.max((l / len - 1.0).abs());
        assert!((1 << 15..=1 << 16).contains(&u.len), "{u:?}");
    }
    assert_eq!(normalize([0; 3]), None);
    // Small integer vectors are exact up to rounding of the direction.
    assert_eq!(
        normalize([0, 0, -1]),
        Some(Unit {
            dir: [0, 0, -65536],
            len: 1 << 15,
            exp: -15
        })
    );
    println!("direction {worst_dir}, length {worst_len}");
    assert!(worst_dir < 4.5e-5, "{worst_dir}");
    assert!(worst_len < 6.5e-5, "{worst_len}");
}

#[test]
fn pow_matches_f64() {
    let mut worst = [0.0f64; 256];
    for e in 0..=255u8 {
        for k in 0..=2048u32 {
            let x = (k * 32).min(ONE);
            for x in [x, x.saturating_sub(7), x.saturating_sub(1)] {
                let exact = (x as f64 / 65536.0).powi(e as i32);
                let got = pow(x, e) as f64 / 65536.0;
                let w = &mut worst[e as usize];
                *w = w.max((got - exact).abs());
            }
        }
    }
    for (e, &w) in worst.iter().enumerate() {
        // Rounding errors of the products, amplified by the later
        // squarings: about e / 2^17.
        assert!(w <= (e as f64 + 2.0) / 131_072.0, "{e}: {w}");
    }
    assert_eq!(pow(0, 0), ONE);
    assert_eq!(pow(0, 1), 0);
    assert_eq!(pow(ONE, 255), ONE);
    assert_eq!(pow(ONE / 2, 1), ONE / 2);
    assert_eq!(pow(ONE / 2, 16), 1);
}

#[test]
fn exp2_matches_f64() {
    for (i, &e) in EXP2.iter().enumerate() {
        let exact = 65536.0 * 2f64.powf(-(i as f64) / 32.0);
        assert!((e as f64 - exact).abs() <= 0.5, "{i}");
    }
    let mut worst = 0.0f64;
    for q in (0..20u64 << 16).step_by(7) {
        let exact = 2f64.powf(-(q as f64) / 65536.0);
        let got = exp2_neg(q) as f64 / 65536.0;
        worst = worst.max((got - exact).abs());
    }
    // The interpolation's error, (1/32)² / 8 · ln(2)², plus roundings.
    assert!(worst < 7.5e-5, "{worst}");
    assert_eq!(exp2_neg(0), ONE);
    assert_eq!(exp2_neg(1 << 40), 0);
}

#[test]
fn attenuation_is_one_at_the_light_and_zero_at_the_range() {
    assert_eq!(attenuation(0), ONE);
    let mut last = ONE;
    for t in 0..ONE {
        let a = attenuation(t);
        assert!(a <= last, "{t}");
        let x = t as f64 / 65536.0;
        let exact = (1.0 - x * x).powi(2) * 65536.0;
        assert!((a as f64 - exact).abs() <= 1.5, "{t}");
        last = a;
    }
    assert_eq!(attenuation(ONE - 1), 0);

    // Through shade: a light of range 2 at distance 2 and beyond adds
    // nothing, one very close adds everything.
    let mat = Material::new();
    let n = [0, 0, 1 << 16];
    let shade_at = |z: f32, x: f32| {
        let lamp = [PointLight::new(
            Vec3::new(x, 0.0, z),
            Rgb888::new(200, 200, 200),
            2.0,
        )];
        let lighting = Lighting::new(Rgb888::new(20, 20, 20)).point(&lamp);
        let s: LightSetup<1> =
            LightSetup::new(&lighting, &Mat4::IDENTITY, Vec3::default()).unwrap();
        s.shade(&mat, [255; 3], [0; 3], n)
    };
    assert_eq!(shade_at(2.0, 0.0), [20; 3]);
    assert_eq!(shade_at(1.6, 1.2), [20; 3]);
    assert_eq!(shade_at(2.5, 0.0), [20; 3]);
    assert_eq!(shade_at(1e30, 0.0), [20; 3]);
    assert_eq!(shade_at(1.0 / 65536.0, 0.0), [220; 3]);
    assert_eq!(shade_at(1.999, 0.0), [20; 3]);
    assert!(shade_at(1.9, 0.0)[0] > 20);
    // Exactly at the light: no direction, no light.
    assert_eq!(shade_at(0.0, 0.0), [20; 3]);
}

#[test]
fn linear_fog_is_zero_at_the_eye_and_full_from_its_end() {
    let mat = Material::new();
    let fogged = |eye: f32| {
        let lighting = Lighting::new(Rgb888::new(100, 150, 200))
            .fog(Fog::Linear {
                start: 1.0,
                end: 5.0,
            })
            .fog_color(Rgb888::new(10, 20, 30));
        let s: LightSetup<0> =
            LightSetup::new(&lighting, &Mat4::IDENTITY, Vec3::new(0.0, 0.0, eye)).unwrap();
        s.shade(&mat, [255; 3], [0; 3], [0, 0, 1 << 16])
    };
    assert_eq!(fogged(0.0), [100, 150, 200]);
    assert_eq!(fogged(1.0), [100, 150, 200]);
    assert_eq!(fogged(3.0), [55, 85, 115]);
    assert_eq!(fogged(5.0), [10, 20, 30]);
    assert_eq!(fogged(5.001), [10, 20, 30]);
    assert_eq!(fogged(-7.0), [10, 20, 30]);
    assert_eq!(fogged(1e9), [10, 20, 30]);

    // The factor itself: 0 up to start, 1 from end on.
    let s: LightSetup<0> = LightSetup::new(
        &Lighting::new(Rgb888::BLACK).fog(Fog::Linear {
            start: 0.0,
            end: 3.0,
        }),
        &Mat4::IDENTITY,
        Vec3::default(),
    )
    .unwrap();
    let FixedFog::Linear { scale, offset } = s.core.fog else {
        panic!()
    };
    let f = |d: i64| {
        let q = normalize([d, 0, 0]).map_or(0, |u| scale.apply(u.len, u.exp));
        (q as i64 - offset).clamp(0, ONE as i64)
    };
    assert_eq!(f(0), 0);
    assert_eq!(f(3 << 16), ONE as i64);
    assert_eq!(f(4 << 16), ONE as i64);
    assert_eq!(f(3 << 15), ONE as i64 / 2);
}
