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

/// The bind group the tests give `VOLFOG_STEREO_FOG_GROUP` (`volfog::stereo_bindings`).
const STEREO_FOG_GROUP: u32 = 2;

/// The flags that are also integer defines, with the values the tests give them.
const GROUP_FLAGS: [(&str, u32); 2] = [
    (FOG_GROUP_FLAG, FOG_GROUP),
    ("VOLFOG_STEREO_FOG_GROUP", STEREO_FOG_GROUP),
];

/// The integer a flag stands for where it is also an integer define.
fn group_value(flag: &str) -> Option<u32> {
    GROUP_FLAGS
        .iter()
        .find(|(name, _)| *name == flag)
        .map(|(_, value)| *value)
}
