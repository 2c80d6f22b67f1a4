//! Shadows and cookies of point and spot lights in [`VolumetricFog`](super::VolumetricFog):
//! the caller's depth maps and cookies, the local-light ESM atlas they are filtered into
//! (the ESM filter; the compare filter reads the maps themselves), and each frame's
//! [`ShadowedLight`]s turned into `LightProjection`s within the budget.

use std::ops::Range;

use super::atlas_layers::{LayerRequest, assign_layers, layer_runs};
use super::config::LocalShadowConfig;
use super::resources::{check_texture_binding, mismatch};
use super::{FogConfig, FogError, SHADOW_MAP_FORMATS, array_view, esm_texture, storage_buffer};
use crate::limits::{self, InvalidValue, check};
use crate::pipeline::esm::EsmPasses;
use crate::pipeline::inject::LocalShadowResources;
use crate::pipeline::local_shadow::LocalShadowPass;
use crate::uniforms::{
    self, FogLight, LOCAL_SHADOW_NONE, LightCamera, LightProjection, LocalShadowSource,
};

/// A point or spot light of the frame with its shadow camera: its shadow map among the
/// caller's depth maps and, for a spot light, its cookie (see
/// [`VolumetricFog::set_spot_shadow_maps`], [`VolumetricFog::set_point_shadow_maps`]
/// and [`VolumetricFog::set_cookies`]).
///
/// ```
/// use glam::Vec3;
/// use volfog::pipeline::ShadowedLight;
/// use volfog::uniforms::{FogLight, LightCamera};
///
/// let lamp = FogLight::spot(Vec3::new(0.0, 3.0, 0.0), Vec3::NEG_Y, Vec3::splat(20.0), 12.0, 0.4, 0.6);
/// // The camera the lamp's shadow map was rendered with (here volfog's own choice),
/// // its layer 0 of the spot shadow maps, and cookie layer 2.
/// let camera = LightCamera::spot(&lamp, 0.1).unwrap();
/// let shadowed = ShadowedLight::new(0, camera).with_shadow(0).with_cookie(2);
/// assert_eq!(shadowed.shadow, Some(0));
/// // A later frame, its shadow map not rendered again: the atlas keeps its filtering.
/// let cached = shadowed.with_unchanged_map();
/// assert!(cached.map_unchanged);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadowedLight {
    /// Index of the light in [`FrameInputs::lights`](super::FrameInputs::lights).
    pub light: u32,
    /// The camera its depth map was rendered with (and its cookie projects through).
    pub camera: LightCamera,
    /// Its shadow map: a layer of the spot shadow maps (a spot camera) or a cube of the
    /// point shadow maps (a point camera: layers `6 * cube ..`); `None`: unshadowed.
    pub shadow: Option<u32>,
    /// A layer of the cookie array the spot light projects; `None`: no cookie.
    pub cookie: Option<u32>,
    /// Receivers are tested this much nearer the light (m), see
    /// [`limits::LOCAL_SHADOW_BIAS`].
    pub bias: f32,
    /// Its shadow map holds what it held the last time a frame filtered it into the
    /// atlas (a static light whose map is rendered once, or rendered every few
    /// frames): the atlas keeps that filtering if its layers still hold it (same map,
    /// camera depth terms, range and exponent, not taken by another light since), and
    /// the frame filters only the other lights' maps. Setting new depth maps
    /// ([`VolumetricFog::set_spot_shadow_maps`], [`VolumetricFog::set_point_shadow_maps`])
    /// forgets every filtering. `false` (the default): filtered every frame.
    pub map_unchanged: bool,
}

impl ShadowedLight {
    /// Light `light` seen from `camera`, without shadow map or cookie yet.
    pub fn new(light: u32, camera: LightCamera) -> Self {
        Self {
            light,
            camera,
            shadow: None,
            cookie: None,
            bias: 0.0,
            map_unchanged: false,
        }
    }

    /// With its shadow map: the spot layer, or the point cube index.
    pub fn with_shadow(self, map: u32) -> Self {
        Self {
            shadow: Some(map),
            ..self
        }
    }

    /// With a cookie (spot lights).
    pub fn with_cookie(self, layer: u32) -> Self {
        Self {
            cookie: Some(layer),
            ..self
        }
    }

    /// With its shadow map unchanged since a frame last filtered it (see
    /// [`ShadowedLight::map_unchanged`]).
    pub fn with_unchanged_map(self) -> Self {
        Self {
            map_unchanged: true,
            ..self
        }
    }
}

/// What the prepared frame's shadowed lights got (see [`VolumetricFog::local_shadow_stats`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LocalShadowStats {
    /// Spot lights shadowed through the atlas.
    pub spot_shadows: u32,
    /// Point lights shadowed through the atlas.
    pub point_shadows: u32,
    /// Lights with a shadow map beyond the budget of their kind, lit unshadowed.
    pub unshadowed: u32,
    /// Atlas layers filled this frame.
    pub layers: u32,
    /// Atlas layers of lights with [`ShadowedLight::map_unchanged`] kept from an
    /// earlier frame's filtering.
    pub kept: u32,
}

/// A frame's shadowed lights, checked and within the budget.
#[derive(Debug)]
pub(super) struct LocalShadowPlan {
    /// The frame's lights with their projection indices.
    pub(super) lights: Vec<FogLight>,
    projections: Vec<LightProjection>,
    /// The atlas maps the frame fills (the kept ones left out).
    sources: Vec<LocalShadowSource>,
    stats: LocalShadowStats,
}

/// The local-light shadows of a fog with `FogConfig::local_shadows`.
#[derive(Debug)]
pub(super) struct LocalShadows {
    config: LocalShadowConfig,
    /// The compare filter: inject reads the depth maps, there is no atlas.
    compare: bool,
    pass: LocalShadowPass,
    /// The atlas and the blur's scratch array, made when the first depth maps are set.
    atlas: Option<[wgpu::Texture; 2]>,
    /// Bound in place of the atlas and of a missing depth array: 1 x 1 x 1 R32Float.
    placeholder: wgpu::Texture,
    spot_maps: Option<wgpu::Texture>,
    point_maps: Option<wgpu::Texture>,
    cookies: Option<wgpu::Texture>,
    /// Bound while no cookies are set: 1 x 1 x 1 Rgba8Unorm.
    no_cookies: wgpu::Texture,
    cookie_sampler: wgpu::Sampler,
    sources: wgpu::Buffer,
    projections: wgpu::Buffer,
    groups: Option<AtlasGroups>,
    /// What each atlas layer holds: the source it was last filled from (`None`:
    /// nothing since the depth maps were set).
    held: Vec<Option<LocalShadowSource>>,
    /// The runs of consecutive layers the prepared frame fills, blurred a run at a time.
    runs: Vec<Range<u32>>,
    device: wgpu::Device,
    stats: LocalShadowStats,
    /// Whether a light of the prepared frame has a shadow or a cookie.
    projects: bool,
}

/// The bind groups that fill the atlas.
#[derive(Debug)]
struct AtlasGroups {
    downsample: wgpu::BindGroup,
    /// The blur of layers from 0 (x: atlas to scratch, y: back).
    blur: [wgpu::BindGroup; 2],
    /// The blur of runs that start past layer 0, made as frames need them: views of
    /// the run's layers alone.
    runs: Vec<(Range<u32>, [wgpu::BindGroup; 2])>,
}

fn small_texture(device: &wgpu::Device, label: &str, format: wgpu::TextureFormat) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: 1,
            height: 1,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    })
}

impl LocalShadows {
    pub(super) fn new(device: &wgpu::Device, config: &FogConfig) -> Result<Option<Self>, FogError> {
        let Some(local) = config.local_shadows else {
            return Ok(None);
        };
        let sources = uniforms::to_storage_bytes(&vec![
            LocalShadowSource::default();
            local.layers().max(1) as usize
        ]);
        let projections = uniforms::to_storage_bytes(&vec![
            LightProjection::default();
            config.max_lights.max(1) as usize
        ]);
        Ok(Some(Self {
            config: local,
            compare: config.shadow_filter.compares(),
            pass: LocalShadowPass::new(device, config.esm_log_space)?,
            atlas: None,
            placeholder: small_texture(
                device,
                "volfog no local shadows",
                wgpu::TextureFormat::R32Float,
            ),
            spot_maps: None,
            point_maps: None,
            cookies: None,
            no_cookies: small_texture(device, "volfog no cookies", wgpu::TextureFormat::Rgba8Unorm),
            cookie_sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("volfog cookies"),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                ..Default::default()
            }),
            sources: storage_buffer(device, "volfog local shadow sources", sources.len()),
            projections: storage_buffer(device, "volfog light projections", projections.len()),
            groups: None,
            held: vec![None; local.layers() as usize],
            runs: Vec::new(),
            device: device.clone(),
            stats: LocalShadowStats::default(),
            projects: false,
        }))
    }

    /// The views inject binds: the atlas, the cookies, the spot and the point maps
    /// (placeholders where there are none).
    pub(super) fn views(&self) -> [wgpu::TextureView; 4] {
        let atlas = self.atlas.as_ref().map_or(&self.placeholder, |a| &a[0]);
        let cookies = self.cookies.as_ref().unwrap_or(&self.no_cookies);
        let maps = |m: &Option<wgpu::Texture>| array_view(m.as_ref().unwrap_or(&self.placeholder));
        [
            array_view(atlas),
            array_view(cookies),
            maps(&self.spot_maps),
            maps(&self.point_maps),
        ]
    }

    pub(super) fn resources<'a>(
        &'a self,
        views: &'a [wgpu::TextureView; 4],
    ) -> LocalShadowResources<'a> {
        LocalShadowResources {
            atlas: &views[0],
            spot_maps: &views[2],
            point_maps: &views[3],
            projections: &self.projections,
            cookies: &views[1],
            cookie_sampler: &self.cookie_sampler,
        }
    }

    /// Checks and uses the spot lights' (`cube` false) or the point lights' depth maps.
    pub(super) fn set_maps(
        &mut self,
        device: &wgpu::Device,
        esm: &EsmPasses,
        texture: &wgpu::Texture,
        cube: bool,
    ) -> Result<(), FogError> {
        if cube {
            self.check_maps("the point shadow maps", texture, true)?;
            self.point_maps = Some(texture.clone());
        } else {
            self.check_maps("the spot shadow maps", texture, false)?;
            self.spot_maps = Some(texture.clone());
        }
        self.rebuild(device, esm);
        Ok(())
    }

    /// Uses the cookies (checked by the caller).
    pub(super) fn set_cookies(&mut self, texture: &wgpu::Texture) {
        self.cookies = Some(texture.clone());
    }

    /// What the prepared frame's shadowed lights got.
    pub(super) fn stats(&self) -> LocalShadowStats {
        self.stats
    }

    /// The atlas, once made (never with the compare filter).
    pub(super) fn atlas(&self) -> Option<&wgpu::Texture> {
        self.atlas.as_ref().map(|a| &a[0])
    }

    /// Makes the atlas (once) and the bind groups that fill it from the depth maps
    /// set so far (nothing with the compare filter).
    fn rebuild(&mut self, device: &wgpu::Device, esm: &EsmPasses) {
        if self.compare {
            return;
        }
        let (size, layers) = (self.config.resolution, self.config.layers().max(1));
        let atlas = self.atlas.get_or_insert_with(|| {
            [
                esm_texture(device, "volfog local shadow atlas", size, layers),
                esm_texture(device, "volfog local shadow scratch", size, layers),
            ]
        });
        let (atlas_view, scratch_view) = (array_view(&atlas[0]), array_view(&atlas[1]));
        let source =
            |maps: &Option<wgpu::Texture>| array_view(maps.as_ref().unwrap_or(&self.placeholder));
        self.groups = Some(AtlasGroups {
            downsample: self.pass.bind_group(
                device,
                &self.sources,
                &source(&self.spot_maps),
                &source(&self.point_maps),
                &atlas_view,
            ),
            blur: [
                esm.blur_bind_group(device, &atlas_view, &scratch_view),
                esm.blur_bind_group(device, &scratch_view, &atlas_view),
            ],
            runs: Vec::new(),
        });
        // New depth maps: no layer holds their filtering yet.
        self.held.fill(None);
    }

    /// Checks a depth array of the lights' shadow maps: square, a whole multiple of the
    /// atlas resolution, single-sampled, a shadow-map format, `TEXTURE_BINDING`, and
    /// (`cube`) six layers a cube.
    fn check_maps(
        &self,
        what: &'static str,
        texture: &wgpu::Texture,
        cube: bool,
    ) -> Result<(), FogError> {
        let size = texture.size();
        let res = self.config.resolution;
        if texture.dimension() != wgpu::TextureDimension::D2 {
            return Err(mismatch(
                what,
                "dimension",
                texture.dimension(),
                "D2 (with array layers)".into(),
            ));
        }
        let factor = size.width / res;
        if size.width != size.height {
            return Err(mismatch(
                what,
                "size",
                (size.width, size.height),
                "square".into(),
            ));
        }
        // The atlas filters whole blocks of texels; the compare filter reads any size.
        if !self.compare
            && (!size.width.is_multiple_of(res) || !limits::LOCAL_SHADOW_FACTOR.contains(factor))
        {
            return Err(mismatch(
                what,
                "size",
                (size.width, size.height),
                format!(
                    "square, k x LocalShadowConfig.resolution = k x {res} texels for k in {}",
                    limits::LOCAL_SHADOW_FACTOR.describe()
                ),
            ));
        }
        if cube && !size.depth_or_array_layers.is_multiple_of(6) {
            return Err(mismatch(
                what,
                "layer count",
                size.depth_or_array_layers,
                "a multiple of 6 (a cube's faces +X, -X, +Y, -Y, +Z, -Z per light)".into(),
            ));
        }
        if !SHADOW_MAP_FORMATS.contains(&texture.format()) {
            return Err(mismatch(
                what,
                "format",
                texture.format(),
                format!("one of {SHADOW_MAP_FORMATS:?}"),
            ));
        }
        if texture.sample_count() != 1 {
            return Err(mismatch(
                what,
                "sample count",
                texture.sample_count(),
                "1".into(),
            ));
        }
        check_texture_binding(what, texture)
    }

    /// Checks the frame's shadowed lights and turns them into projections within the
    /// budget: the lights with their projection indices, the projections and the atlas
    /// maps to fill (those of lights with unchanged maps that the atlas still holds are
    /// kept). Writes nothing.
    pub(super) fn plan(
        &self,
        lights: &[FogLight],
        shadowed: &[ShadowedLight],
    ) -> Result<LocalShadowPlan, FogError> {
        let mut out: Vec<FogLight> = lights
            .iter()
            .map(|l| FogLight {
                projection: LOCAL_SHADOW_NONE,
                ..*l
            })
            .collect();
        // Each shadowed light with its cookie and its request for atlas layers.
        let mut entries = Vec::with_capacity(shadowed.len());
        let mut requests = Vec::new();
        let mut stats = LocalShadowStats::default();
        let (mut spots, mut points) = (0, 0);
        for s in shadowed {
            let light = lights.get(s.light as usize).ok_or_else(|| InvalidValue {
                field: "ShadowedLight.light",
                value: s.light.to_string(),
                expected: format!("an index into FrameInputs.lights (0..{})", lights.len()).into(),
            })?;
            check(
                out[s.light as usize].projection == LOCAL_SHADOW_NONE,
                "ShadowedLight.light",
                s.light,
                "each light at most once",
            )?;
            check(
                !light.is_directional(),
                "ShadowedLight.light",
                s.light,
                "a point or spot light (a directional FogLight has no shadow; the sun's is \
                 FrameInputs.cascades)",
            )?;
            let depth_terms = s.camera.depth_terms()?;
            let point = matches!(s.camera, LightCamera::Point { .. });
            let cookie = match s.cookie {
                None => LOCAL_SHADOW_NONE,
                Some(layer) => {
                    check(
                        !point,
                        "ShadowedLight.cookie",
                        layer,
                        "None for a point light (cookies are projected by spot lights)",
                    )?;
                    let layers = self
                        .cookies
                        .as_ref()
                        .map_or(0, |c| c.size().depth_or_array_layers);
                    check(
                        layer < layers,
                        "ShadowedLight.cookie",
                        layer,
                        format!(
                            "a layer of the cookie array (0..{layers}; VolumetricFog::set_cookies)"
                        ),
                    )?;
                    layer
                }
            };
            let mut request = None;
            let mut direct = None;
            if let Some(map) = s.shadow {
                let (maps, per_map, what) = if point {
                    (
                        &self.point_maps,
                        6,
                        "a cube of the point shadow maps (VolumetricFog::set_point_shadow_maps)",
                    )
                } else {
                    (
                        &self.spot_maps,
                        1,
                        "a layer of the spot shadow maps (VolumetricFog::set_spot_shadow_maps)",
                    )
                };
                let available = maps
                    .as_ref()
                    .map_or(0, |m| m.size().depth_or_array_layers / per_map);
                check(
                    map < available,
                    "ShadowedLight.shadow",
                    map,
                    format!("{what}: 0..{available}"),
                )?;
                let granted = if point {
                    points < self.config.point_shadows
                } else {
                    spots < self.config.spot_shadows
                };
                if granted && self.compare {
                    // The light's own map, read where it lies.
                    direct = Some(map * per_map);
                    if point {
                        points += 1;
                    } else {
                        spots += 1;
                    }
                } else if granted {
                    request = Some(requests.len());
                    requests.push(LayerRequest {
                        sources: (0..per_map)
                            .map(|face| LocalShadowSource {
                                depth_terms,
                                depth_range: light.range,
                                exponent: self.config.exponent,
                                source_layer: map * per_map + face,
                                atlas_layer: 0,
                                source: u32::from(point),
                            })
                            .collect(),
                        unchanged: s.map_unchanged,
                    });
                    if point {
                        points += 1;
                    } else {
                        spots += 1;
                    }
                } else {
                    stats.unshadowed += 1;
                }
            }
            out[s.light as usize].projection = entries.len() as u32;
            entries.push((s, light, cookie, request, direct));
        }
        let grants = assign_layers(&self.held, &requests);
        let mut sources = Vec::new();
        for (r, g) in requests.iter().zip(&grants) {
            if !g.fill {
                stats.kept += r.sources.len() as u32;
                continue;
            }
            sources.extend(
                r.sources
                    .iter()
                    .zip(g.first..)
                    .map(|(s, layer)| LocalShadowSource {
                        atlas_layer: layer,
                        ..*s
                    }),
            );
        }
        let projections = entries
            .iter()
            .map(|(s, light, cookie, request, direct)| {
                let layer = match (request, direct) {
                    (Some(r), _) => grants[*r].first,
                    (None, Some(layer)) => *layer,
                    (None, None) => LOCAL_SHADOW_NONE,
                };
                LightProjection::new(
                    light,
                    &s.camera,
                    layer,
                    *cookie,
                    self.config.exponent,
                    s.bias,
                )
            })
            .collect::<Result<Vec<_>, _>>()?;
        stats.spot_shadows = spots;
        stats.point_shadows = points;
        stats.layers = sources.len() as u32;
        Ok(LocalShadowPlan {
            lights: out,
            projections,
            sources,
            stats,
        })
    }

    /// Uploads a frame's plan (its projections and atlas maps); from here on the
    /// atlas counts as holding the maps the frame fills.
    pub(super) fn write(&mut self, queue: &wgpu::Queue, esm: &EsmPasses, plan: &LocalShadowPlan) {
        if !plan.projections.is_empty() {
            let bytes = uniforms::to_storage_bytes(&plan.projections);
            queue.write_buffer(&self.projections, 0, &bytes);
        }
        if !plan.sources.is_empty() {
            let bytes = uniforms::to_storage_bytes(&plan.sources);
            queue.write_buffer(&self.sources, 0, &bytes);
        }
        for s in &plan.sources {
            self.held[s.atlas_layer as usize] = Some(*s);
        }
        self.runs = layer_runs(plan.sources.iter().map(|s| s.atlas_layer));
        if let (Some(groups), Some(atlas)) = (self.groups.as_mut(), &self.atlas) {
            for run in self.runs.iter().filter(|r| r.start > 0) {
                if groups.runs.iter().any(|(r, _)| r == run) {
                    continue;
                }
                let (atlas, scratch) = (layers_view(&atlas[0], run), layers_view(&atlas[1], run));
                let blur = [
                    esm.blur_bind_group(&self.device, &atlas, &scratch),
                    esm.blur_bind_group(&self.device, &scratch, &atlas),
                ];
                groups.runs.push((run.clone(), blur));
            }
        }
        self.stats = plan.stats;
        self.projects = plan
            .projections
            .iter()
            .any(|p| p.layer != LOCAL_SHADOW_NONE || p.cookie != LOCAL_SHADOW_NONE);
    }

    /// Records the downsample and blur of this frame's atlas layers.
    pub(super) fn encode(&self, compute: &mut wgpu::ComputePass<'_>, esm: &EsmPasses) {
        let (Some(groups), layers) = (&self.groups, self.stats.layers) else {
            return;
        };
        if layers == 0 {
            return;
        }
        let size = self.config.resolution;
        self.pass.encode(compute, &groups.downsample, size, layers);
        for axis in 0..2 {
            for run in &self.runs {
                let blur = if run.start == 0 {
                    &groups.blur
                } else {
                    let made = groups.runs.iter().find(|(r, _)| r == run);
                    &made.expect("made by write").1
                };
                esm.encode_blur(compute, &blur[axis], axis as u32, size, run.len() as u32);
            }
        }
    }

    /// Whether a light of this frame has a shadow in the atlas or a cookie (the frame
    /// then runs inject with local shadows).
    pub(super) fn projects(&self) -> bool {
        self.projects
    }

    /// Whether this frame fills atlas layers.
    pub(super) fn runs(&self) -> bool {
        self.groups.is_some() && self.stats.layers > 0
    }

    /// The textures this object owns (the caller's depth maps and cookies excluded).
    pub(super) fn textures(&self) -> Vec<&wgpu::Texture> {
        let mut t = vec![&self.placeholder, &self.no_cookies];
        if let Some(a) = &self.atlas {
            t.extend(a);
        }
        t
    }

    /// Its buffers.
    pub(super) fn buffers(&self) -> [&wgpu::Buffer; 2] {
        [&self.sources, &self.projections]
    }

    /// The caller's textures, to carry over a reconfiguration.
    pub(super) fn user_textures(&self) -> [Option<&wgpu::Texture>; 3] {
        [
            self.spot_maps.as_ref(),
            self.point_maps.as_ref(),
            self.cookies.as_ref(),
        ]
    }
}

/// A 2D-array view of `layers` of an atlas array.
fn layers_view(texture: &wgpu::Texture, layers: &Range<u32>) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        base_array_layer: layers.start,
        array_layer_count: Some(layers.len() as u32),
        ..Default::default()
    })
}
