//! The translation forms volfog's own modules do not use, on a synthetic module,
//! compiled and compared with naga_oil.

use naga_oil::compose::Composer;
use volfog_codegen::wesl::translate;

use crate::equivalence::check_equivalence;
use crate::fixtures::Sources;

/// A naga_oil module with every form of the translation that volfog's own modules do
/// not use: conditional struct members, nested conditional parameters, declarations
/// used after their region (one `@if` per statement, nested conditions joined), a
/// block-opening `if` header per branch, and several declarations per module-scope
/// branch.
const SYNTHETIC: &str = "\
struct Sample {
    value: f32,
#ifdef A
    weight: f32,
#endif
}

fn pick(
    x: f32,
#ifdef A
    a: f32,
#ifndef B
    b: f32,
#endif
#endif
) -> f32 {
#ifdef A
    let base = x * a;
#ifndef B
    let scale = b;
#else
    let scale = 2.0;
#endif
#else
    let base = x;
    let scale = 3.0;
#endif
    var total = base * scale;
#ifdef B
    if total > 1.0 && x > 0.0 {
#else
    if total > 1.0 {
#endif
        total -= 1.0;
    }
    return total;
}

#ifdef B
fn helper() -> f32 {
    return 1.0;
}

fn helper_twice() -> f32 {
    return helper() * 2.0;
}
#else
fn helper() -> f32 {
    return 0.5;
}
#endif

fn weighted(s: Sample) -> f32 {
#ifdef A
    return s.value * s.weight * helper();
#else
    return s.value * helper();
#endif
}
";

#[test]
fn synthetic_forms_compile_and_match_naga_oil() {
    let wesl = translate("synthetic.wgsl", SYNTHETIC).unwrap_or_else(|e| panic!("{e}"));
    for form in [
        "    @if(A)\n    weight: f32,",
        "    @if(A)\n    a: f32,\n    @if(A && !B)\n    b: f32,",
        "    @if(A)\n    let base = x * a;\n    @if(A && !B)\n    let scale = b;\n    @if(A && B)\n    let scale = 2.0;\n    @if(!A)\n    let base = x;\n    @if(!A)\n    let scale = 3.0;",
        "    @if(B)\n    if total > 1.0 && x > 0.0 {\n        total -= 1.0;\n    }\n    @else\n    if total > 1.0 {\n        total -= 1.0;\n    }",
        "@if(B) {\n    fn helper() -> f32 {",
        "}\n@else {\n    fn helper() -> f32 {\n        return 0.5;\n    }\n}",
    ] {
        assert!(wesl.contains(form), "missing\n{form}\nin\n{wesl}");
    }
    let modules: Sources = [("synthetic".to_string(), wesl)].into();
    let all = vec!["A".to_string(), "B".to_string()];
    let mut composer = Composer::default();
    let (combos, items) = check_equivalence(
        &mut composer,
        &modules,
        "synthetic",
        &all,
        ("synthetic.wgsl", SYNTHETIC),
    )
    .unwrap_or_else(|report| panic!("WESL and naga_oil differ:\n{report}"));
    // Sample, pick, helper and weighted, and helper_twice where B is on.
    assert_eq!((combos, items), (4, 4 * 4 + 2));
}
