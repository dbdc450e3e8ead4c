//! The set-up: the scene light reproduced bit for bit, bad input as
//! typed errors, extreme normals, positions and scales, and the checks
//! without conversions agreeing with the general set-up.

use super::*;

/// The vertex stage's lighting before this module, copied.
fn old_light_vertex(
    dir: [i32; 3],
    color: [u32; 3],
    ambient: [u32; 3],
    n: [i32; 3],
    base: [u8; 3],
) -> [u8; 3] {
    let d = n[0] as i64 * dir[0] as i64 + n[1] as i64 * dir[1] as i64 + n[2] as i64 * dir[2] as i64;
    let ndotl = (d >> 24).clamp(0, 256) as u32;
    let mut out = [0u8; 3];
    for c in 0..3 {
        let intensity = ambient[c] * 256 + color[c] * ndotl;
        let v = (base[c] as u32 * intensity + 32_640) / 65_280;
        out[c] = v.min(255) as u8;
    }
    out
}

/// The old vertex stage's set-up of `scene::Light`, copied.
fn old_dir(model: &Mat4, direction: Vec3) -> [i32; 3] {
    let local = model
        .inverse_transform_vector(direction)
        .and_then(|v| v.normalize())
        .unwrap();
    let fx = |v: f32| (v * 65536.0) as i32;
    [fx(local.x), fx(local.y), fx(local.z)]
}

#[test]
fn reproduces_scene_light_bit_for_bit() {
    let mut rng = Rng(0x5eed_1234_abcd_0001);
    let mat = Material::new();
    let mut n_lit = 0;
    for case in 0..4_000 {
        let model = Mat4::rotation_y(rng.range(-3.0, 3.0) as f32)
            * Mat4::rotation_x(rng.range(-3.0, 3.0) as f32)
            * Mat4::scale(Vec3::new(
                rng.log(0.1, 10.0) as f32,
                rng.log(0.1, 10.0) as f32,
                rng.log(0.1, 10.0) as f32,
            ));
        let model = Mat4::translation(vec3([0.0; 3].map(|_| rng.range(-9.0, 9.0)))) * model;
        let direction = vec3(rng.dir().map(|c| c * rng.log(0.01, 100.0)));
        let light = crate::scene::Light::new(direction)
            .color(rng.color())
            .ambient(rng.color());
        let dl = [DirectionalLight::new(light.direction, light.color)];
        let lighting = Lighting::new(light.ambient).directional(&dl);
        let eye = vec3([0.0; 3].map(|_| rng.range(-50.0, 50.0)));
        let setup: LightSetup<3> = LightSetup::new(&lighting, &model, eye).unwrap();
        let dir = old_dir(&model, light.direction);
        let (color, ambient) = (
            rgb(light.color).map(u32::from),
            rgb(light.ambient).map(u32::from),
        );
        for k in 0..250 {
            // Unit normals as meshes hold them, and every few
            // vertices arbitrary bits.
            let normal = if k % 5 == 4 {
                let mut b = || (rng.next() as i32) >> (rng.next() % 32);
                [b(), b(), b()]
            } else {
                raw(rng.dir())
            };
            let base = [rng.byte(), rng.byte(), rng.byte()];
            let p = [rng.next() as i32, rng.next() as i32, rng.next() as i32];
            let expected = old_light_vertex(dir, color, ambient, normal, base);
            let got = setup.shade(&mat, base, p, normal);
            assert_eq!(got, expected, "case {case}: n {normal:?} base {base:?}");
            n_lit += (expected != old_light_vertex(dir, color, ambient, [0; 3], base)) as u32;
        }
    }
    assert!(n_lit > 300_000, "{n_lit}");
}

#[test]
fn bad_input_is_an_error() {
    let white = Rgb888::WHITE;
    let id = Mat4::IDENTITY;
    let eye = Vec3::new(0.0, 0.0, 5.0);
    let setup = |l: &Lighting<'_>| LightSetup::<2>::new(l, &id, eye).map(|_| ());
    let dir = |d: Vec3| [DirectionalLight::new(d, white)];
    for (i, d) in [
        Vec3::new(f32::NAN, 0.0, 1.0),
        Vec3::new(0.0, f32::INFINITY, 0.0),
        Vec3::default(),
    ]
    .into_iter()
    .enumerate()
    {
        let ok = DirectionalLight::new(Vec3::new(0.0, 1.0, 0.0), white);
        let lights = [ok, dir(d)[0]];
        assert_eq!(
            setup(&Lighting::new(white).directional(&lights)),
            Err(LightError::BadDirection { light: 1 }),
            "{i}"
        );
    }
    let point = |p: Vec3, r: f32| [PointLight::new(p, white, r)];
    for p in [
        Vec3::new(f32::NAN, 0.0, 0.0),
        Vec3::new(0.0, 0.0, f32::NEG_INFINITY),
    ] {
        assert_eq!(
            setup(&Lighting::new(white).point(&point(p, 1.0))),
            Err(LightError::BadPosition { light: 0 })
        );
    }
    for r in [0.0, -1.0, f32::NAN, f32::INFINITY, -0.0] {
        assert_eq!(
            setup(&Lighting::new(white).point(&point(Vec3::default(), r))),
            Err(LightError::BadRange { light: 0 }),
            "{r}"
        );
    }
    for fog in [
        Fog::Linear {
            start: 2.0,
            end: 2.0,
        },
        Fog::Linear {
            start: 3.0,
            end: 2.0,
        },
        Fog::Linear {
            start: f32::NAN,
            end: 2.0,
        },
        Fog::Linear {
            start: 0.0,
            end: f32::INFINITY,
        },
        Fog::Linear {
            start: -3e38,
            end: 3e38,
        },
        Fog::Exponential { density: -1.0 },
        Fog::Exponential { density: f32::NAN },
        Fog::Exponential {
            density: f32::INFINITY,
        },
    ] {
        assert_eq!(
            setup(&Lighting::new(white).fog(fog)),
            Err(LightError::BadFog),
            "{fog:?}"
        );
    }
    let three = dir(Vec3::new(1.0, 0.0, 0.0)).repeat(3);
    assert_eq!(
        setup(&Lighting::new(white).directional(&three)),
        Err(LightError::TooManyLights { count: 3, max: 2 })
    );
    let one_point = point(Vec3::default(), 1.0);
    let one_each = Lighting::new(white)
        .directional(&three[..1])
        .point(&one_point);
    assert_eq!(setup(&one_each), Ok(()));
    let two_points = [point(Vec3::default(), 1.0)[0]; 2];
    assert_eq!(
        setup(&one_each.point(&two_points)),
        Err(LightError::TooManyLights { count: 3, max: 2 })
    );
    for m in [
        Mat4::scale(Vec3::new(1.0, 0.0, 1.0)),
        Mat4::translation(Vec3::new(f32::NAN, 0.0, 0.0)),
    ] {
        assert_eq!(
            LightSetup::<1>::new(&Lighting::new(white), &m, eye).map(|_| ()),
            Err(LightError::BadMatrix)
        );
    }
    assert_eq!(
        LightSetup::<1>::new(&Lighting::new(white), &id, Vec3::new(f32::NAN, 0.0, 0.0)).map(|_| ()),
        Err(LightError::BadMatrix)
    );
    // Every error has a message.
    let e = LightError::TooManyLights { count: 3, max: 2 };
    assert_eq!(format!("{e}"), "3 lights exceed the capacity of 2");
}

/// Zero, huge and random normals, extreme positions, and lights and
/// eyes far out: a defined colour, never a panic (the tests run with
/// overflow checks).
#[test]
fn any_normal_and_position_gives_a_colour() {
    let mut rng = Rng(0x7777_1234_5678_9999);
    let dl = [
        DirectionalLight::new(Vec3::new(1.0, 2.0, 3.0), Rgb888::WHITE),
        DirectionalLight::new(Vec3::new(-1.0, 0.0, 0.0), Rgb888::new(9, 99, 199)),
    ];
    let pl = [
        PointLight::new(Vec3::new(30000.0, -30000.0, 0.0), Rgb888::WHITE, 1e5),
        PointLight::new(Vec3::new(1.0, 0.0, 0.0), Rgb888::new(255, 0, 0), 1e-4),
    ];
    let mat = Material::new()
        .specular(Rgb888::WHITE)
        .shininess(255)
        .diffuse(Rgb888::new(1, 128, 255));
    let mut seen = [0u32; 3];
    for fog in [
        Fog::None,
        Fog::Linear {
            start: 1.0,
            end: 1.000_001,
        },
        Fog::Exponential { density: 1e30 },
    ] {
        for model in [
            Mat4::IDENTITY,
            Mat4::scale(Vec3::new(1e-6, 1e-6, 1e-6)),
            Mat4::scale(Vec3::new(3e4, 3e4, 3e4)),
        ] {
            let lighting = Lighting::new(Rgb888::new(10, 20, 30))
                .directional(&dl)
                .point(&pl)
                .fog(fog)
                .fog_color(Rgb888::new(1, 2, 3));
            let s: LightSetup<4> =
                LightSetup::new(&lighting, &model, Vec3::new(-1e3, 2e3, 1e4)).unwrap();
            let edge = [
                0,
                1,
                -1,
                i32::MAX,
                i32::MIN,
                1 << 17,
                (1 << 17) + 1,
                -(1 << 17) - 1,
            ];
            for &a in &edge {
                for &b in &edge {
                    for &c in &edge {
                        let out = s.shade(&mat, [255, 128, 0], [a, b, c], [c, a, b]);
                        seen[0] += out[0] as u32;
                    }
                }
            }
            for _ in 0..20_000 {
                let mut r = || (rng.next() as i32) >> (rng.next() % 32);
                let out = s.shade(&mat, [255; 3], [r(), r(), r()], [r(), r(), r()]);
                seen[1] += out[1] as u32;
            }
            // A zero normal: ambient only (and fog).
            let z = s.shade(&mat, [255; 3], [0; 3], [0; 3]);
            seen[2] += z[2] as u32;
        }
    }
    assert!(seen.iter().all(|&s| s > 0), "{seen:?}");

    // Zero normal, no fog: exactly the ambient term.
    let lighting = Lighting::new(Rgb888::new(10, 20, 30))
        .directional(&dl)
        .point(&pl);
    let s: LightSetup<4> = LightSetup::new(&lighting, &Mat4::IDENTITY, Vec3::default()).unwrap();
    assert_eq!(s.shade(&mat, [255; 3], [0; 3], [0; 3]), [10, 20, 30]);
    // A huge normal: saturated diffuse light from the lights in front.
    assert_eq!(
        s.shade(
            &Material::new(),
            [255; 3],
            [0; 3],
            [i32::MAX, i32::MAX, i32::MAX]
        ),
        [255, 255, 255]
    );
}

#[test]
fn far_and_unreachable_lights_are_off() {
    let pl = [
        PointLight::new(Vec3::new(1e20, 0.0, 0.0), Rgb888::WHITE, 10.0),
        PointLight::new(Vec3::new(0.0, 0.0, 1.0), Rgb888::WHITE, 1e-9),
    ];
    let s: LightSetup<2> = LightSetup::new(
        &Lighting::new(Rgb888::BLACK).point(&pl),
        &Mat4::IDENTITY,
        Vec3::default(),
    )
    .unwrap();
    assert!(s.lights.iter().all(|l| l.source == Source::Off));
    assert_eq!(
        LightSetup::<2>::new(
            &Lighting::new(Rgb888::BLACK).point(&[PointLight::new(
                Vec3::default(),
                Rgb888::WHITE,
                1e30
            )]),
            &Mat4::IDENTITY,
            Vec3::default()
        )
        .map(|_| ()),
        Err(LightError::BadRange { light: 0 })
    );
}

#[test]
fn raw_positions_are_rounded() {
    for x in [189.1292f32, -189.1292, 0.3, -0.3, 32767.99, 1e6, -3.5e12] {
        let exact = (x as f64 * 65536.0).round() as i64;
        assert_eq!(to_raw(Vec3::new(x, 0.0, 0.0)), Some([exact, 0, 0]), "{x}");
    }
    // Half a raw unit rounds away from zero.
    let half = 0.5 / 65536.0;
    assert_eq!(to_raw(Vec3::new(half, -half, 0.0)), Some([1, -1, 0]));
    assert_eq!(to_raw(Vec3::new(f32::NAN, 0.0, 0.0)), None);
    assert_eq!(to_raw(Vec3::new(0.0, 2e13, 0.0)), None);
}

/// The coordinate by the bits is the `f32` formula it replaced, over
/// random bits and over values near the boundaries of its cases.
#[test]
fn raw_coordinates_by_the_bits_are_the_f32_formula() {
    fn reference(c: f32) -> Option<i64> {
        const LIMIT: f32 = (1u64 << 60) as f32;
        let x = c * 65536.0;
        if x.is_nan() || x.abs() > LIMIT {
            return None;
        }
        let half = if x.abs() >= 8_388_608.0 {
            0.0
        } else if x < 0.0 {
            -0.5
        } else {
            0.5
        };
        Some(crate::math::f32_to_i64(x + half))
    }
    let mut rng = Rng(0x2718_2818_2845_9045);
    for i in 0..400_000u32 {
        let c = match i % 3 {
            0 => f32::from_bits(rng.next() as u32),
            // Exponents 2^-22 to 2^49 (units of 2^-16): every case.
            _ => f32::from_bits((rng.next() as u32 & 0x807f_ffff) | ((105 + i % 72) << 23)),
        };
        assert_eq!(raw_coord(c), reference(c), "{c:e} {:#x}", c.to_bits());
    }
    // Near the halves, where the f32 add rounds.
    for k in 0..(1u32 << 16) {
        for c in [
            k as f32 / 65536.0 + 0.5 / 65536.0,
            (k as f32 + 0.5) / 65536.0,
        ] {
            for d in [-2i32, -1, 0, 1, 2] {
                let c = f32::from_bits(c.to_bits().wrapping_add_signed(d));
                assert_eq!(raw_coord(c), reference(c), "{c:e}");
                assert_eq!(raw_coord(-c), reference(-c), "{c:e}");
            }
        }
    }
}

#[test]
fn scale_applies_like_f64() {
    let mut rng = Rng(0x3141_5926_5358_9793);
    for _ in 0..100_000 {
        let x = rng.log(1e-30, 1e30) as f32;
        let s = Scale::from_f32(x).unwrap();
        let len = (1 << 15) + (rng.next() % (1 << 15)) as u32;
        let exp = (rng.next() % 120) as i32 - 60;
        let exact = len as f64 * 2f64.powi(exp) * x as f64;
        let got = s.apply(len, exp) as f64;
        if exact < SCALE_CAP as f64 / 2.0 {
            // The mantissa's rounding to 16 bits: 2^-16 relative.
            let bound = 0.5 + exact / 65536.0;
            assert!(
                (got - exact).abs() <= bound,
                "{x} {len} {exp}: {got} {exact}"
            );
        } else {
            assert!(got >= SCALE_CAP as f64 / 2.0 - 1.0);
        }
    }
    assert_eq!(Scale::from_f32(0.0), Some(Scale { m: 0, s: 0 }));
    assert_eq!(Scale::from_f32(-1.0), None);
    assert_eq!(Scale::from_f32(f32::NAN), None);
    assert_eq!(Scale::from_f32(1.0).unwrap().apply(1 << 15, -15), 1);
}

/// The set-ups without the general lighting's code (`check_lighting` for a
/// frame's lights, `one_light` and `model_checks` per draw) give the
/// general set-up's results and errors, edge cases included.
#[test]
fn checks_without_conversions_agree_with_the_general_setup() {
    let specials = [
        0.0,
        -0.0,
        1.0,
        -2.5,
        1e-30,
        1e-45,
        3e38,
        -3e38,
        1e13,
        2e13,
        1.8e13,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
    ];
    let mut rng = Rng(0x5eed_1234_abcd_0042);
    let mut pick = |rng: &mut Rng| -> f32 {
        if rng.next().is_multiple_of(3) {
            specials[(rng.next() % specials.len() as u64) as usize]
        } else {
            rng.log(1e-6, 1e15) as f32
                * if rng.next().is_multiple_of(2) {
                    1.0
                } else {
                    -1.0
                }
        }
    };
    let mut agreed = [0usize; 2];
    for case in 0..20_000 {
        let v = |rng: &mut Rng, pick: &mut dyn FnMut(&mut Rng) -> f32| {
            Vec3::new(pick(rng), pick(rng), pick(rng))
        };
        let eye = if case % 4 == 0 {
            v(&mut rng, &mut pick)
        } else {
            Vec3::new(0.0, 1.0, 5.0)
        };
        let dirs = [
            DirectionalLight::new(v(&mut rng, &mut pick), 0.5),
            DirectionalLight::new(Vec3::new(0.3, -1.0, 0.2), 0.7),
        ];
        let points = [
            PointLight::new(v(&mut rng, &mut pick), 0.8, pick(&mut rng)),
            PointLight::new(Vec3::new(1.0, 2.0, 3.0), 0.8, pick(&mut rng)),
        ];
        let fog = match rng.next() % 4 {
            0 => Fog::None,
            1 => Fog::Linear {
                start: pick(&mut rng),
                end: pick(&mut rng),
            },
            2 => Fog::Exponential {
                density: pick(&mut rng),
            },
            _ => Fog::Linear {
                start: 1.0,
                end: 1.0 + pick(&mut rng).abs(),
            },
        };
        let nd = (rng.next() % 3) as usize;
        let np = (rng.next() % 3) as usize;
        let mut lighting = Lighting::new(0.2)
            .directional(&dirs[..nd])
            .point(&points[..np]);
        lighting.fog = fog;
        let max = [1, 8][(rng.next() % 2) as usize];
        let general = match max {
            1 => LightSetup::<1>::new(&lighting, &Mat4::IDENTITY, eye).map(|_| ()),
            _ => LightSetup::<8>::new(&lighting, &Mat4::IDENTITY, eye).map(|_| ()),
        };
        assert_eq!(
            check_lighting(&lighting, eye, max),
            general,
            "{lighting:?} eye {eye:?}"
        );

        // One light under a draw's matrix.
        let model = match rng.next() % 4 {
            0 => Mat4::scale(v(&mut rng, &mut pick)),
            1 => Mat4::translation(v(&mut rng, &mut pick)),
            2 => Mat4::rotation_y(pick(&mut rng)) * Mat4::scale(Vec3::new(2.0, 2.0, 2.0)),
            _ => Mat4::IDENTITY,
        };
        let one = Lighting::new(0.2).directional(&dirs[..1]);
        let general: Result<LightSetup<8>, _> = LightSetup::new(&one, &model, eye);
        let fast = one_light(dirs[0].direction, &model, eye);
        match general {
            Ok(s) => {
                let (dir, _, _) = s.single_directional().unwrap();
                assert_eq!(fast, Ok(dir), "{model:?} eye {eye:?}");
                agreed[0] += 1;
            }
            Err(e) => {
                assert_eq!(fast, Err(e), "{model:?} eye {eye:?}");
                agreed[1] += 1;
            }
        }
        let unlit = Lighting::new(0.2);
        let general: Result<LightSetup<8>, _> = LightSetup::new(&unlit, &model, eye);
        assert_eq!(model_checks(&model, eye), general.map(|_| ()));
    }
    // Both outcomes were exercised.
    assert!(agreed.iter().all(|&n| n > 1_000), "{agreed:?}");
}
