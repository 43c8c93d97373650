//! The OBJ loader on arbitrary text, and what follows it for a mesh that loads:
//! the conversion to the core's fixed-point mesh (which may reject it with an
//! error). Asserted: no panic; an error names the file; a loaded mesh has a unit
//! normal per vertex and only valid indices.
#![no_main]

use fixshade_sim::scene::convert::{quantize_mesh, FixedMesh};
use fixshade_sim::scene::mesh::parse_obj;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    match parse_obj(&text, "fuzz.obj") {
        Err(e) => assert!(e.to_string().contains("fuzz.obj"), "{e}"),
        Ok(m) => {
            assert!(!m.triangles.is_empty());
            assert_eq!(m.normals.len(), m.positions.len());
            let n = m.positions.len() as u32;
            assert!(m.triangles.iter().flatten().all(|i| *i < n));
            for v in &m.normals {
                let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                assert!((len - 1.0).abs() < 1e-6, "normal {v:?}");
            }
            let _ = FixedMesh::from_mesh(&quantize_mesh(&m));
        }
    }
});
