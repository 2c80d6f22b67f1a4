//! Shader errors are reported with file, line, column and the offending source line;
//! import paths must match file paths.

use volfog_codegen::CodegenError;
use volfog_codegen::compose::{Defines, add_module, compose_pass, composer, declared_import_path};
use volfog_codegen::manifest::{self, Axis, ModuleSource, PassSource};

fn pass(source: &'static str) -> PassSource {
    PassSource {
        name: "broken",
        file: "shaders/passes/broken.wgsl",
        source,
        axes: &[],
        values: &[],
        usage: "",
        non_filtering_samplers: &[],
        render: None,
        hooks: &[],
    }
}

#[test]
fn wgsl_error_names_file_line_column_and_source() {
    let broken = pass(
        "#import volfog::phase::phase_hg\n\
         @compute @workgroup_size(1)\n\
         fn main() {\n    let p = phase_hg(0.5, 0.7) + undefined_value;\n}\n",
    );
    let mut composer = composer().unwrap();
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
    let mut composer = composer().unwrap();
    let bad = ModuleSource {
        import_path: "volfog::bad",
        file: "shaders/volfog/bad.wgsl",
        source: "#define_import_path volfog::bad\n\nfn f() -> f32 {\n    return vec2<f32>(1.0);\n}\n",
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

/// Every file under `shaders/volfog` (read from disk, not from the manifest) declares
/// `volfog::<file stem>` and is listed in the manifest with the same text; every file
/// under `shaders/passes` is a pass of the manifest.
#[test]
fn every_shader_file_is_in_the_manifest_under_its_path() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let files = |dir: &str| {
        let mut v: Vec<std::path::PathBuf> = std::fs::read_dir(root.join(dir))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "wgsl"))
            .collect();
        v.sort();
        v
    };
    let modules = files("volfog");
    assert_eq!(modules.len(), manifest::MODULES.len(), "{modules:?}");
    for path in modules {
        let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            declared_import_path(&text),
            Some(format!("volfog::{stem}").as_str()),
            "{}",
            path.display()
        );
        let listed = manifest::MODULES
            .iter()
            .find(|m| m.file == format!("shaders/volfog/{stem}.wgsl"))
            .unwrap_or_else(|| panic!("{stem} is not in the manifest"));
        assert_eq!(listed.source, text);
    }
    let passes = files("passes");
    assert_eq!(passes.len(), manifest::PASSES.len());
    for path in passes {
        let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
        let listed = manifest::pass(&stem).unwrap_or_else(|| panic!("pass {stem} is not listed"));
        assert_eq!(listed.source, std::fs::read_to_string(&path).unwrap());
    }
}

#[test]
fn unknown_defines_and_bad_values_are_rejected_with_the_valid_ones() {
    use volfog_codegen::reflect::HlslSamplers;
    use volfog_codegen::translate::compose_variant;
    let err =
        compose_variant("scan", &["VOLFOG_NOPE".to_string()], HlslSamplers::Classic).unwrap_err();
    assert!(
        err.to_string().contains("VOLFOG_SCAN_WRONSKI_STEP"),
        "{err}"
    );
    let err = compose_variant(
        "scan",
        &["VOLFOG_SCAN_WRONSKI_STEP=3".to_string()],
        HlslSamplers::Classic,
    )
    .unwrap_err();
    assert!(err.to_string().contains("takes no value"), "{err}");
    let err = compose_variant(
        "esm_blur",
        &["VOLFOG_ESM_BLUR_RADIUS=17".to_string()],
        HlslSamplers::Classic,
    )
    .unwrap_err();
    assert!(err.to_string().contains("out of range 1..=16"), "{err}");
    let err = compose_variant(
        "esm_blur",
        &["VOLFOG_ESM_BLUR_RADIUS".to_string()],
        HlslSamplers::Classic,
    )
    .unwrap_err();
    assert!(err.to_string().contains("needs a value"), "{err}");
    let err = compose_variant("nope", &[], HlslSamplers::Classic).unwrap_err();
    assert!(err.to_string().contains("scan"), "{err}");
}

/// Mutually exclusive defines (an `Axis::OneOf`), on a pass built for the test: one
/// is accepted, two are an error naming both, and the variants of the axis are the
/// pass without the defines plus one per define.
#[test]
fn exclusive_defines_exclude_each_other() {
    static AXES: &[Axis] = &[Axis::OneOf(&["VOLFOG_TEST_A", "VOLFOG_TEST_B"])];
    let p = PassSource {
        axes: AXES,
        ..pass(
            "@compute @workgroup_size(1)\nfn main() {\n#ifdef VOLFOG_TEST_A\n    let a = 1;\n#endif\n}\n",
        )
    };
    assert!(Defines::parse(&p, &["VOLFOG_TEST_A".to_string()]).is_ok());
    let err = Defines::parse(
        &p,
        &["VOLFOG_TEST_A".to_string(), "VOLFOG_TEST_B".to_string()],
    )
    .unwrap_err();
    assert!(
        err.to_string().contains("VOLFOG_TEST_A, VOLFOG_TEST_B")
            && err.to_string().contains("exclude"),
        "{err}"
    );
    let combos = manifest::expand_axes(AXES);
    assert_eq!(
        combos,
        vec![vec![], vec!["VOLFOG_TEST_A"], vec!["VOLFOG_TEST_B"]]
    );
    let mut composer = composer().unwrap();
    for combo in combos {
        compose_pass(&mut composer, &p, &Defines::flags(combo)).unwrap();
    }
}

/// The user's custom density module, composed into inject
/// (`VOLFOG_INJECT_CUSTOM_DENSITY`): each way it can be wrong is a typed error that names
/// the user's file (and, where there is one, the line and column) and the required
/// signature.
#[test]
fn custom_density_errors_name_the_users_file_and_the_signature() {
    use volfog_codegen::custom::{CustomModule, compose_with};
    use volfog_codegen::manifest::CUSTOM_DENSITY;

    let inject = manifest::pass("inject").unwrap();
    let defines = Defines::parse(inject, &[CUSTOM_DENSITY.define.to_string()]).unwrap();
    let compose = |file: &str, source: &str| {
        compose_with(
            inject,
            &defines,
            &[(&CUSTOM_DENSITY, &CustomModule::new(file, source))],
        )
    };
    let header = "#import volfog::types::{FogSample, FogCustomParams}\n";

    // Without the function.
    let err = compose(
        "empty.wgsl",
        &format!("{header}fn helper() -> f32 {{ return 1.0; }}\n"),
    )
    .unwrap_err();
    eprintln!("{err}");
    assert!(
        matches!(err, CodegenError::CustomFunctionMissing { .. }),
        "{err:?}"
    );
    let text = err.to_string();
    assert!(
        text.contains("empty.wgsl") && text.contains(CUSTOM_DENSITY.signature),
        "{text}"
    );

    // Another signature: the function's own line and column.
    let err = compose(
        "two_args.wgsl",
        &format!(
            "{header}\n   fn volfog_custom_density(world: vec3<f32>, time: f32) -> FogSample {{\n\
             \x20   return FogSample(vec3<f32>(1.0), 0.1, vec3<f32>(0.0));\n}}\n"
        ),
    )
    .unwrap_err();
    eprintln!("{err}");
    match &err {
        CodegenError::CustomSignature {
            file, line, column, ..
        } => {
            assert_eq!((file.as_str(), *line, *column), ("two_args.wgsl", 3, 4));
        }
        other => panic!("expected a signature error, got {other:?}"),
    }
    let text = err.to_string();
    assert!(
        text.starts_with("two_args.wgsl:3:4:") && text.contains(CUSTOM_DENSITY.signature),
        "{text}"
    );

    // An error inside the function: naga's message at the user's file, line and column,
    // the offending line, and the signature.
    let err = compose(
        "typo.wgsl",
        &format!(
            "{header}\nfn volfog_custom_density(world: vec3<f32>, time: f32, params: FogCustomParams) -> FogSample {{\n\
             \x20   let e = 0.1 * undefined_height;\n\
             \x20   return FogSample(vec3<f32>(1.0), e, vec3<f32>(0.0));\n}}\n"
        ),
    )
    .unwrap_err();
    eprintln!("{err}");
    assert!(matches!(err, CodegenError::CustomModule { .. }), "{err:?}");
    let text = err.to_string();
    assert!(text.contains("typo.wgsl:4:"), "file:line:column in {text}");
    assert!(
        text.contains("undefined_height"),
        "the offending line in {text}"
    );
    assert!(text.contains(CUSTOM_DENSITY.signature), "{text}");

    // An error after an imported name on the same line: the column is the user's
    // (naga_oil counts it in the line with the name decorated), and so is the line shown.
    let line = "    return FogSample(vec3<f32>(1.0), oops, vec3<f32>(0.0));";
    let err = compose(
        "decorated.wgsl",
        &format!(
            "{header}fn volfog_custom_density(world: vec3<f32>, time: f32, params: FogCustomParams) -> FogSample {{\n{line}\n}}\n"
        ),
    )
    .unwrap_err();
    eprintln!("{err}");
    let text = err.to_string();
    // `oops` starts at the 38th character of the line.
    assert!(text.contains("decorated.wgsl:3:38"), "{text}");
    assert!(text.contains(line), "the user's line in {text}");

    // The wrong return type, found where the function returns.
    let err = compose(
        "scalar.wgsl",
        &format!(
            "{header}fn volfog_custom_density(world: vec3<f32>, time: f32, params: FogCustomParams) -> f32 {{\n\
             \x20   return 0.1;\n}}\n"
        ),
    )
    .unwrap_err();
    eprintln!("{err}");
    assert!(
        matches!(
            err,
            CodegenError::CustomSignature {
                line: 2,
                column: 1,
                ..
            }
        ),
        "{err:?}"
    );

    // A module that declares another import path.
    let err = compose(
        "moved.wgsl",
        "#define_import_path my::density\nfn volfog_custom_density() {}\n",
    )
    .unwrap_err();
    assert!(
        matches!(&err, CodegenError::ImportPath { file, expected, .. }
            if file == "moved.wgsl" && expected == CUSTOM_DENSITY.import_path),
        "{err:?}"
    );

    // The define without a module.
    let mut composer = composer().unwrap();
    let err = compose_pass(&mut composer, inject, &defines).unwrap_err();
    assert!(
        matches!(err, CodegenError::CustomModuleMissing { .. }),
        "{err:?}"
    );
    // The shared composer keeps no user's module: the define fails again afterwards.
    let err = volfog_codegen::compose::compose_validated(inject, &defines).unwrap_err();
    assert!(
        matches!(err, CodegenError::CustomModuleMissing { .. }),
        "{err:?}"
    );
}
