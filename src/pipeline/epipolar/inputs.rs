//! The inputs of [`EpipolarShafts`]: the scene depth, the cascaded shadow map and the
//! light colours, checked and bound into every pass's bind groups.

use super::layouts::D2;
use super::textures::view;
use super::{DEPTH_FORMATS, EpipolarError, EpipolarShafts, LEVEL_STRIDE, SHADOW_FORMATS};
use crate::pipeline::bind_group;

#[derive(Debug)]
pub(super) struct Groups {
    pub(super) coords: wgpu::BindGroup,
    pub(super) refine: wgpu::BindGroup,
    pub(super) tree: Vec<wgpu::BindGroup>,
    pub(super) march: wgpu::BindGroup,
    pub(super) steps: wgpu::BindGroup,
    pub(super) interpolate: wgpu::BindGroup,
    pub(super) resolve: wgpu::BindGroup,
    pub(super) upscale: Option<wgpu::BindGroup>,
    pub(super) reference: wgpu::BindGroup,
    pub(super) depth: wgpu::TextureView,
}

impl EpipolarShafts {
    /// Binds the scene depth buffer (`width` x `height`, one of [`DEPTH_FORMATS`],
    /// single-sampled) and the cascaded shadow map (a 2D texture of side
    /// `shadow_size`, one layer per cascade, one of [`SHADOW_FORMATS`]); both need
    /// `TEXTURE_BINDING` usage. Call again when either is recreated. With
    /// `EpipolarSampling::colored`, see [`EpipolarShafts::set_inputs_colored`].
    pub fn set_inputs(
        &mut self,
        device: &wgpu::Device,
        depth: &wgpu::Texture,
        shadow: &wgpu::Texture,
    ) -> Result<(), EpipolarError> {
        self.bind(device, depth, shadow, None)
    }

    /// [`EpipolarShafts::set_inputs`] for coloured shafts (`EpipolarSampling::colored`):
    /// `colors` is the light-space colour texture, the light's colour after stained
    /// glass as the cascade sees it (2D, `shadow_size` texels square, texel-aligned with
    /// the cascade; a float format, rgb used), with `TEXTURE_BINDING` usage.
    pub fn set_inputs_colored(
        &mut self,
        device: &wgpu::Device,
        depth: &wgpu::Texture,
        shadow: &wgpu::Texture,
        colors: &wgpu::Texture,
    ) -> Result<(), EpipolarError> {
        self.bind(device, depth, shadow, Some(colors))
    }

    fn bind(
        &mut self,
        device: &wgpu::Device,
        depth: &wgpu::Texture,
        shadow: &wgpu::Texture,
        colors: Option<&wgpu::Texture>,
    ) -> Result<(), EpipolarError> {
        let s = self.sampling;
        if s.colored != colors.is_some() {
            return Err(EpipolarError::Texture {
                texture: "the light colours",
                property: "presence",
                found: if colors.is_some() { "given" } else { "missing" }.into(),
                expected: if s.colored {
                    "a colour texture: EpipolarSampling::colored is set (set_inputs_colored)"
                } else {
                    "none: EpipolarSampling::colored is not set (set_inputs)"
                }
                .into(),
            });
        }
        if let Some(c) = colors {
            let float = matches!(
                c.format().sample_type(None, Some(device.features())),
                Some(wgpu::TextureSampleType::Float { .. })
            );
            if !float {
                return Err(EpipolarError::Texture {
                    texture: "the light colours",
                    property: "format",
                    found: format!("{:?}", c.format()),
                    expected: "a float format (rgba8unorm, rgba16float, ...)".into(),
                });
            }
            check_texture(
                "the light colours",
                c,
                &[c.format()],
                (s.shadow_size, s.shadow_size),
            )?;
        }
        check_texture(
            "the depth buffer",
            depth,
            &DEPTH_FORMATS,
            (s.width, s.height),
        )?;
        check_texture(
            "the shadow map",
            shadow,
            &SHADOW_FORMATS,
            (s.shadow_size, s.shadow_size),
        )?;
        let aspect = |t: &wgpu::Texture| {
            if t.format().has_depth_aspect() {
                wgpu::TextureAspect::DepthOnly
            } else {
                wgpu::TextureAspect::All
            }
        };
        let depth_view = depth.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(D2),
            aspect: aspect(depth),
            ..Default::default()
        });
        let shadow_view = shadow.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            aspect: aspect(shadow),
            ..Default::default()
        });
        let t = &self.textures;
        let p = &self.pipelines;
        let (coords, sources, marched, interpolated, shafts) = (
            view(&t.coords),
            view(&t.sources),
            view(&t.marched),
            view(&t.interpolated),
            view(&t.shafts),
        );
        let (tree, scratch) = (view(&t.tree), view(&t.scratch));
        use wgpu::BindingResource as R;
        let frame = self.frame.as_entire_binding();
        let medium = self.medium.as_entire_binding();
        let counters = self.counters.as_entire_binding();
        let top = s.shadow_size.trailing_zeros();
        let tree_groups = (0..=top)
            .map(|l| {
                // Level 0 is written into the tree; level l > 0 is read from the tree
                // into the scratch texture, then copied into the tree.
                let (src, dst) = if l == 0 {
                    (&scratch, &tree)
                } else {
                    (&tree, &scratch)
                };
                bind_group(
                    device,
                    "epipolar_tree",
                    &p.tree.0,
                    &[
                        (0, frame.clone()),
                        (1, R::TextureView(&shadow_view)),
                        (2, R::TextureView(src)),
                        (3, R::TextureView(dst)),
                        (
                            4,
                            R::Buffer(wgpu::BufferBinding {
                                buffer: &self.levels,
                                offset: LEVEL_STRIDE * u64::from(l),
                                size: wgpu::BufferSize::new(16),
                            }),
                        ),
                    ],
                )
            })
            .collect();
        let low = t.low.as_ref().map(view);
        let resolve_target = low.as_ref().unwrap_or(&shafts);
        let color_view = colors.map(view);
        let color = |binding: u32| color_view.as_ref().map(|v| (binding, R::TextureView(v)));
        let groups = Groups {
            coords: bind_group(
                device,
                "epipolar_coords",
                &p.coords.0,
                &[
                    (0, frame.clone()),
                    (1, R::TextureView(&depth_view)),
                    (2, R::TextureView(&coords)),
                ],
            ),
            refine: bind_group(
                device,
                "epipolar_refine",
                &p.refine.0,
                &[
                    (0, frame.clone()),
                    (1, R::TextureView(&coords)),
                    (2, R::TextureView(&sources)),
                ],
            ),
            tree: tree_groups,
            march: bind_group(
                device,
                "epipolar_march",
                &p.march.0,
                &[
                    (0, frame.clone()),
                    (1, medium.clone()),
                    (2, R::TextureView(&coords)),
                    (3, R::TextureView(&sources)),
                    (4, R::TextureView(&tree)),
                    (5, R::TextureView(&marched)),
                ]
                .into_iter()
                .chain(color(6))
                .collect::<Vec<_>>(),
            ),
            steps: bind_group(
                device,
                "epipolar_march steps",
                &p.steps.0,
                &[
                    (0, frame.clone()),
                    (1, medium.clone()),
                    (2, R::TextureView(&coords)),
                    (3, R::TextureView(&sources)),
                    (4, R::TextureView(&shadow_view)),
                    (5, R::TextureView(&marched)),
                ]
                .into_iter()
                .chain(color(6))
                .collect::<Vec<_>>(),
            ),
            interpolate: bind_group(
                device,
                "epipolar_interpolate",
                &p.interpolate.0,
                &[
                    (0, frame.clone()),
                    (1, R::TextureView(&sources)),
                    (2, R::TextureView(&marched)),
                    (3, R::TextureView(&interpolated)),
                ],
            ),
            resolve: bind_group(
                device,
                "epipolar_resolve",
                &p.resolve.0,
                &[
                    (0, frame.clone()),
                    (1, medium.clone()),
                    (2, R::TextureView(&depth_view)),
                    (3, R::TextureView(&coords)),
                    (4, R::TextureView(&interpolated)),
                    (5, R::TextureView(&shadow_view)),
                    (6, R::TextureView(resolve_target)),
                    (7, counters.clone()),
                ]
                .into_iter()
                .chain(color(8))
                .collect::<Vec<_>>(),
            ),
            upscale: low.as_ref().map(|low| {
                bind_group(
                    device,
                    "epipolar_upscale",
                    &p.upscale.0,
                    &[
                        (0, frame.clone()),
                        (1, medium.clone()),
                        (2, R::TextureView(&depth_view)),
                        (3, R::TextureView(low)),
                        (4, R::TextureView(&shadow_view)),
                        (5, R::TextureView(&shafts)),
                        (6, counters.clone()),
                    ]
                    .into_iter()
                    .chain(color(7))
                    .collect::<Vec<_>>(),
                )
            }),
            reference: bind_group(
                device,
                "epipolar_reference",
                &p.reference.0,
                &[
                    (0, frame.clone()),
                    (1, medium.clone()),
                    (2, R::TextureView(&depth_view)),
                    (3, R::TextureView(&shadow_view)),
                    (4, R::TextureView(&shafts)),
                ]
                .into_iter()
                .chain(color(5))
                .collect::<Vec<_>>(),
            ),
            depth: depth_view,
        };
        self.groups = Some(groups);
        Ok(())
    }
}

fn check_texture(
    what: &'static str,
    texture: &wgpu::Texture,
    formats: &[wgpu::TextureFormat],
    (width, height): (u32, u32),
) -> Result<(), EpipolarError> {
    let fail = |property, found: String, expected: String| {
        Err(EpipolarError::Texture {
            texture: what,
            property,
            found,
            expected,
        })
    };
    let size = texture.size();
    if texture.dimension() != wgpu::TextureDimension::D2 {
        return fail(
            "dimension",
            format!("{:?}", texture.dimension()),
            "D2".into(),
        );
    }
    if (size.width, size.height) != (width, height) {
        return fail(
            "size",
            format!("{} x {}", size.width, size.height),
            format!("{width} x {height} (EpipolarSampling)"),
        );
    }
    if !formats.contains(&texture.format()) {
        return fail(
            "format",
            format!("{:?}", texture.format()),
            format!("one of {formats:?}"),
        );
    }
    if texture.sample_count() != 1 {
        return fail(
            "sample count",
            texture.sample_count().to_string(),
            "1".into(),
        );
    }
    if !texture
        .usage()
        .contains(wgpu::TextureUsages::TEXTURE_BINDING)
    {
        return fail(
            "usage",
            format!("{:?}", texture.usage()),
            "TEXTURE_BINDING".into(),
        );
    }
    Ok(())
}
