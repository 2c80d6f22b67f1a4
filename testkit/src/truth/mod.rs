//! Path-traced references for volfog's froxel fog: one scene description
//! ([`scene::TruthScene`]), the scenes themselves ([`scenes`]) and Mitsuba 3's
//! `volpath` integrator in single scattering as the reference renderer ([`mitsuba`]),
//! whose renders are kept by [`stored`].

pub mod area;
pub mod compare;
pub mod floor;
pub mod mitsuba;
pub mod report;
pub mod scene;
pub mod scenes;
pub mod shadow_maps;
pub mod stored;
pub mod volfog;
