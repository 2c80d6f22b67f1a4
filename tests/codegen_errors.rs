//! Shader errors are reported with file, line, column and the offending source line;
//! import paths must match file paths.

use volfog::codegen::compose::{add_module, compose_pass, Defines};
use volfog::codegen::CodegenError;
use volfog::manifest::{ModuleSource, PassSource};

fn pass(source: &'static str) -> PassSource {
    PassSource {
        name: "broken",
        file: "shaders/passes/broken.wgsl",
        source,
        axes: &[],
        values: &[],
        fixed: &[],
        usage: "",
    }
}

#[test]
fn wgsl_error_names_file_line_column_and_source() {
    let broken = pass(
        "#import volfog::phase::phase_hg\n\
         @compute @workgroup_size(1)\n\
         fn main() {\n    let p = phase_hg(0.5, 0.7) + undefined_value;\n}\n",
    );
    let mut composer = volfog::codegen::compose::composer().unwrap();
    let err = compose_pass(&mut composer, &broken, &Defines::default()).unwrap_err();
    let text = err.to_string();
    eprintln!("{text}");
    assert!(
        text.contains("shaders/passes/broken.wgsl:4:"),
        "file:line:column in {text}"
    );
    assert!(
        text.contains("undefined_value"),
        "the offending line in {text}"
    );
}

#[test]
fn error_in_an_imported_module_points_into_that_module() {
    let mut composer = volfog::codegen::compose::composer().unwrap();
    let bad = ModuleSource {
        import_path: "volfog::bad",
        file: "shaders/volfog/bad.wgsl",
        source:
            "#define_import_path volfog::bad\n\nfn f() -> f32 {\n    return vec2<f32>(1.0);\n}\n",
    };
    add_module(&mut composer, &bad).unwrap();
    let user =
        pass("#import volfog::bad::f\n@compute @workgroup_size(1)\nfn main() { let x = f(); }\n");
    let err = compose_pass(&mut composer, &user, &Defines::default()).unwrap_err();
    let text = err.to_string();
    eprintln!("{text}");
    assert!(text.contains("shaders/volfog/bad.wgsl:3:"), "{text}");
    assert!(
        text.contains("return vec2<f32>(1.0);"),
        "the offending line in {text}"
    );
}

#[test]
fn import_path_must_match_the_file() {
    let mut composer = naga_oil::compose::Composer::default();
    let misplaced = ModuleSource {
        import_path: "volfog::phase",
        file: "shaders/volfog/phase.wgsl",
        source: "#define_import_path volfog::phases\nfn f() -> f32 { return 1.0; }\n",
    };
    match add_module(&mut composer, &misplaced) {
        Err(CodegenError::ImportPath {
            found, expected, ..
        }) => {
            assert_eq!(found, "volfog::phases");
            assert_eq!(expected, "volfog::phase");
        }
        other => panic!("expected an import path error, got {other:?}"),
    }
}

#[test]
fn every_module_path_matches_its_file_stem() {
    for m in volfog::manifest::MODULES {
        let stem = std::path::Path::new(m.file)
            .file_stem()
            .unwrap()
            .to_string_lossy();
        assert_eq!(m.import_path, format!("volfog::{stem}"));
        assert_eq!(
            volfog::codegen::compose::declared_import_path(m.source),
            Some(m.import_path)
        );
    }
}

#[test]
fn unknown_and_conflicting_defines_are_rejected_with_the_valid_ones() {
    let err = volfog::shaders::compose_variant("scan", &["VOLFOG_NOPE".to_string()]).unwrap_err();
    assert!(
        err.to_string().contains("VOLFOG_SCAN_WRONSKI_STEP"),
        "{err}"
    );
    let err = volfog::shaders::compose_variant("scan", &["VOLFOG_SCAN_WRONSKI_STEP=3".to_string()])
        .unwrap_err();
    assert!(err.to_string().contains("takes no value"), "{err}");
    let err = volfog::shaders::compose_variant("nope", &[]).unwrap_err();
    assert!(err.to_string().contains("scan"), "{err}");
}
