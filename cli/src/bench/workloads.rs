//! The series measured every frame and the workloads that produce them.

use super::*;
use volfog::options::ShadowFilter;

/// Series measured each frame, in table order: (key, label).
pub(super) const SERIES: &[(&str, &str)] = &[
    ("inject", "inject 160x90x128"),
    ("inject_no_transmittance", "inject, light transmittance off"),
    ("inject_compare_2", "inject, compare, 2 taps #"),
    ("esm_downsample", "esm downsample (4 cascades) #"),
    ("esm_blur", "esm blur (x + y) #"),
    ("inject_esm", "inject, ESM filter #"),
    ("esm_filter_total", "esm passes + inject, ESM #"),
    ("temporal", "temporal 160x90x128"),
    ("scan", "scan 160x90x128"),
    ("cull", "froxel_cull, 1080p depth +"),
    ("inject_cull", "inject, depth culling +"),
    ("inject_checkerboard", "inject, checkerboard +"),
    ("inject_noise_texture", "inject, noise texture +"),
    ("inject_fast", "inject, all three, temporal fused +"),
    ("inject_fast_separate", "inject, all three, apart +"),
    ("temporal_cull", "temporal, depth culling +"),
    ("temporal_checkerboard", "temporal, checkerboard +"),
    ("temporal_fast", "temporal, all three, apart +"),
    ("scan_fast", "scan, depth culling +"),
    ("write", "write 160x90x128 (floor)"),
    ("copy", "copy 160x90x128 (floor)"),
    ("apply_1080p", "apply 1920x1080"),
    ("blit_1080p", "blit 1920x1080 (floor)"),
    ("apply_part_depth", "apply part: depth texel"),
    ("apply_part_unproject", "apply part: + view position"),
    ("apply_part_lookup", "apply part: + volume look-up"),
    ("apply_part_untaken", "apply part: tail not taken"),
    ("froxel_1080p", "froxel pipeline 1080p *"),
    ("froxel_fast_1080p", "froxel fast 1080p *+"),
    (
        "froxel_fast_separate_1080p",
        "froxel fast, temporal apart *+",
    ),
    ("raymarch_1080p", "raymarch 1080p, 64 steps"),
    ("froxel_720p", "froxel 720p camera **"),
    ("froxel_4k", "froxel 4K camera **"),
    ("apply_720p", "apply 1280x720"),
    ("apply_4k", "apply 3840x2160"),
    ("sky_solve", "sky solve 128x64 texels"),
    ("cloud_shadow_1080p", "cloud shadow 1920x1080"),
    ("distance_clouds_1080p", "distance clouds 1920x1080"),
    ("epipolar_tree", "epipolar min/max trees"),
    ("epipolar_march_tree", "epipolar march, tree"),
    ("epipolar_march_steps", "epipolar march, every section"),
    ("epipolar_1080p", "epipolar shafts 1080p ***"),
    ("epipolar_reference_1080p", "per-pixel shafts 1080p"),
    ("local_inject_compiled_out", "inject, 6 lights, None ++"),
    ("local_inject_unshadowed", "inject, 6 lights unshadowed ++"),
    ("local_inject_shadowed", "inject, 6 lights shadowed ++"),
    ("local_shadow_atlas", "local shadow atlas ++"),
    ("local_shadowed_total", "inject + atlas, shadowed ++"),
    ("local_inject_kept", "inject, 6 lights, maps kept ++"),
    ("local_kept_total", "inject + atlas, maps kept ++"),
    ("local_compare_unshadowed", "inject, compare, unshadowed ++"),
    ("local_compare_shadowed", "inject, compare, shadowed ++"),
    ("scan_transient_0", "scan, no transient light ~"),
    ("scan_transient_1", "scan, 1 transient light ~"),
    ("scan_transient_8", "scan, 8 transient lights ~"),
    ("inject_area_none", "inject, area variant, no area light"),
    ("inject_area_points", "inject, 4 point lights added"),
    ("inject_area_rects", "inject, 4 rectangle lights"),
    ("inject_area_disks", "inject, 4 disk lights"),
    ("inject_particles_0", "inject, particle variant, none"),
    ("inject_particles_1000", "inject, 1,000 particles"),
    ("inject_particles_10000", "inject, 10,000 particles"),
    ("medium_shadow", "medium_shadow pass, 64^3"),
    ("inject_medium_shadow", "inject, medium shadows"),
];

/// The target ratios taken frame by frame: (key, numerator series, denominator
/// series). Both sides run in the same frame, so a ratio is the median of the frames'
/// ratios and a frame slowed as a whole by the machine moves it less than a ratio of
/// medians taken over different frames (the raymarch runs in a few of them only).
pub(super) const PAIRED: &[(&str, &str, &str)] = &[
    ("scan_vs_copy", "scan", "copy"),
    ("apply_vs_blit", "apply_1080p", "blit_1080p"),
    ("raymarch_vs_froxel", "raymarch_1080p", "froxel_1080p"),
    ("inject_vs_write", "inject", "write"),
    ("inject_fast_vs_write", "inject_fast", "write"),
    (
        "raymarch_vs_froxel_fast",
        "raymarch_1080p",
        "froxel_fast_1080p",
    ),
    ("compare_vs_esm", "inject", "esm_filter_total"),
    ("compare_2_vs_esm", "inject_compare_2", "esm_filter_total"),
    (
        "transient_1_vs_none",
        "scan_transient_1",
        "scan_transient_0",
    ),
    (
        "transient_8_vs_none",
        "scan_transient_8",
        "scan_transient_0",
    ),
];

pub(super) fn froxel_cost(t: &PassTimings) -> f64 {
    t.cull + t.inject + t.temporal + t.scan
}

/// The configurations compared at 1080p with the baseline (no culling, every froxel
/// injected each frame, procedural noise, the temporal pass apart): depth culling, the
/// checkerboard, the noise texture, each with the temporal pass apart; all three with
/// the temporal blend fused into inject (the cheap path as `FogConfig::default`
/// builds it), and all three with the temporal pass apart.
pub(crate) fn variant_configs(base: &FogConfig) -> [FogConfig; 5] {
    let with = |depth_cull, amortize, noise_texture, fuse_temporal| FogConfig {
        depth_cull,
        amortize,
        noise_texture,
        fuse_temporal,
        ..base.clone()
    };
    [
        with(true, false, false, false),
        with(false, true, false, false),
        with(false, false, true, false),
        with(true, true, true, true),
        with(true, true, true, false),
    ]
}

/// The bench's baseline configuration: it times every pass apart, the temporal pass
/// included (no culling, every froxel injected, procedural noise), and tests the
/// shadows with `FogConfig::default`'s filter (the compare filter, one tap).
pub(crate) fn base_config() -> FogConfig {
    FogConfig {
        timestamps: true,
        depth_cull: false,
        amortize: false,
        noise_texture: false,
        fuse_temporal: false,
        ..FogConfig::default()
    }
}

/// `config` with its shadows tested by `filter`.
pub(super) fn with_filter(config: &FogConfig, filter: ShadowFilter) -> FogConfig {
    FogConfig {
        shadow_filter: filter,
        ..config.clone()
    }
}

/// The passes of the sun's ESM filter and the inject that reads it.
const ESM_PASSES: [FogPass; 3] = [FogPass::EsmDownsample, FogPass::EsmBlur, FogPass::Inject];

/// Frame counts of a run.
#[derive(Debug, Clone, Copy)]
pub(super) struct Plan {
    pub(super) warmup: u32,
    pub(super) frames: u32,
    pub(super) raymarch_frames: u32,
}

impl Plan {
    pub(super) fn new(args: &BenchArgs) -> Result<Self, BenchError> {
        let pick = |given: Option<u32>, quick: u32, default: u32| {
            given.unwrap_or(if args.quick { quick } else { default })
        };
        let frames = pick(args.frames, QUICK_FRAMES, DEFAULT_FRAMES);
        if frames == 0 {
            return Err(BenchError::NoFrames);
        }
        Ok(Self {
            warmup: pick(args.warmup, QUICK_WARMUP, DEFAULT_WARMUP),
            frames,
            raymarch_frames: pick(
                args.raymarch_frames,
                QUICK_RAYMARCH_FRAMES,
                DEFAULT_RAYMARCH_FRAMES,
            )
            .clamp(1, frames),
        })
    }

    /// Whether frame `f` is measured, and whether it runs the raymarch (the last
    /// warm-up frame and the first `raymarch_frames` measured ones).
    pub(super) fn frame(&self, f: u32) -> (bool, bool) {
        let measured = f >= self.warmup;
        let raymarch = if measured {
            f - self.warmup < self.raymarch_frames
        } else {
            f + 1 == self.warmup
        };
        (measured, raymarch)
    }
}

/// Every workload of a frame, built once.
pub(super) struct Workloads {
    pub(super) config: FogConfig,
    pub(super) scene: Scene,
    pub(super) cascades: volfog::uniforms::ShadowCascades,
    pub(super) main: Screen,
    /// Culling, checkerboard, noise texture, all three fused, all three with the
    /// temporal pass apart (see [`variant_configs`]).
    pub(super) variants: [Screen; 5],
    /// The baseline with `FogConfig::light_transmittance` off.
    pub(super) untransmitted: Screen,
    /// The baseline with the ESM filter (`ShadowFilter::Esm`): its ESM passes and
    /// inject run each frame, and the raymarch reads its filtered ESM.
    pub(super) esm: Screen,
    /// The baseline with the compare filter at two taps: its inject runs each frame.
    pub(super) compare_2: Screen,
    pub(super) small: Screen,
    pub(super) large: Screen,
    pub(super) write: VolumePass,
    pub(super) copy: VolumePass,
    pub(super) blit: BlitPass,
    /// The apply pass's stages over the main screen.
    pub(super) apply_parts: ApplyParts,
    /// Share of the main screen's pixels beyond the fog's far plane.
    pub(super) beyond_far: f64,
    pub(super) reference: Raymarch,
    pub(super) reference_group: wgpu::BindGroup,
    pub(super) reference_target: wgpu::TextureView,
    pub(super) timer: Timer,
    /// The sky light and the cloud passes over the main screen's depth.
    pub(super) atmosphere: Atmosphere,
    /// Epipolar sun shafts over the main screen's depth.
    pub(super) shafts: Shafts,
    /// Four spot and two point lights, unshadowed, shadowed and without local shadows
    /// compiled in, over the main screen.
    pub(super) local_lights: LocalLights,
    /// The baseline's scan with 0, 1 and 8 transient lights.
    pub(super) transient: TransientLights,
    /// The baseline's inject with four point, rectangle or disk lights added.
    pub(super) area_lights: AreaLights,
    /// The baseline's inject with 0, 1,000 and 10,000 particles.
    pub(super) particles: Particles,
    /// The baseline with the medium's shadows: their pass and inject.
    pub(super) medium_shadows: MediumShadows,
}

impl Workloads {
    pub(super) fn new(gpu: &Gpu) -> Result<Self, BenchError> {
        let config = base_config();
        let scene = Scene::new();
        eprintln!("preparing the scene (shadow cascades, depth buffers, pipelines)...");
        let (cascades, layers) = scene.cascades(&config);
        let shadow_size = config.esm_resolution * 4;
        let layer_refs: Vec<&[f32]> = layers.iter().map(Vec::as_slice).collect();
        let shadow_map = volfog_testkit::selfcheck::depth_array_texture(
            gpu,
            shadow_size,
            shadow_size,
            &layer_refs,
        )?;
        let depth = Screen::scene_depth(gpu, &scene, SCREEN)?;
        let main = Screen::new(gpu, &config, &shadow_map, &depth, SCREEN)?;
        let [a, b, c, d, e] = variant_configs(&config);
        let variants = [
            Screen::new(gpu, &a, &shadow_map, &depth, SCREEN)?,
            Screen::new(gpu, &b, &shadow_map, &depth, SCREEN)?,
            Screen::new(gpu, &c, &shadow_map, &depth, SCREEN)?,
            Screen::new(gpu, &d, &shadow_map, &depth, SCREEN)?,
            Screen::new(gpu, &e, &shadow_map, &depth, SCREEN)?,
        ];
        let untransmitted = Screen::new(
            gpu,
            &FogConfig {
                light_transmittance: false,
                ..config.clone()
            },
            &shadow_map,
            &depth,
            SCREEN,
        )?;
        let esm = Screen::new(
            gpu,
            &with_filter(&config, ShadowFilter::Esm),
            &shadow_map,
            &depth,
            SCREEN,
        )?;
        let compare_2 = Screen::new(
            gpu,
            &with_filter(&config, ShadowFilter::Compare { taps: 2 }),
            &shadow_map,
            &depth,
            SCREEN,
        )?;
        let small_depth = Screen::scene_depth(gpu, &scene, SMALL_SCREEN)?;
        let small = Screen::new(gpu, &config, &shadow_map, &small_depth, SMALL_SCREEN)?;
        let large_depth = Screen::scene_depth(gpu, &scene, LARGE_SCREEN)?;
        let large = Screen::new(gpu, &config, &shadow_map, &large_depth, LARGE_SCREEN)?;
        let write = VolumePass::write(gpu, main.fog.scattering_texture().size())?;
        let copy = VolumePass::copy(gpu, main.fog.scattering_texture())?;
        let blit = BlitPass::new(gpu, SCREEN, COLOR_FORMAT)?;
        let apply_parts = ApplyParts::new(gpu, &main, &config)?;
        let beyond_far = {
            let depths = scene.depth_buffer(SCREEN.0, SCREEN.1);
            let view_from_clip = scene.projection.inverse();
            let beyond = depths
                .iter()
                .filter(|&&d| {
                    -view_from_clip
                        .project_point3(glam::Vec3::new(0.0, 0.0, d))
                        .z
                        > config.far
                })
                .count();
            beyond as f64 / depths.len() as f64
        };
        let reference = Raymarch::new(
            &gpu.device,
            &RaymarchOptions {
                steps: RAYMARCH_STEPS,
                noise_octaves: config.noise_octaves,
                color_format: COLOR_FORMAT,
                max_lights: config.max_lights,
                max_local_volumes: config.max_local_volumes,
            },
        )?;
        let reference_target = texture_2d(
            &gpu.device,
            "bench raymarch target",
            SCREEN,
            COLOR_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        )
        .create_view(&Default::default());
        // The baseline's compare filter has no ESM (a 1 x 1 placeholder): the raymarch
        // reads the ESM fog's, filtered from the same shadow map and cascades each frame
        // before the raymarch runs.
        let esm_view = esm
            .fog
            .esm_texture()
            .create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            });
        let shafts = Shafts::new(gpu, &scene, &cascades, &depth, &shadow_map)?;
        let reference_group = reference.bind_group(&gpu.device, &esm_view, &main.depth);
        let local_lights = LocalLights::new(gpu, &config, &scene, &shadow_map, &depth)?;
        let transient = TransientLights::new(gpu, &config, &scene, cascades, &shadow_map, &depth)?;
        let area_lights = AreaLights::new(gpu, &config, &scene, cascades, &shadow_map, &depth)?;
        let particles = Particles::new(gpu, &config, &scene, cascades, &shadow_map, &depth)?;
        let medium_shadows =
            MediumShadows::new(gpu, &config, &scene, cascades, &shadow_map, &depth)?;
        Ok(Self {
            config,
            scene,
            cascades,
            main,
            variants,
            untransmitted,
            esm,
            compare_2,
            small,
            large,
            write,
            copy,
            blit,
            apply_parts,
            beyond_far,
            reference,
            reference_group,
            reference_target,
            timer: Timer::new(gpu, 8 + APPLY_PARTS.len() as u32),
            atmosphere: Atmosphere::new(gpu, &depth)?,
            shafts,
            local_lights,
            transient,
            area_lights,
            particles,
            medium_shadows,
        })
    }

    /// Runs frame `f` and returns its samples by series key.
    pub(super) fn frame(
        &mut self,
        gpu: &Gpu,
        f: u32,
        with_raymarch: bool,
    ) -> Result<Vec<(&'static str, Sample)>, BenchError> {
        let inputs = self.scene.inputs(f as f32 / 60.0, self.cascades);
        let [v0, v1, v2, v3, v4] = &mut self.variants;
        for s in [
            &mut self.main,
            &mut self.small,
            &mut self.large,
            &mut self.untransmitted,
            &mut self.esm,
            &mut self.compare_2,
            v0,
            v1,
            v2,
            v3,
            v4,
        ] {
            s.fog.prepare(&gpu.queue, &inputs)?;
        }
        // The baseline (the compare filter, one tap), the same without light
        // transmittance, the ESM filter's passes and inject, and the compare filter's
        // inject at two taps, rotating which runs first from frame to frame so that
        // drift cancels; the floors right after the baseline, whose passes they are
        // compared with.
        let timer = &self.timer;
        let (copy, write, blit) = (&self.copy, &self.write, &self.blit);
        let floors = || -> Result<[Sample; 3], BenchError> {
            Ok([
                timer.run(gpu, 0, |e| copy.encode(e, timer, 0))?,
                timer.run(gpu, 3, |e| write.encode(e, timer, 3))?,
                timer.run(gpu, 1, |e| blit.encode(e, timer, 1))?,
            ])
        };
        let (mut main, mut floor_t, mut untransmitted, mut esm, mut compare_2) =
            (None, None, None, None, None);
        for k in 0..4 {
            match (k + f) % 4 {
                0 => {
                    main = Some(self.main.frame(gpu)?);
                    floor_t = Some(floors()?);
                }
                1 => untransmitted = Some(self.untransmitted.frame(gpu)?),
                2 => esm = Some(self.esm.passes(gpu, &ESM_PASSES, false)?),
                _ => compare_2 = Some(self.compare_2.passes(gpu, &[FogPass::Inject], false)?),
            }
        }
        let ran = "every fog runs once in the rotation";
        let (main, [copy_t, write_t, blit_t]) = (main.expect(ran), floor_t.expect(ran));
        let (untransmitted, esm) = (untransmitted.expect(ran), esm.expect(ran));
        let compare_2 = compare_2.expect(ran);
        let mut variants = Vec::new();
        for s in &mut self.variants[..3] {
            variants.push(s.frame(gpu)?);
        }
        // The cheap path fused and apart, in alternating order.
        let [.., fused, apart] = &mut self.variants;
        let (fast, separate) = if f.is_multiple_of(2) {
            let fast = fused.frame(gpu)?;
            (fast, apart.frame(gpu)?)
        } else {
            let separate = apart.frame(gpu)?;
            (fused.frame(gpu)?, separate)
        };
        let mut part_t = Vec::new();
        for part in 0..APPLY_PARTS.len() {
            let slot = 8 + part as u32;
            part_t.push(timer.run(gpu, slot, |e| {
                self.apply_parts.encode(e, &self.main, part, timer, slot)
            })?);
        }
        let [sky_t, shadow_t, clouds_t] = self.atmosphere.frame(gpu, timer, f)?;
        let shafts = self.shafts.frame(gpu, timer, with_raymarch)?;
        let local = self.local_lights.frame(gpu, &inputs, f)?;
        let transient = self.transient.frame(gpu, &inputs, f)?;
        let area = self.area_lights.frame(gpu, &inputs, f)?;
        let particles = self.particles.frame(gpu, &inputs, f)?;
        let medium = self.medium_shadows.frame(gpu, &inputs)?;
        let index = self.main.fog.frame_index().expect("prepared above");
        let uniforms = inputs.uniforms(&self.config, index)?;
        self.reference.upload(
            &gpu.queue,
            &uniforms,
            &self.scene.lights,
            &self.scene.local_volumes,
        );
        let raymarch_t = if with_raymarch {
            Some(timer.run(gpu, 2, |e| {
                self.reference.draw(
                    e,
                    &self.reference_target,
                    &self.reference_group,
                    timer.render(2),
                )
            })?)
        } else {
            None
        };
        // The two cameras, SCREEN_PAIRS times, the order alternating from pair to pair
        // and frame to frame so that drift cancels.
        let mut screens = Vec::new();
        for pair in 0..SCREEN_PAIRS {
            screens.push(if (f + pair).is_multiple_of(2) {
                let ts = self.small.frame(gpu)?;
                (ts, self.large.frame(gpu)?)
            } else {
                let tl = self.large.frame(gpu)?;
                (self.small.frame(gpu)?, tl)
            });
        }
        let both = |pick: &dyn Fn(&PassTimings) -> f64, t: &(PassTimings, PassTimings)| Sample {
            gpu: pick(&t.0),
            cpu: pick(&t.1),
        };
        let mut samples = vec![
            ("cull", both(&|p| p.cull, &fast)),
            ("inject_cull", both(&|p| p.inject, &variants[0])),
            ("inject_checkerboard", both(&|p| p.inject, &variants[1])),
            ("inject_noise_texture", both(&|p| p.inject, &variants[2])),
            ("inject_fast", both(&|p| p.inject, &fast)),
            ("inject_fast_separate", both(&|p| p.inject, &separate)),
            ("temporal_cull", both(&|p| p.temporal, &variants[0])),
            ("temporal_checkerboard", both(&|p| p.temporal, &variants[1])),
            ("temporal_fast", both(&|p| p.temporal, &separate)),
            ("scan_fast", both(&|p| p.scan, &variants[0])),
            ("write", write_t),
            (
                "froxel_fast_1080p",
                both(&|p| froxel_cost(p) + p.apply, &fast),
            ),
            (
                "froxel_fast_separate_1080p",
                both(&|p| froxel_cost(p) + p.apply, &separate),
            ),
            ("inject", both(&|p| p.inject, &main)),
            (
                "inject_no_transmittance",
                both(&|p| p.inject, &untransmitted),
            ),
            ("inject_compare_2", both(&|p| p.inject, &compare_2)),
            ("esm_downsample", both(&|p| p.esm_downsample, &esm)),
            ("esm_blur", both(&|p| p.esm_blur, &esm)),
            ("inject_esm", both(&|p| p.inject, &esm)),
            (
                "esm_filter_total",
                both(&|p| p.esm_downsample + p.esm_blur + p.inject, &esm),
            ),
            ("temporal", both(&|p| p.temporal, &main)),
            ("scan", both(&|p| p.scan, &main)),
            ("copy", copy_t),
            ("apply_1080p", both(&|p| p.apply, &main)),
            ("blit_1080p", blit_t),
            ("apply_part_depth", part_t[0]),
            ("apply_part_unproject", part_t[1]),
            ("apply_part_lookup", part_t[2]),
            ("apply_part_untaken", part_t[3]),
            ("froxel_1080p", both(&|p| froxel_cost(p) + p.apply, &main)),
            ("sky_solve", sky_t),
            ("cloud_shadow_1080p", shadow_t),
            ("distance_clouds_1080p", clouds_t),
        ];
        for (ts, tl) in &screens {
            samples.extend([
                ("froxel_720p", both(&froxel_cost, ts)),
                ("froxel_4k", both(&froxel_cost, tl)),
                ("apply_720p", both(&|p| p.apply, ts)),
                ("apply_4k", both(&|p| p.apply, tl)),
            ]);
        }
        samples.extend([
            ("epipolar_tree", shafts.tree),
            ("epipolar_march_tree", shafts.march_tree),
            ("epipolar_march_steps", shafts.march_steps),
            ("epipolar_1080p", shafts.total),
            ("local_inject_compiled_out", local.inject_compiled_out),
            ("local_inject_unshadowed", local.inject_unshadowed),
            ("local_inject_shadowed", local.inject_shadowed),
            ("local_shadow_atlas", local.atlas),
            ("local_shadowed_total", local.inject_shadowed + local.atlas),
            ("local_inject_kept", local.inject_kept),
            ("local_kept_total", local.inject_kept + local.atlas_kept),
            ("local_compare_unshadowed", local.compare_unshadowed),
            ("local_compare_shadowed", local.compare_shadowed),
            ("scan_transient_0", transient.none),
            ("scan_transient_1", transient.one),
            ("scan_transient_8", transient.eight),
            ("inject_area_none", area.none),
            ("inject_area_points", area.points),
            ("inject_area_rects", area.rects),
            ("inject_area_disks", area.disks),
            ("inject_particles_0", particles.none),
            ("inject_particles_1000", particles.some),
            ("inject_particles_10000", particles.most),
            ("medium_shadow", medium.pass),
            ("inject_medium_shadow", medium.inject),
        ]);
        samples.extend(raymarch_t.map(|r| ("raymarch_1080p", r)));
        samples.extend(shafts.reference.map(|r| ("epipolar_reference_1080p", r)));
        Ok(samples)
    }
}
