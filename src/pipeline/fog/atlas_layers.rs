//! Which layers of the local-light atlas a frame's shadowed lights take, and which of
//! them the frame fills: a light whose depth maps are unchanged
//! ([`ShadowedLight::map_unchanged`](super::ShadowedLight::map_unchanged)) keeps the
//! layers that still hold its filtering, the others take the lowest free layers.

use std::ops::Range;

use crate::uniforms::LocalShadowSource;

/// A granted light's maps: its sources in face order (one for a spot light, six for
/// a point light's cube; `atlas_layer` is set by the grant) and whether its depth maps
/// are unchanged since the frame that last filtered them.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct LayerRequest {
    pub(super) sources: Vec<LocalShadowSource>,
    pub(super) unchanged: bool,
}

/// Where a request's maps go: `first` and the layers after it, one per source;
/// `fill`: the frame filters them (otherwise they already hold them).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct LayerGrant {
    pub(super) first: u32,
    pub(super) fill: bool,
}

/// Whether `layers` from `first` hold `sources`, face by face, as `held` records.
fn holds(held: &[Option<LocalShadowSource>], first: usize, sources: &[LocalShadowSource]) -> bool {
    sources.iter().enumerate().all(|(face, s)| {
        held.get(first + face).copied().flatten()
            == Some(LocalShadowSource {
                atlas_layer: (first + face) as u32,
                ..*s
            })
    })
}

/// The lowest `first` whose `len` layers are all free, or `None`.
fn lowest_free(used: &[bool], len: usize) -> Option<usize> {
    (0..=used.len().checked_sub(len)?).find(|&first| used[first..first + len].iter().all(|u| !u))
}

/// Grants each request its layers of an atlas whose layers hold `held` (the source
/// each was last filled from, `atlas_layer` included; `None`: nothing valid). A request
/// with `unchanged` keeps the lowest run of layers that holds its sources and that no
/// request before it kept; every other request takes, in order, the lowest run of
/// free layers and is filled. The requests must fit the atlas (their sources number at
/// most `held.len()`); where kept layers leave no free run for a cube, nothing is kept
/// and every request is filled from layer 0 up in order, as it is when nothing is
/// kept.
pub(super) fn assign_layers(
    held: &[Option<LocalShadowSource>],
    requests: &[LayerRequest],
) -> Vec<LayerGrant> {
    let mut used = vec![false; held.len()];
    let mut grants: Vec<Option<LayerGrant>> = vec![None; requests.len()];
    let claim = |used: &mut [bool], first: usize, len: usize| {
        used[first..first + len].iter_mut().for_each(|u| *u = true);
    };
    for (grant, r) in grants.iter_mut().zip(requests) {
        let len = r.sources.len();
        if !r.unchanged || len == 0 || len > held.len() {
            continue;
        }
        let kept = (0..=held.len() - len).find(|&first| {
            used[first..first + len].iter().all(|u| !u) && holds(held, first, &r.sources)
        });
        if let Some(first) = kept {
            claim(&mut used, first, len);
            *grant = Some(LayerGrant {
                first: first as u32,
                fill: false,
            });
        }
    }
    for (grant, r) in grants.iter_mut().zip(requests) {
        if grant.is_some() {
            continue;
        }
        let len = r.sources.len();
        let Some(first) = lowest_free(&used, len) else {
            return from_zero(requests);
        };
        claim(&mut used, first, len);
        *grant = Some(LayerGrant {
            first: first as u32,
            fill: true,
        });
    }
    grants
        .into_iter()
        .map(|g| g.expect("granted above"))
        .collect()
}

/// Every request filled, from layer 0 up in order.
fn from_zero(requests: &[LayerRequest]) -> Vec<LayerGrant> {
    let mut next = 0;
    requests
        .iter()
        .map(|r| {
            let first = next;
            next += r.sources.len() as u32;
            LayerGrant { first, fill: true }
        })
        .collect()
}

/// The runs of consecutive layers among `layers` (in any order, each at most once),
/// lowest first.
pub(super) fn layer_runs(layers: impl IntoIterator<Item = u32>) -> Vec<Range<u32>> {
    let mut sorted: Vec<u32> = layers.into_iter().collect();
    sorted.sort_unstable();
    let mut runs: Vec<Range<u32>> = Vec::new();
    for layer in sorted {
        match runs.last_mut() {
            Some(run) if run.end == layer => run.end += 1,
            _ => runs.push(layer..layer + 1),
        }
    }
    runs
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;
    use proptest::prelude::*;

    fn source(map: u32, face: u32) -> LocalShadowSource {
        LocalShadowSource {
            depth_terms: Vec4::new(1.0, 0.1, 0.0, 1.0),
            depth_range: 10.0,
            exponent: 80.0,
            source_layer: 6 * map + face,
            atlas_layer: 0,
            source: u32::from(face > 0),
        }
    }

    fn request(map: u32, faces: u32, unchanged: bool) -> LayerRequest {
        LayerRequest {
            sources: (0..faces).map(|f| source(map, f)).collect(),
            unchanged,
        }
    }

    /// What the atlas holds after a frame's grants are filled.
    fn after(
        held: &[Option<LocalShadowSource>],
        requests: &[LayerRequest],
        grants: &[LayerGrant],
    ) -> Vec<Option<LocalShadowSource>> {
        let mut out = held.to_vec();
        for (r, g) in requests.iter().zip(grants).filter(|(_, g)| g.fill) {
            for (face, s) in r.sources.iter().enumerate() {
                let layer = g.first as usize + face;
                out[layer] = Some(LocalShadowSource {
                    atlas_layer: layer as u32,
                    ..*s
                });
            }
        }
        out
    }

    #[test]
    fn nothing_held_fills_from_zero_in_order() {
        let requests = [
            request(0, 1, true),
            request(1, 6, false),
            request(2, 1, true),
        ];
        let grants = assign_layers(&[None; 9], &requests);
        assert_eq!(grants, from_zero(&requests));
        assert_eq!(
            grants.iter().map(|g| g.first).collect::<Vec<_>>(),
            [0, 1, 7]
        );
    }

    #[test]
    fn unchanged_lights_keep_their_layers_when_the_order_changes() {
        let first = [
            request(0, 1, false),
            request(1, 6, false),
            request(2, 1, false),
        ];
        let held = after(&[None; 9], &first, &assign_layers(&[None; 9], &first));
        // The cube now comes first and the second spot light is gone: the two left
        // keep their layers, a new light takes the free layer 0.
        let second = [
            request(1, 6, true),
            request(3, 1, true),
            request(2, 1, true),
        ];
        let grants = assign_layers(&held, &second);
        assert_eq!(
            grants,
            [
                LayerGrant {
                    first: 1,
                    fill: false
                },
                LayerGrant {
                    first: 0,
                    fill: true
                },
                LayerGrant {
                    first: 7,
                    fill: false
                },
            ]
        );
    }

    #[test]
    fn a_changed_map_is_filled_again() {
        let requests = [request(0, 1, false), request(1, 1, false)];
        let held = after(&[None; 2], &requests, &assign_layers(&[None; 2], &requests));
        let grants = assign_layers(&held, &[request(0, 1, true), request(1, 1, false)]);
        assert_eq!(
            grants[0],
            LayerGrant {
                first: 0,
                fill: false
            }
        );
        assert_eq!(
            grants[1],
            LayerGrant {
                first: 1,
                fill: true
            }
        );
        // The same light with another exponent is another filtering.
        let mut other = request(0, 1, true);
        other.sources[0].exponent = 40.0;
        assert!(assign_layers(&held, &[other])[0].fill);
    }

    #[test]
    fn kept_layers_that_leave_no_room_for_a_cube_are_given_up() {
        // Spot light 0 held in layer 3 of 7: no run of six free layers is left.
        let mut held = vec![None; 7];
        held[3] = Some(LocalShadowSource {
            atlas_layer: 3,
            ..source(0, 0)
        });
        let requests = [request(0, 1, true), request(1, 6, false)];
        assert_eq!(assign_layers(&held, &requests), from_zero(&requests));
    }

    #[test]
    fn runs_merge_consecutive_layers() {
        assert_eq!(layer_runs([4, 0, 1, 7, 5, 2]), [0..3, 4..6, 7..8]);
        assert!(layer_runs([]).is_empty());
    }

    proptest! {
        /// Over a sequence of frames of random lights: the grants never overlap and
        /// stay in the atlas, a kept light's layers hold exactly its sources, and a
        /// light whose maps changed is always filled.
        #[test]
        fn grants_are_disjoint_and_kept_layers_hold_their_sources(
            frames in prop::collection::vec(
                prop::collection::vec((0u32..5, any::<bool>(), any::<bool>()), 0..6),
                1..6,
            ),
        ) {
            // Budget: 3 spot lights and 1 cube, so 9 layers.
            let mut held = vec![None; 9];
            for frame in frames {
                let mut requests = Vec::new();
                let (mut spots, mut cubes) = (0, 0);
                let mut seen = Vec::new();
                for (map, cube, unchanged) in frame {
                    if seen.contains(&(map, cube)) {
                        continue;
                    }
                    let fits = if cube { cubes < 1 } else { spots < 3 };
                    if !fits {
                        continue;
                    }
                    seen.push((map, cube));
                    if cube { cubes += 1 } else { spots += 1 }
                    requests.push(request(map + if cube { 100 } else { 0 }, if cube { 6 } else { 1 }, unchanged));
                }
                let grants = assign_layers(&held, &requests);
                let mut used = [false; 9];
                for (r, g) in requests.iter().zip(&grants) {
                    let layers = g.first as usize..g.first as usize + r.sources.len();
                    prop_assert!(layers.end <= 9);
                    for l in layers.clone() {
                        prop_assert!(!used[l]);
                        used[l] = true;
                    }
                    if !r.unchanged {
                        prop_assert!(g.fill);
                    }
                    if !g.fill {
                        prop_assert!(holds(&held, g.first as usize, &r.sources));
                    }
                }
                held = after(&held, &requests, &grants);
            }
        }
    }
}
