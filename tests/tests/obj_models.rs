//! Users' OBJ models drawn as OpenGL would: `vn` normals keep hard edges hard,
//! recomputed normals shade smoothly, MTL materials colour their groups; and the
//! messages for bad input name the file, the line and the valid range.

use fixshade_sim::image::Image;
use fixshade_sim::render;
use fixshade_sim::scene::load::{load, read_scene, LoadedScene};
use fixshade_sim::scene::names::FormatName;
use fixshade_tests::catalogue;
use fixshade_tests::{area2, project, P2};

/// A catalogue scene drawn with 8-bit channels (the catalogue draws it in
/// rgb565le, as the MCU images do).
fn scene(name: &str) -> LoadedScene {
    let path = catalogue::path(&format!("scenes/{name}.toml"));
    let (mut desc, dir) = read_scene(&path.display().to_string()).unwrap();
    desc.format = FormatName::RGB888;
    load(name, &desc, &dir).unwrap()
}

fn image(ls: &LoadedScene) -> Image {
    render::render(ls, None).unwrap().image
}

/// The largest difference, over the channels, between the colours of each face's
/// interior pixels, for every face facing the camera. A face is two consecutive
/// triangles (a quad of the file); a pixel is in its interior when its centre is
/// more than a pixel inside one of them, so edge pixels shared with a neighbour
/// face do not count.
fn face_spreads(ls: &LoadedScene, img: &Image) -> Vec<(usize, u8, usize)> {
    let tris = project(&ls.desc, &ls.meshes).tris;
    let w = img.width as usize;
    let inside = |t: &[P2; 3], p: P2| {
        // Front faces have a negative snapped area (y down).
        let a = area2(t[0], t[1], t[2]);
        a < 0
            && (0..3).all(|k| {
                let (u, v) = (t[k], t[(k + 1) % 3]);
                let len = (((v.0 - u.0) as f64).powi(2) + ((v.1 - u.1) as f64).powi(2)).sqrt();
                // Distance inside the edge, in 1/16 pixels.
                -(area2(u, v, p) as f64) / len > 16.0
            })
    };
    let mut out = Vec::new();
    for face in 0..tris.len() / 2 {
        let mut lo = [255u8; 3];
        let mut hi = [0u8; 3];
        let mut n = 0;
        for (i, px) in img.pixels.iter().enumerate() {
            let p = (16 * (i % w) as i32 + 8, 16 * (i / w) as i32 + 8);
            if inside(&tris[2 * face], p) || inside(&tris[2 * face + 1], p) {
                for c in 0..3 {
                    lo[c] = lo[c].min(px[c]);
                    hi[c] = hi[c].max(px[c]);
                }
                n += 1;
            }
        }
        if n > 0 {
            let spread = (0..3).map(|c| hi[c] - lo[c]).max().unwrap();
            out.push((face, spread, n));
        }
    }
    out
}

/// With `vn` face normals every vertex of a face has the same normal, so the
/// vertex stage lights them to the same colour and Gouraud interpolation of equal
/// colours is that colour: each face is flat. The bound is 1 LSB of the 8-bit
/// format for the gradient stepping's rounding; the render shows 0.
#[test]
fn obj_cube_with_face_normals_renders_flat_faces() {
    let ls = scene("obj-cube-vn");
    assert_eq!(ls.meshes[0].positions.len(), 24);
    let spreads = face_spreads(&ls, &image(&ls));
    assert_eq!(
        spreads.len(),
        3,
        "three faces seen from a corner: {spreads:?}"
    );
    for (face, spread, n) in &spreads {
        assert!(*n > 50, "face {face}: only {n} interior pixels");
        assert!(*spread <= 1, "face {face}: colours spread {spread} levels");
    }
}

/// The same cube without `vn`: recomputed (area-weighted) corner normals lean
/// along the diagonals, so the faces are shaded smoothly, not flat.
#[test]
fn obj_cube_without_normals_renders_smooth_faces() {
    let ls = scene("obj-cube-no-vn");
    assert_eq!(ls.meshes[0].positions.len(), 8);
    let spreads = face_spreads(&ls, &image(&ls));
    assert_eq!(spreads.len(), 3, "{spreads:?}");
    for (face, spread, _) in &spreads {
        assert!(
            *spread >= 8,
            "face {face}: colours spread only {spread} levels"
        );
    }
}

/// The colour at the centre of the left and the right square of `obj-mtl`.
fn left_right(ls: &LoadedScene) -> ([u8; 3], [u8; 3]) {
    let img = image(ls);
    let (w, h) = (img.width as usize, img.height as usize);
    let at = |x: usize| img.pixels[h / 2 * w + x];
    (at(w / 2 - w / 8), at(w / 2 + w / 8))
}

/// Two material groups with different `Kd` are drawn as two objects, each with
/// its MTL material: red on the left, green (and shiny) on the right; the scene's
/// `[material]` (blue) only fills in what the MTL file leaves out (nothing here).
#[test]
fn obj_with_mtl_renders_with_its_materials() {
    let ls = scene("obj-mtl");
    assert_eq!(ls.desc.objects.len(), 2);
    let kd = ls.desc.objects[0].material.diffuse;
    assert!(
        (kd[0] - 0.9).abs() < 1e-4 && kd[1] == 0.0 && kd[2] == 0.0,
        "{kd:?}"
    );
    let (left, right) = left_right(&ls);
    assert!(
        left[0] > 100 && left[1] == 0 && left[2] == 0,
        "left {left:?}"
    );
    // Green, with the white highlight of its `Ks` (`Ns 0`, clamped to 1: broad).
    assert!(
        right[1] > 200 && right[0] == right[2] && right[1] - right[0] > 100,
        "right {right:?}"
    );
}

/// An `[object.material]` table overrides the MTL materials: both groups blue.
#[test]
fn object_material_overrides_mtl_materials() {
    let path = catalogue::path("scenes/obj-mtl.toml");
    let text = std::fs::read_to_string(&path).unwrap()
        + "\n[object.material]\ndiffuse = [0.0, 0.0, 0.9]\n";
    let mut desc = fixshade_sim::scene::file::parse_scene(&text, "override.toml").unwrap();
    desc.format = FormatName::RGB888;
    let ls = load("override", &desc, path.parent().unwrap()).unwrap();
    let (left, right) = left_right(&ls);
    assert_eq!(left, right);
    // Red and green only from the ambient term (0.2 × 0.2 of the defaults).
    assert!(left[2] > 100 && left[0] < 16 && left[1] < 16, "{left:?}");
}

/// A near plane below the core's smallest one is the scene file's error, with
/// the file, the line and the valid range (it used to pass the parser and fail in
/// the core as "invalid projection (fovy, near or far)").
#[test]
fn tiny_near_plane_names_file_line_and_range() {
    let dir = fixshade_tests::temp_dir("tiny-near");
    let path = dir.join("tiny-near.toml");
    let text = std::fs::read_to_string(catalogue::path("scenes/obj-cube-vn.toml"))
        .unwrap()
        .replace("near = 1.0", "near = 1e-6");
    std::fs::write(&path, text).unwrap();
    let e = fixshade_sim::scene::load::load_arg(&path.display().to_string()).unwrap_err();
    assert!(
        e.contains("tiny-near.toml:11: `near` must be at least 0.0000152587890625 (2^-16"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// A vertex beyond the core's coordinate range is the OBJ loader's error, naming
/// the OBJ file, the line and the range.
#[test]
fn huge_vertex_names_obj_file_line_and_range() {
    let dir = fixshade_tests::temp_dir("huge-vertex");
    let obj = "v 0 0 0\nv 1 0 0\n# far away\nv 0 1e30 0\nf 1 2 3\n";
    std::fs::write(dir.join("far.obj"), obj).unwrap();
    let scene = "[camera]\neye = [0.0, 0.0, 4.0]\n[[object]]\nmesh = \"obj\"\npath = \"far.obj\"\n";
    std::fs::write(dir.join("far.toml"), scene).unwrap();
    let e = fixshade_sim::scene::load::load_arg(&dir.join("far.toml").display().to_string())
        .unwrap_err();
    assert!(
        e.contains("far.obj:4: vertex coordinate `1e30` is out of range: model coordinates must lie strictly between -16384 and 16384"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// With `cull = "none"` the triangles the core drops are not back faces: the
/// render's statistics count them as of zero area or off the frame, and say
/// nothing of culling; with culling the back faces are counted apart.
#[test]
fn statistics_without_culling_do_not_call_triangles_culled() {
    let dir = fixshade_tests::temp_dir("stats-cull");
    let out = dir.join("odd.png").display().to_string();
    let odd = catalogue::path("scenes/odd-obj.toml").display().to_string();
    let args: Vec<String> = ["render", odd.as_str(), "-o", out.as_str()]
        .map(String::from)
        .to_vec();
    let text = fixshade_sim::cli::run(&args).unwrap();
    assert!(
        text.contains("of zero area after snapping,")
            && text.contains("off the frame")
            && !text.contains("culled"),
        "{text}"
    );
    let sphere = ["render", "sphere", "-o", out.as_str()]
        .map(String::from)
        .to_vec();
    let text = fixshade_sim::cli::run(&sphere).unwrap();
    assert!(
        text.contains(" culled as back faces, ") && text.contains("of zero area after snapping"),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(dir);
}
