//! What the bench times besides the fog's floors (`floors.rs`): timestamp pairs, the
//! screens (a camera with its apply target), the sky and clouds, and the epipolar sun
//! shafts.

use super::*;

/// Timestamp queries of the bench's own passes (begin/end pair per pass).
pub(super) struct Timer {
    pub(super) pairs: TimestampPairs,
}

impl Timer {
    pub(super) fn new(gpu: &Gpu, pairs: u32) -> Self {
        Self {
            pairs: TimestampPairs::new(&gpu.device, "bench timestamps", pairs),
        }
    }

    pub(super) fn compute(&self, pass: u32) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        Some(self.pairs.compute(pass))
    }

    pub(super) fn render(&self, pass: u32) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        Some(self.pairs.render(pass, true, true))
    }

    /// Records one pass with `record` (which uses the timestamp writes of `slot`),
    /// submits it alone and returns its time by both clocks.
    pub(super) fn run(
        &self,
        gpu: &Gpu,
        slot: u32,
        record: impl FnOnce(&mut wgpu::CommandEncoder),
    ) -> Result<Sample, BenchError> {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        record(&mut encoder);
        self.pairs.resolve(&mut encoder);
        let cpu = submit_and_wait(gpu, encoder.finish())?;
        let gpu_ms = self
            .pairs
            .read_ms(&gpu.device, &gpu.queue)
            .map_err(|e| BenchError::Readback(e.to_string()))?[slot as usize];
        Ok(Sample { gpu: gpu_ms, cpu })
    }
}

pub(super) fn depth_view(texture: &wgpu::Texture) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        aspect: wgpu::TextureAspect::DepthOnly,
        ..Default::default()
    })
}

/// One screen the froxel pipeline is applied to: its `VolumetricFog`, apply pass,
/// depth group and colour target.
pub(super) struct Screen {
    pub(super) fog: VolumetricFog,
    pub(super) apply: ApplyPipeline,
    pub(super) depth: wgpu::TextureView,
    pub(super) depth_group: wgpu::BindGroup,
    pub(super) color: wgpu::TextureView,
}

impl Screen {
    /// The scene's depth buffer at `size` (traced on the CPU).
    pub(super) fn scene_depth(
        gpu: &Gpu,
        scene: &Scene,
        size: (u32, u32),
    ) -> Result<wgpu::Texture, BenchError> {
        Ok(volfog_testkit::selfcheck::depth_texture(
            gpu,
            size.0,
            size.1,
            &scene.depth_buffer(size.0, size.1),
        )?)
    }

    /// A fog of `config` behind a camera of `size` whose depth buffer is `depth`; the
    /// fog culls by that depth when `config.depth_cull` is set.
    pub(super) fn new(
        gpu: &Gpu,
        config: &FogConfig,
        shadow_map: &wgpu::Texture,
        depth: &wgpu::Texture,
        size: (u32, u32),
    ) -> Result<Self, BenchError> {
        let mut fog = VolumetricFog::new(&gpu.device, config)?;
        fog.set_shadow_map(&gpu.device, shadow_map)?;
        if config.depth_cull {
            fog.set_scene_depth(&gpu.device, depth, 0)?;
        }
        let apply = fog.create_apply(&gpu.device, COLOR_FORMAT)?;
        let depth = depth_view(depth);
        let depth_group = apply.depth_bind_group(&gpu.device, &depth);
        let color = texture_2d(
            &gpu.device,
            "bench colour",
            size,
            COLOR_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        Ok(Self {
            fog,
            apply,
            depth,
            depth_group,
            color: color.create_view(&Default::default()),
        })
    }

    /// Runs one frame, each pass (and the apply) submitted alone; returns its pass
    /// timings by both clocks.
    pub(super) fn frame(&mut self, gpu: &Gpu) -> Result<(PassTimings, PassTimings), BenchError> {
        self.passes(gpu, &FogPass::ALL, true)
    }

    /// Runs `passes` of the prepared frame in order (a pass that does not run in this
    /// configuration records nothing), then the apply when `apply` is set, each
    /// submitted alone; returns their timings by both clocks (0 for those not run).
    pub(super) fn passes(
        &mut self,
        gpu: &Gpu,
        passes: &[FogPass],
        apply: bool,
    ) -> Result<(PassTimings, PassTimings), BenchError> {
        let mut gpu_ms = PassTimings::default();
        let mut wall_ms = PassTimings::default();
        let passes = passes
            .iter()
            .copied()
            .map(Some)
            .chain(apply.then_some(None));
        for pass in passes {
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            match pass {
                Some(pass) => self.fog.encode_pass(&mut encoder, pass)?,
                None => self.fog.record_apply(
                    &mut encoder,
                    &self.apply,
                    &self.color,
                    &self.depth_group,
                )?,
            }
            self.fog.resolve_timestamps(&mut encoder);
            *timing(&mut wall_ms, pass) = submit_and_wait(gpu, encoder.finish())?;
            let mut t = self
                .fog
                .read_timings(&gpu.device, &gpu.queue)
                .ok_or_else(|| BenchError::Readback("VolumetricFog::read_timings".to_string()))?;
            *timing(&mut gpu_ms, pass) = *timing(&mut t, pass);
        }
        Ok((gpu_ms, wall_ms))
    }
}

/// The field of `timings` that holds `pass` (`None`: the apply).
fn timing(timings: &mut PassTimings, pass: Option<FogPass>) -> &mut f64 {
    match pass {
        Some(FogPass::Cull) => &mut timings.cull,
        Some(FogPass::EsmDownsample) => &mut timings.esm_downsample,
        Some(FogPass::EsmBlur) => &mut timings.esm_blur,
        Some(FogPass::LocalShadows) => &mut timings.local_shadows,
        Some(FogPass::MediumShadow) => &mut timings.medium_shadow,
        Some(FogPass::Inject) => &mut timings.inject,
        Some(FogPass::Temporal) => &mut timings.temporal,
        Some(FogPass::Scan) => &mut timings.scan,
        None => &mut timings.apply,
    }
}

/// The sky and the clouds over the main screen: the whole sky texture solved per
/// frame, the clouds' shadow and the distance clouds at 1080p (default sample counts:
/// 128 view and 32 sun samples per texel; 12 view and 4 sun samples per pixel).
pub(super) struct Atmosphere {
    sky: volfog::pipeline::sky::SkyLight,
    clouds: volfog::pipeline::clouds::CloudPasses,
    group: wgpu::BindGroup,
    target: wgpu::TextureView,
}

impl Atmosphere {
    pub(super) fn new(gpu: &Gpu, depth: &wgpu::Texture) -> Result<Self, BenchError> {
        use volfog::pipeline::clouds::CloudPasses;
        use volfog::pipeline::sky::SkyLight;
        use volfog::uniforms::SkyAtmosphere;
        let mut sky = SkyLight::new(&gpu.device, COLOR_FORMAT)?;
        let sun = glam::Vec3::new(0.3, 0.35, -0.9).normalize();
        sky.set_atmosphere(SkyAtmosphere::earth(sun)?)?;
        let clouds = CloudPasses::new(&gpu.device, COLOR_FORMAT)?;
        let n = 128u32;
        let densities: Vec<f32> = (0..n * n)
            .map(|i| {
                let (x, y) = ((i % n) as f32, (i / n) as f32);
                0.5 + 0.5 * (x * 0.21).sin() * (y * 0.17).cos()
            })
            .collect();
        let map = volfog::pipeline::clouds::cloud_map_texture(
            &gpu.device,
            &gpu.queue,
            (n, n),
            &densities,
        )?;
        let group = clouds.bind_group(
            &gpu.device,
            &map.create_view(&Default::default()),
            &depth_view(depth),
        );
        let target = texture_2d(
            &gpu.device,
            "bench clouds target",
            SCREEN,
            COLOR_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        )
        .create_view(&Default::default());
        Ok(Self {
            sky,
            clouds,
            group,
            target,
        })
    }

    /// The sky solve, the cloud shadow and the distance clouds of frame `f`, each
    /// submitted alone (timer slots 4, 5, 6).
    pub(super) fn frame(
        &mut self,
        gpu: &Gpu,
        timer: &Timer,
        f: u32,
    ) -> Result<[Sample; 3], BenchError> {
        use volfog::pipeline::clouds::CloudDraw;
        use volfog::uniforms::{CloudLayer, FrustumRays};
        let proj = volfog_testkit::scene::projection();
        let view = volfog_testkit::scene::view(2.0, 0.15);
        let rays = FrustumRays::new(view.inverse(), proj)?;
        self.sky.prepare(&gpu.queue, &rays, 64)?;
        let layer = CloudLayer::new(800.0, 200.0, 0.01, 2000.0)
            .and_then(|l| {
                l.with_sun(
                    glam::Vec3::new(0.3, 0.35, -0.9).normalize(),
                    glam::Vec3::splat(4.0),
                    glam::Vec3::splat(0.3),
                    0.6,
                )
            })
            .and_then(|l| l.with_wind(glam::Vec2::new(8.0, 2.0), f as f32 / 60.0))?;
        self.clouds.prepare(&gpu.queue, &rays, &layer)?;
        let sky_t = timer.run(gpu, 4, |e| self.sky.encode_solve_timed(e, timer.compute(4)))?;
        let draw = |slot: u32, what: CloudDraw| {
            timer.run(gpu, slot, |e| {
                let mut pass =
                    raymarch::fullscreen_pass(e, "bench clouds", &self.target, timer.render(slot));
                self.clouds.draw(&mut pass, &self.group, what);
            })
        };
        let shadow_t = draw(5, CloudDraw::Shadow)?;
        let clouds_t = draw(6, CloudDraw::Distance)?;
        Ok([sky_t, shadow_t, clouds_t])
    }
}

/// Epipolar sun shafts over the main screen (`EpipolarShafts`, default sampling: 512
/// slices of 256 samples, initial step 16, downscale 2) in the scene's height fog,
/// marched in its outermost cascade: every pass of the tree path, the march of the
/// same samples without the tree, and the per-pixel brute-force reference.
pub(super) struct Shafts {
    shafts: volfog::pipeline::epipolar::EpipolarShafts,
    /// The same with a finer per-pixel reference ([`FINE_REFERENCE_STEPS`]), for the
    /// image error only.
    fine: volfog::pipeline::epipolar::EpipolarShafts,
}

/// Steps per pixel of the fine reference the image error is measured against (the
/// timed reference takes the default 256, about the shadow texels a ray crosses here).
pub(super) const FINE_REFERENCE_STEPS: u32 = 2048;

/// Samples of one frame of [`Shafts`].
pub(super) struct ShaftSamples {
    /// Every pass of the tree path.
    pub(super) total: Sample,
    /// The tree build.
    pub(super) tree: Sample,
    /// The tree march.
    pub(super) march_tree: Sample,
    /// The march of the same samples over every section.
    pub(super) march_steps: Sample,
    /// The per-pixel reference, when run.
    pub(super) reference: Option<Sample>,
}

impl Shafts {
    pub(super) fn new(
        gpu: &Gpu,
        scene: &Scene,
        cascades: &volfog::uniforms::ShadowCascades,
        depth: &wgpu::Texture,
        shadow_map: &wgpu::Texture,
    ) -> Result<Self, BenchError> {
        use volfog::pipeline::epipolar::EpipolarShafts;
        use volfog::uniforms::{EpipolarPhase, EpipolarSampling, EpipolarView, HeightFog};
        let shadow_size = shadow_map.size().width;
        let sampling = EpipolarSampling::new(SCREEN.0, SCREEN.1, shadow_size);
        let mut shafts = EpipolarShafts::new(&gpu.device, sampling)?;
        shafts.set_inputs(&gpu.device, depth, shadow_map)?;
        let mut fine = EpipolarShafts::new(
            &gpu.device,
            EpipolarSampling {
                reference_steps: FINE_REFERENCE_STEPS,
                ..sampling
            },
        )?;
        fine.set_inputs(&gpu.device, depth, shadow_map)?;
        let last = cascades.count.max(1) - 1;
        let medium = HeightFog::from_medium(&scene.medium, glam::Vec3::splat(0.05)).with_sun(
            scene.sun.direction,
            scene.sun.color * scene.medium.albedo,
            scene.medium.phase_g,
        )?;
        let view = EpipolarView {
            view_from_world: scene.view,
            clip_from_view: scene.projection,
            light_from_world: cascades.light_from_world[last as usize],
            cascade: last,
            rayleigh: glam::Vec3::ZERO,
            phase: EpipolarPhase::HenyeyGreenstein,
            start_depth: 0.0,
            max_depth: 500.0,
            depth_bias: 0.002,
        };
        shafts.prepare(&gpu.queue, &view, &medium)?;
        fine.prepare(&gpu.queue, &view, &medium)?;
        Ok(Self { shafts, fine })
    }

    /// Every pass of the tree path, the steps march and (with `reference`) the
    /// reference, each submitted alone (timer slot 7).
    pub(super) fn frame(
        &self,
        gpu: &Gpu,
        timer: &Timer,
        reference: bool,
    ) -> Result<ShaftSamples, BenchError> {
        use volfog::pipeline::epipolar::{EpipolarMode, EpipolarPass};
        let run = |pass: EpipolarPass, mode: EpipolarMode| -> Result<Sample, BenchError> {
            let mut result = Ok(());
            let sample = timer.run(gpu, 7, |e| {
                result = self.shafts.encode_pass(e, pass, mode, timer.compute(7));
            })?;
            result?;
            Ok(sample)
        };
        let mut total = Sample::default();
        let (mut tree, mut march_tree) = (Sample::default(), Sample::default());
        for pass in EpipolarPass::of(EpipolarMode::Tree, self.shafts.sampling().downscale) {
            let t = run(pass, EpipolarMode::Tree)?;
            total = total + t;
            match pass {
                EpipolarPass::Tree => tree = t,
                EpipolarPass::March => march_tree = t,
                _ => {}
            }
        }
        let march_steps = run(EpipolarPass::March, EpipolarMode::Steps)?;
        let reference = if reference {
            Some(run(EpipolarPass::Reference, EpipolarMode::Reference)?)
        } else {
            None
        };
        Ok(ShaftSamples {
            total,
            tree,
            march_tree,
            march_steps,
            reference,
        })
    }

    /// The lit fraction of the tree path against the per-pixel references at 1080p
    /// (the timed one and the fine one), and the pixels the path corrected.
    pub(super) fn image_error(&self, gpu: &Gpu) -> Result<ShaftImage, BenchError> {
        use volfog::pipeline::epipolar::{EpipolarMode, EpipolarShafts};
        let read = |shafts: &EpipolarShafts, mode| -> Result<Vec<glam::Vec4>, BenchError> {
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            shafts.encode(&mut encoder, mode)?;
            submit_and_wait(gpu, encoder.finish())?;
            Ok(gpu.read_texture_rgba16f(shafts.shaft_texture())?)
        };
        let reference = read(&self.shafts, EpipolarMode::Reference)?;
        let fine = read(&self.fine, EpipolarMode::Reference)?;
        let image = read(&self.shafts, EpipolarMode::Tree)?;
        let corrected = self.shafts.read_corrected(&gpu.device)?;
        let errors = |against: &[glam::Vec4]| -> (f64, f64) {
            let mut e: Vec<f32> = image
                .iter()
                .zip(against)
                .map(|(a, b)| (a.x - b.x).abs())
                .collect();
            let mean = e.iter().map(|&v| f64::from(v)).sum::<f64>() / e.len() as f64;
            e.sort_by(f32::total_cmp);
            (mean, f64::from(e[e.len() * 99 / 100]))
        };
        let (mean, p99) = errors(&reference);
        let (fine_mean, fine_p99) = errors(&fine);
        let reference_vs_fine = reference
            .iter()
            .zip(&fine)
            .map(|(a, b)| f64::from((a.x - b.x).abs()))
            .sum::<f64>()
            / reference.len() as f64;
        Ok(ShaftImage {
            lit_fraction_mean_abs_error: mean,
            lit_fraction_p99_abs_error: p99,
            fine_mean_abs_error: fine_mean,
            fine_p99_abs_error: fine_p99,
            reference_vs_fine_mean_abs_error: reference_vs_fine,
            fine_reference_steps: FINE_REFERENCE_STEPS,
            corrected_pixels: corrected.0 + corrected.1,
            nan_pixels: image.iter().filter(|p| !p.is_finite()).count(),
            memory_bytes: self.shafts.memory_bytes(),
        })
    }
}
