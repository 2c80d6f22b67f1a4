//! Composes every variant of the shader manifest with naga_oil and validates it with
//! naga (every flag), so a shader error fails `cargo build` with the file, line, column
//! and source line. Nothing is generated for the library: the runtime composes the
//! variants it needs, and translations come from `volfog_codegen::translate`.
//! Writes only `OUT_DIR/codegen_stats.txt`.

use std::path::PathBuf;
use std::time::Instant;

use volfog_codegen::{compose, manifest};

fn main() {
    println!("cargo:rerun-if-changed=shaders");
    let out_dir = PathBuf::from(std::env::var_os("OUT_DIR").expect("OUT_DIR is set by cargo"));
    let started = Instant::now();
    let variants = manifest::variants();
    let checked = compose::with_shared_composer(|composer| {
        for variant in &variants {
            let defines = compose::Defines::flags(variant.defines.iter().copied());
            let module = compose::compose_pass(composer, variant.pass, &defines)?;
            compose::validate(&module, &variant.name)?;
        }
        Ok(())
    });
    if let Err(message) = checked {
        eprintln!("\nvolfog shader codegen failed:\n\n{message}\n");
        std::process::exit(1);
    }
    let stats = format!(
        "variants {}\nmilliseconds {}\n",
        variants.len(),
        started.elapsed().as_millis()
    );
    std::fs::write(out_dir.join("codegen_stats.txt"), stats).expect("OUT_DIR is writable");
}
