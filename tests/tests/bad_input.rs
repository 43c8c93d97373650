//! Bad input to the library API gets a typed error or a documented cull, never a
//! panic: NaN and infinite `f32` input, meshes that are empty or refer to missing
//! vertices, buffers smaller than their declared frame, frames and caches that do
//! not fit, a degenerate camera, and screen coordinates anywhere in `i32`.

use fixshade::fixed::{Angle, NumError, Q16_16, Q2_14};
use fixshade::geometry::{Mesh, MeshError, MAX_COORD};
use fixshade::light::{Light, Material};
use fixshade::raster::span::{Gradient, NoDepth};
use fixshade::raster::{draw_triangle, ScreenVertex};
use fixshade::render::{Frame, RenderError, XfVertex};
use fixshade::scene::{Camera, Object, Placement, Projection, Scene};
use fixshade::shade::Gouraud;
use fixshade::target::{Framebuffer, Rgb565Le, Strip, TargetError};

#[test]
fn f32_nan_and_infinity_are_errors() {
    for x in [f32::NAN, -f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        assert_eq!(Q16_16::from_f32(x), Err(NumError::NotFinite), "{x}");
        assert_eq!(Q2_14::from_f32(x), Err(NumError::NotFinite), "{x}");
    }
    // Out of range: at and beyond 2¹⁵ (Q16.16) and 2 (Q2.14), the largest f32.
    for x in [32768.0f32, 1e9, f32::MAX, -32768.5, -f32::MAX] {
        assert_eq!(Q16_16::from_f32(x), Err(NumError::OutOfRange), "{x}");
    }
    for x in [2.0f32, -2.0001, 1e30] {
        assert_eq!(Q2_14::from_f32(x), Err(NumError::OutOfRange), "{x}");
    }
    // The edges that do fit, and the tiny ones that round to zero.
    assert_eq!(Q16_16::from_f32(-32768.0), Ok(Q16_16::MIN));
    assert_eq!(Q2_14::from_f32(-2.0), Ok(Q2_14::from_bits(i16::MIN)));
    for x in [0.0f32, -0.0, f32::MIN_POSITIVE, 1e-45, -1e-45] {
        assert_eq!(Q16_16::from_f32(x), Ok(Q16_16::ZERO), "{x}");
        assert_eq!(Q2_14::from_f32(x), Ok(Q2_14::from_bits(0)), "{x}");
    }
}

fn p(x: i32, y: i32, z: i32) -> [Q16_16; 3] {
    [x, y, z].map(Q16_16::from_int)
}

const N: [Q2_14; 3] = [Q2_14::from_bits(0), Q2_14::from_bits(0), Q2_14::ONE];

#[test]
fn meshes_with_bad_indices_or_coordinates_are_errors() {
    let pos = [p(0, 0, 0), p(1, 0, 0), p(0, 1, 0)];
    let nrm = [N; 3];
    assert_eq!(
        Mesh::new(&pos, &nrm[..2], &[[0, 1, 2]]).err(),
        Some(MeshError::NormalCount)
    );
    assert_eq!(
        Mesh::new(&pos, &nrm, &[[0, 1, 2], [0, 1, 3]]).err(),
        Some(MeshError::IndexOutOfRange(1))
    );
    assert_eq!(
        Mesh::new(&pos, &nrm, &[[u16::MAX, 0, 1]]).err(),
        Some(MeshError::IndexOutOfRange(0))
    );
    let far = [p(0, 0, 0), p(MAX_COORD, 0, 0), [Q16_16::MIN; 3]];
    assert_eq!(
        Mesh::new(&far, &nrm, &[]).err(),
        Some(MeshError::CoordinateOutOfRange(1))
    );
    let far = [p(0, 0, 0), p(0, 0, 0), [Q16_16::MIN; 3]];
    assert_eq!(
        Mesh::new(&far, &nrm, &[]).err(),
        Some(MeshError::CoordinateOutOfRange(2))
    );
    let many = vec![p(0, 0, 0); 65536];
    let many_n = vec![N; 65536];
    assert_eq!(
        Mesh::new(&many, &many_n, &[]).err(),
        Some(MeshError::TooManyVertices)
    );
}

fn camera() -> Camera {
    Camera {
        eye: p(0, 0, 3),
        target: p(0, 0, 0),
        up: p(0, 1, 0),
        projection: Projection::Perspective {
            fovy: Angle::from_degrees(60),
            near: Q16_16::ONE,
            far: Q16_16::from_int(10),
        },
    }
}

fn scene_with(mesh: Mesh<'_>) -> Scene<'_> {
    let mut s = Scene::new(camera());
    let white = [Q16_16::ONE; 3];
    s.add_light(Light::directional(p(0, 0, 1), white, white))
        .unwrap();
    s.add_object(Object {
        mesh,
        placement: Placement::default(),
        material: Material::default(),
        back_material: None,
    })
    .unwrap();
    s
}

/// Empty meshes (no vertices, or vertices but no triangles) and a scene without
/// objects are valid and draw nothing.
#[test]
fn empty_meshes_draw_nothing() {
    let pos = [p(0, 0, 0)];
    let nrm = [N];
    for mesh in [
        Mesh::new(&[], &[], &[]).unwrap(),
        Mesh::new(&pos, &nrm, &[]).unwrap(),
    ] {
        let scene = scene_with(mesh);
        let mut cache = vec![XfVertex::default(); scene.vertex_count()];
        let mut color = [0x1234u16; 8 * 6];
        let mut depth = [0xFFFFu16; 8 * 6];
        let mut fb = Framebuffer::<Rgb565Le>::new(&mut color, Some(&mut depth), 8, 6).unwrap();
        let frame = Frame::<Rgb565Le>::prepare(&scene, 8, 6, &mut cache).unwrap();
        let st = frame.draw::<Gradient, _>(&mut fb).unwrap();
        assert_eq!((st.triangles, st.drawn, st.pixels), (0, 0, 0), "{st:?}");
        assert!(color.iter().all(|c| *c == 0x1234));
    }
    let scene = Scene::new(camera());
    let frame = Frame::<Rgb565Le>::prepare(&scene, 8, 6, &mut []).unwrap();
    let mut color = [0u16; 48];
    let mut fb = Framebuffer::<Rgb565Le>::new(&mut color, None, 8, 6).unwrap();
    let mut s = Scene::new(camera());
    s.depth_test = false;
    let frame2 = Frame::<Rgb565Le>::prepare(&s, 8, 6, &mut []).unwrap();
    assert_eq!(frame2.draw::<Gradient, _>(&mut fb).unwrap().pixels, 0);
    // The depth test without a depth buffer is an error, not a panic.
    assert_eq!(
        frame.draw::<Gradient, _>(&mut fb).err(),
        Some(RenderError::NoDepthBuffer)
    );
}

/// Buffers smaller than the declared frame, sizes of 0 or above 4096, strips
/// outside their frame.
#[test]
fn targets_smaller_than_declared_are_errors() {
    let mut c = vec![0u16; 4096 * 2];
    let mut d = vec![0u16; 4096 * 2];
    assert_eq!(
        Framebuffer::<Rgb565Le>::new(&mut c[..47], None, 8, 6).err(),
        Some(TargetError::ColorBufferTooSmall)
    );
    assert_eq!(
        Framebuffer::<Rgb565Le>::new(&mut c[..48], Some(&mut d[..47]), 8, 6).err(),
        Some(TargetError::DepthBufferTooSmall)
    );
    assert_eq!(
        Framebuffer::<Rgb565Le>::new(&mut c[..0], None, 0, 0).err(),
        Some(TargetError::BadSize)
    );
    assert_eq!(
        Framebuffer::<Rgb565Le>::new(&mut c, None, 4097, 1).err(),
        Some(TargetError::BadSize)
    );
    assert_eq!(
        Framebuffer::<Rgb565Le>::new(&mut c, None, 1, 4097).err(),
        Some(TargetError::BadSize)
    );
    assert_eq!(
        Strip::<Rgb565Le>::new(&mut c, None, 8, 6, 5, 2).err(),
        Some(TargetError::StripOutsideFrame)
    );
    assert_eq!(
        Strip::<Rgb565Le>::new(&mut c, None, 8, 6, u32::MAX, 2).err(),
        Some(TargetError::StripOutsideFrame)
    );
    assert_eq!(
        Strip::<Rgb565Le>::new(&mut c, None, 8, 6, 0, 0).err(),
        Some(TargetError::StripOutsideFrame)
    );
    let mut s = Strip::<Rgb565Le>::new(&mut c, None, 8, 6, 0, 2).unwrap();
    assert_eq!(s.set_y0(5).err(), Some(TargetError::StripOutsideFrame));
    assert_eq!(
        s.set_y0(u32::MAX).err(),
        Some(TargetError::StripOutsideFrame)
    );
    assert_eq!(s.set_y0(4), Ok(()));
    // The largest frame fits.
    assert!(Strip::<Rgb565Le>::new(&mut c, Some(&mut d), 4096, 4096, 4094, 2).is_ok());
}

/// A frame prepared for one size and drawn into another, a cache too small, a
/// degenerate camera or model: typed errors.
#[test]
fn frames_that_do_not_fit_are_errors() {
    let pos = [p(-1, -1, 0), p(1, -1, 0), p(0, 1, 0)];
    let nrm = [N; 3];
    let tri = [[0u16, 1, 2]];
    let scene = scene_with(Mesh::new(&pos, &nrm, &tri).unwrap());
    let mut cache = [XfVertex::default(); 3];
    assert_eq!(
        Frame::<Rgb565Le>::prepare(&scene, 8, 6, &mut cache[..2]).err(),
        Some(RenderError::CacheTooSmall { needed: 3 })
    );
    for (w, h) in [(0, 6), (8, 0), (4097, 6), (8, 4097)] {
        assert_eq!(
            Frame::<Rgb565Le>::prepare(&scene, w, h, &mut cache).err(),
            Some(RenderError::BadSize)
        );
    }
    let frame = Frame::<Rgb565Le>::prepare(&scene, 8, 6, &mut cache).unwrap();
    let mut c = [0u16; 9 * 6];
    let mut d = [0u16; 9 * 6];
    let mut fb = Framebuffer::<Rgb565Le>::new(&mut c, Some(&mut d), 9, 6).unwrap();
    assert_eq!(
        frame.draw::<Gradient, _>(&mut fb).err(),
        Some(RenderError::TargetSizeMismatch)
    );

    let mut bad = scene_with(Mesh::new(&pos, &nrm, &tri).unwrap());
    bad.camera.target = bad.camera.eye;
    assert_eq!(
        Frame::<Rgb565Le>::prepare(&bad, 8, 6, &mut cache).err(),
        Some(RenderError::BadView)
    );
    let mut bad = scene_with(Mesh::new(&pos, &nrm, &tri).unwrap());
    bad.camera.up = p(0, 0, 5);
    assert_eq!(
        Frame::<Rgb565Le>::prepare(&bad, 8, 6, &mut cache).err(),
        Some(RenderError::BadView)
    );
    for (near, far) in [(0, 10), (-1, 10), (5, 5), (5, 2)] {
        let mut bad = scene_with(Mesh::new(&pos, &nrm, &tri).unwrap());
        bad.camera.projection = Projection::Perspective {
            fovy: Angle::from_degrees(60),
            near: Q16_16::from_int(near),
            far: Q16_16::from_int(far),
        };
        assert_eq!(
            Frame::<Rgb565Le>::prepare(&bad, 8, 6, &mut cache).err(),
            Some(RenderError::BadProjection),
            "near {near} far {far}"
        );
    }
    let mut bad = Scene::new(camera());
    bad.add_object(Object {
        mesh: Mesh::new(&pos, &nrm, &tri).unwrap(),
        placement: Placement {
            scale: Q16_16::ZERO,
            ..Placement::default()
        },
        material: Material::default(),
        back_material: None,
    })
    .unwrap();
    assert_eq!(
        Frame::<Rgb565Le>::prepare(&bad, 8, 6, &mut cache).err(),
        Some(RenderError::SingularModel { object: 0 })
    );
}

/// Screen vertices anywhere in `i32` (including `i32::MIN`, whose `abs` overflows)
/// are culled when outside the guard band, never wrapped; colours and depths
/// anywhere in their types do not panic.
#[test]
fn screen_coordinates_anywhere_in_i32_are_culled() {
    let mut c = [0u16; 8 * 6];
    let mut fb = Framebuffer::<Rgb565Le>::new(&mut c, None, 8, 6).unwrap();
    let ok = ScreenVertex {
        x: 40,
        y: 40,
        z: 0,
        c: [0; 3],
    };
    for bad in [i32::MIN, i32::MIN + 1, -65536, 65536, i32::MAX] {
        for k in 0..3 {
            let mut v = [
                ok,
                ScreenVertex { x: 100, ..ok },
                ScreenVertex { y: 90, ..ok },
            ];
            v[k].x = bad;
            assert_eq!(
                draw_triangle::<Rgb565Le, _, Gradient, NoDepth, Gouraud>(&mut fb, v),
                0
            );
            v[k].x = ok.x;
            v[k].y = bad;
            assert_eq!(
                draw_triangle::<Rgb565Le, _, Gradient, NoDepth, Gouraud>(&mut fb, v),
                0
            );
        }
    }
    // Colours far outside the channel range wrap in the packed pixel (a contract
    // violation: the result is unspecified) but never panic; any depth is fine.
    let tri = [
        ok,
        ScreenVertex { x: 100, ..ok },
        ScreenVertex { y: 90, ..ok },
    ];
    for (cv, z) in [(i32::MIN, 0), (i32::MAX, u32::MAX), (-1, 1 << 31)] {
        let v = tri.map(|t| ScreenVertex {
            c: [cv, cv.wrapping_neg() / 2, cv / 3],
            z,
            ..t
        });
        let mut d = [0u16; 8 * 6];
        let mut fb = Framebuffer::<Rgb565Le>::new(&mut c, Some(&mut d), 8, 6).unwrap();
        assert!(
            draw_triangle::<Rgb565Le, _, Gradient, fixshade::raster::span::DepthTest, Gouraud>(
                &mut fb, v
            ) > 0
        );
    }
}
