//! The WESL package of `volfog_codegen::wesl`, compiled with the WESL compiler of Bevy
//! 0.20 (wesl 0.6) the way Bevy compiles shaders, under every combination of each
//! module's feature flags; validated with naga; and compared item by item with the
//! naga_oil composition of the same module under the same defines, so a misplaced
//! `@if` fails here.

mod compile;
mod equivalence;
mod fixtures;
mod package;
mod synthetic;

/// The bind group the tests give `VOLFOG_FOG_GROUP`.
const FOG_GROUP: u32 = 3;

/// The flag that is also an integer define (`#{VOLFOG_FOG_GROUP}`).
const FOG_GROUP_FLAG: &str = "VOLFOG_FOG_GROUP";
