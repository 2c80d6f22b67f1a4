//! `EpipolarFrame`: one frame of epipolar sun shafts (`volfog::epipolar`).

use encase::ShaderType;
use glam::{Mat4, Vec2, Vec3, Vec4};

use super::HeightFog;
use crate::limits::{InvalidValue, check};

/// Phase of the sun lobe of the shafts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EpipolarPhase {
    /// Henyey-Greenstein (as the height fog's sun lobe).
    #[default]
    HenyeyGreenstein,
    /// Cornette-Shanks.
    CornetteShanks,
}

/// How epipolar sun shafts are sampled: fixed for the life of an
/// [`EpipolarShafts`](crate::pipeline::epipolar::EpipolarShafts).
///
/// ```
/// use volfog::uniforms::EpipolarSampling;
///
/// let sampling = EpipolarSampling::new(1920, 1080, 1024);
/// assert!(sampling.validate().is_ok());
/// let bad = EpipolarSampling { initial_step: 12, ..sampling };
/// assert!(bad.validate().unwrap_err().to_string().contains("initial_step"));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EpipolarSampling {
    /// Target width, pixels, [1, 16384].
    pub width: u32,
    /// Target height, pixels, [1, 16384].
    pub height: u32,
    /// Epipolar slices, [4, 4096] (Yusov 2012 uses 512).
    pub slices: u32,
    /// Samples per slice: a multiple of 128 in [128, 2048].
    pub samples: u32,
    /// Initial step between ray-marching samples: 8, 16, 32 or 64.
    pub initial_step: u32,
    /// Downscale factor of the screen-space resolve: 1, 2 or 4.
    pub downscale: u32,
    /// Side of the shadow map in texels: a power of two in [64, 4096].
    pub shadow_size: u32,
    /// Relative view-depth difference that counts as a depth break, (0, 10].
    pub depth_threshold: f32,
    /// Steps of the per-pixel march correcting pixels no sample serves, [1, 4096].
    pub fix_steps: u32,
    /// Steps of the brute-force reference march per pixel, [1, 65536].
    pub reference_steps: u32,
    /// Coloured shafts: the marches multiply the light by a light-space colour texture
    /// (the `VOLFOG_EPIPOLAR_COLORED` variants; the tree then skips only shadow).
    pub colored: bool,
}

impl EpipolarSampling {
    /// Yusov's settings for a `width` x `height` target and a shadow map of side
    /// `shadow_size`: 512 slices of 256 samples, initial step 16, downscale 2, depth
    /// breaks at 3 % of the view depth, 32 correction steps, 256 reference steps, white
    /// light.
    pub fn new(width: u32, height: u32, shadow_size: u32) -> Self {
        Self {
            width,
            height,
            slices: 512,
            samples: 256,
            initial_step: 16,
            downscale: 2,
            shadow_size,
            depth_threshold: 0.03,
            fix_steps: 32,
            reference_steps: 256,
            colored: false,
        }
    }

    /// Checks every field against its valid range.
    pub fn validate(&self) -> Result<(), InvalidValue> {
        let within = |v: u32, lo: u32, hi: u32| (lo..=hi).contains(&v);
        check(
            within(self.width, 1, 16384),
            "EpipolarSampling.width",
            self.width,
            "[1, 16384] pixels",
        )?;
        check(
            within(self.height, 1, 16384),
            "EpipolarSampling.height",
            self.height,
            "[1, 16384] pixels",
        )?;
        check(
            within(self.slices, 4, 4096),
            "EpipolarSampling.slices",
            self.slices,
            "[4, 4096]",
        )?;
        check(
            within(self.samples, 128, 2048) && self.samples.is_multiple_of(128),
            "EpipolarSampling.samples",
            self.samples,
            "a multiple of 128 in [128, 2048]",
        )?;
        check(
            matches!(self.initial_step, 8 | 16 | 32 | 64),
            "EpipolarSampling.initial_step",
            self.initial_step,
            "8, 16, 32 or 64",
        )?;
        check(
            matches!(self.downscale, 1 | 2 | 4),
            "EpipolarSampling.downscale",
            self.downscale,
            "1, 2 or 4",
        )?;
        check(
            within(self.shadow_size, 64, 4096) && self.shadow_size.is_power_of_two(),
            "EpipolarSampling.shadow_size",
            self.shadow_size,
            "a power of two in [64, 4096] texels",
        )?;
        check(
            self.depth_threshold > 0.0 && self.depth_threshold <= 10.0,
            "EpipolarSampling.depth_threshold",
            self.depth_threshold,
            "(0, 10]",
        )?;
        check(
            within(self.fix_steps, 1, 4096),
            "EpipolarSampling.fix_steps",
            self.fix_steps,
            "[1, 4096]",
        )?;
        check(
            within(self.reference_steps, 1, 65536),
            "EpipolarSampling.reference_steps",
            self.reference_steps,
            "[1, 65536]",
        )
    }

    /// Size of the resolved (downscaled) texture.
    pub fn resolved_size(&self) -> (u32, u32) {
        (
            self.width.div_ceil(self.downscale),
            self.height.div_ceil(self.downscale),
        )
    }
}

/// The camera and light of one frame of shafts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EpipolarView {
    /// World -> view transform of the camera (rigid, looking down -Z).
    pub view_from_world: Mat4,
    /// Perspective projection (standard, reversed or infinite depth).
    pub clip_from_view: Mat4,
    /// World -> light clip space of the cascade the shafts are marched in
    /// (orthographic; `ShadowCascades::light_from_world` of that cascade).
    pub light_from_world: Mat4,
    /// Array layer of that cascade in the shadow map.
    pub cascade: u32,
    /// Rayleigh in-scatter colour (sun radiance times the Rayleigh share of the
    /// extinction), [0, 1e9] per channel; zero for fog without molecules.
    pub rayleigh: Vec3,
    /// Phase of the medium's sun lobe.
    pub phase: EpipolarPhase,
    /// View depth (m) where the march starts: 0 alone, the froxel far plane as the far
    /// field of a `VolumetricFog`.
    pub start_depth: f32,
    /// Longest view depth (m) marched (sky pixels stop here), > start_depth, <= 1e7.
    pub max_depth: f32,
    /// Added to the shadow depths before the lit test, in light depth units, [0, 1]:
    /// the usual bias against shadow acne where rays end on a receiver (about the depth
    /// change of a receiver across one or two shadow texels).
    pub depth_bias: f32,
}

/// One frame of epipolar sun shafts (WGSL `volfog::types::EpipolarFrame`, used by
/// `volfog::epipolar` and the `epipolar_*` passes). Build it with
/// [`EpipolarFrame::new`]; `Default` is a placeholder for layout probes.
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct EpipolarFrame {
    /// Inverse of the camera's projection.
    pub view_from_clip: Mat4,
    /// Camera view -> light clip space of the cascade.
    pub light_from_view: Mat4,
    /// The epipole in normalised device coordinates.
    pub light_screen: Vec2,
    /// Full-resolution target size, pixels.
    pub screen_size: Vec2,
    /// Rayleigh in-scatter colour.
    pub rayleigh: Vec3,
    /// View depth where the march starts (m).
    pub start_depth: f32,
    /// Epipolar slices.
    pub slices: u32,
    /// Samples per slice.
    pub samples: u32,
    /// Initial step between ray-marching samples.
    pub initial_step: u32,
    /// Shadow map side, texels.
    pub shadow_size: u32,
    /// Cascade layer.
    pub cascade: u32,
    /// Downscale factor of the resolve.
    pub downscale: u32,
    /// Steps of the correcting march.
    pub fix_steps: u32,
    /// 0 Henyey-Greenstein, 1 Cornette-Shanks.
    pub phase_model: u32,
    /// Relative depth-break threshold.
    pub depth_threshold: f32,
    /// Longest view depth marched (m).
    pub max_depth: f32,
    /// Steps of the reference march.
    pub reference_steps: u32,
    /// Shadow depth bias (light depth units).
    pub depth_bias: f32,
}

/// Largest |coordinate| of the epipole kept (a sun at 90 degrees from the view axis
/// projects to infinity; beyond this the lines are parallel to f32 precision).
pub const EPIPOLE_LIMIT: f32 = 1e6;

impl EpipolarFrame {
    /// The frame of a validated `sampling`, a camera and light `view`, and the
    /// medium's sun direction (world space, towards the sun; `HeightFog::sun_direction`
    /// of the medium before it is moved to view space).
    pub fn new(
        sampling: &EpipolarSampling,
        view: &EpipolarView,
        sun_direction: Vec3,
    ) -> Result<Self, InvalidValue> {
        sampling.validate()?;
        check(
            view.view_from_world.is_finite()
                && view.clip_from_view.is_finite()
                && view.light_from_world.is_finite(),
            "EpipolarView",
            (
                view.view_from_world,
                view.clip_from_view,
                view.light_from_world,
            ),
            "finite matrices",
        )?;
        let lw = view.light_from_world;
        check(
            lw.row(3).abs_diff_eq(Vec4::W, 1e-6) && lw.determinant().abs() > 1e-30,
            "EpipolarView.light_from_world",
            lw,
            "an invertible orthographic light projection (last row 0, 0, 0, 1)",
        )?;
        let view_from_clip = view.clip_from_view.inverse();
        check(
            view_from_clip.is_finite(),
            "EpipolarView.clip_from_view",
            view.clip_from_view,
            "an invertible perspective projection",
        )?;
        check(
            view.cascade < 2048,
            "EpipolarView.cascade",
            view.cascade,
            "[0, 2047]",
        )?;
        check(
            view.rayleigh.is_finite()
                && view.rayleigh.min_element() >= 0.0
                && view.rayleigh.max_element() <= 1e9,
            "EpipolarView.rayleigh",
            view.rayleigh,
            "[0, 1e9] per channel",
        )?;
        check(
            view.start_depth.is_finite() && view.start_depth >= 0.0,
            "EpipolarView.start_depth",
            view.start_depth,
            ">= 0 m",
        )?;
        check(
            view.max_depth > view.start_depth && view.max_depth <= 1e7,
            "EpipolarView.max_depth",
            view.max_depth,
            "(start_depth, 1e7] m",
        )?;
        check(
            (0.0..=1.0).contains(&view.depth_bias),
            "EpipolarView.depth_bias",
            view.depth_bias,
            "[0, 1] (light depth units)",
        )?;
        super::check_unit("HeightFog.sun_direction", sun_direction)?;
        let sun = view.view_from_world.transform_vector3(sun_direction);
        let clip = view.clip_from_view * sun.extend(0.0);
        let w = if clip.w.abs() < 1e-12 {
            1e-12_f32.copysign(clip.w)
        } else {
            clip.w
        };
        let light_screen = (clip.truncate().truncate() / w)
            .clamp(Vec2::splat(-EPIPOLE_LIMIT), Vec2::splat(EPIPOLE_LIMIT));
        Ok(Self {
            view_from_clip,
            light_from_view: lw * view.view_from_world.inverse(),
            light_screen,
            screen_size: Vec2::new(sampling.width as f32, sampling.height as f32),
            rayleigh: view.rayleigh,
            start_depth: view.start_depth,
            slices: sampling.slices,
            samples: sampling.samples,
            initial_step: sampling.initial_step,
            shadow_size: sampling.shadow_size,
            cascade: view.cascade,
            downscale: sampling.downscale,
            fix_steps: sampling.fix_steps,
            phase_model: match view.phase {
                EpipolarPhase::HenyeyGreenstein => 0,
                EpipolarPhase::CornetteShanks => 1,
            },
            depth_threshold: sampling.depth_threshold,
            max_depth: view.max_depth,
            reference_steps: sampling.reference_steps,
            depth_bias: view.depth_bias,
        })
    }

    /// The medium in the space the passes read it: `fog` (world space) moved to the
    /// camera's view space.
    pub fn medium(fog: &HeightFog, view_from_world: Mat4) -> HeightFog {
        fog.to_view_space(view_from_world)
    }
}
