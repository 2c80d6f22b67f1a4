//! Writes the `volfog` WESL package, generated from volfog's WGSL modules, into
//! OUT_DIR/wesl: one `<module>.wesl` per module and `modules.rs`, the list that
//! `volfog_bevy::wesl::MODULES` includes.

use std::fmt::Write as _;
use std::path::PathBuf;

fn main() {
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR")).join("wesl");
    std::fs::create_dir_all(&out).expect("create OUT_DIR/wesl");
    let modules = volfog_codegen::wesl::wesl_package()
        .unwrap_or_else(|e| panic!("volfog's WESL package: {e}"));
    let mut list = String::from("&[\n");
    for module in &modules {
        let file = format!("{}.wesl", module.name);
        std::fs::write(out.join(&file), &module.source).expect("write a WESL module");
        writeln!(
            list,
            "    ({:?}, include_str!(concat!(env!(\"OUT_DIR\"), \"/wesl/{file}\"))),",
            module.name
        )
        .expect("write to a String");
    }
    list.push(']');
    std::fs::write(out.join("modules.rs"), list).expect("write modules.rs");
}
