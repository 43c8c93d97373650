//! The README's library section is `crates/core-nostd/docs/library.md`, the file
//! the crate docs include (`#![doc = include_str!(...)]` in the core's lib.rs); this
//! test fails when they drift apart. `FIXSHADE_BLESS=1` rewrites the README section.

use std::path::Path;

const START: &str = "<!-- Generated from crates/core-nostd/docs/library.md (the crate docs); a test checks they agree. -->\n";
const END: &str = "<!-- End of crates/core-nostd/docs/library.md. -->\n";

#[test]
fn readme_library_section_is_the_crate_docs() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let lib = std::fs::read_to_string(root.join("crates/core-nostd/docs/library.md")).unwrap();
    let crate_root = std::fs::read_to_string(root.join("crates/core-nostd/src/lib.rs")).unwrap();
    assert!(
        crate_root.contains("#![doc = include_str!(\"../docs/library.md\")]"),
        "the crate docs no longer include docs/library.md"
    );
    let readme_path = root.join("README.md");
    let readme = std::fs::read_to_string(&readme_path).unwrap();
    let (Some(a), Some(b)) = (readme.find(START), readme.find(END)) else {
        panic!("README.md has lost the markers of its library section");
    };
    let section = &readme[a + START.len()..b];
    if section != lib && std::env::var("FIXSHADE_BLESS").as_deref() == Ok("1") {
        let fixed = format!("{}{START}{lib}{}", &readme[..a], &readme[b..]);
        std::fs::write(&readme_path, fixed).unwrap();
        return;
    }
    assert!(
        section == lib,
        "README.md's library section differs from crates/core-nostd/docs/library.md; run FIXSHADE_BLESS=1 cargo test -p fixshade-tests --test readme_library"
    );
}
