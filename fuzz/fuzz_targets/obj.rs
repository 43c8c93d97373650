//! The OBJ loader (tobj and the checks around it) on arbitrary text, with `vn`
//! normals and an MTL library, and what follows it for a model that loads: the
//! conversion of every part to the core's fixed-point mesh, and the part's
//! material over the default one. The input is the OBJ text, then optionally a 0
//! byte and the text every `mtllib` reads. Asserted: no panic; an error names the
//! OBJ or the MTL file; a loaded part has a unit normal per vertex, only valid
//! indices, coordinates the core takes and material colours in 0..=1.
#![no_main]

use fixshade_sim::scene::convert::{quantize_mesh, FixedMesh};
use fixshade_sim::scene::desc::MaterialDesc;
use fixshade_sim::scene::mesh::{parse_obj, MtlFile};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let (obj, mtl) = match data.iter().position(|b| *b == 0) {
        Some(i) => (&data[..i], Some(&data[i + 1..])),
        None => (data, None),
    };
    let text = String::from_utf8_lossy(obj);
    let mtl = mtl.map(|m| String::from_utf8_lossy(m).into_owned());
    let read = |_: &std::path::Path| match &mtl {
        Some(text) => Ok(MtlFile {
            name: "fuzz.mtl".to_owned(),
            text: text.clone(),
        }),
        None => Err("no material library in this input".to_owned()),
    };
    match parse_obj(&text, "fuzz.obj", &read) {
        Err(e) => assert!(e.file == "fuzz.obj" || e.file == "fuzz.mtl", "{e}"),
        Ok(parts) => {
            assert!(!parts.is_empty());
            for part in parts {
                let m = &part.mesh;
                assert!(!m.triangles.is_empty());
                assert_eq!(m.normals.len(), m.positions.len());
                let n = m.positions.len() as u32;
                assert!(m.triangles.iter().flatten().all(|i| *i < n));
                for v in &m.normals {
                    let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                    assert!((len - 1.0).abs() < 1e-6, "normal {v:?}");
                }
                FixedMesh::from_mesh(&quantize_mesh(m)).unwrap();
                if let Some(mtl) = part.material {
                    let d = mtl.over(&MaterialDesc::default());
                    for c in [d.emission, d.ambient, d.diffuse, d.specular] {
                        assert!(c.iter().all(|x| (0.0..=1.0).contains(x)), "{d:?}");
                    }
                    assert!((1.0..=1000.0).contains(&d.shininess), "{d:?}");
                }
            }
        }
    }
});
