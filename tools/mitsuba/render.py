"""Render a volfog truth scene (testkit/src/truth/scene.rs, `TruthScene`) with Mitsuba 3.

Usage: render.py scene.json out.bin --spp N --seed S --mode radiance|transmittance

Writes width * height * 3 little-endian float32 values: row-major, top row first, rgb.
Prints one timing line to stderr on success; a failure exits non-zero with the reason
on stderr.

Scene mapping (units are volfog's: metres, +Y up):
- camera: `perspective` sensor, fov_axis "y", fov = fov_y_deg, to_world =
  look_at(position, target, up = +Y), an `hdrfilm` (rgb, `box` reconstruction filter:
  a pixel is the mean over its square) and `medium` = the global medium (the eye is
  inside it). Mitsuba's clip planes stay at 0.01 and 10^4 m: the occluders end every
  ray.
- global medium: a `cube` shape over [bounds_min, (bounds_max_xz[0], top,
  bounds_max_xz[1])] with a `null` BSDF and `interior` = the medium, albedo = albedo,
  phase `hg` with g = phase_g. Mitsuba's HG takes g > 0 as forward scattering (strongest
  when the eye looks towards the light), as volfog does; testkit/tests/mitsuba.rs
  checks it against the formula.
  falloff > 0: a `heterogeneous` medium whose sigma_t is a `gridvolume` of 2 x N x 2
  cells holding density * exp(-falloff (y - base_height)). Mitsuba's grids are
  cell-centred (value i at (i + 0.5) / N of the grid's box, clamped outside), so the
  grid's box reaches half a spacing beyond the medium's box and its cell centres lie on
  N equally spaced heights from the bottom to the top face: trilinear interpolation of
  the exponential then errs by at most (falloff h)^2 / 8 relative for a spacing h, and
  N keeps that under HEIGHT_GRID_ERROR.
  falloff == 0: sigma_t = density everywhere in the box, a `homogeneous` medium, except
  for the radiance of a scene with a sun: there a `heterogeneous` one whose grid holds
  density inside the box and HOMOGENEOUS_MAJORANT * density in one layer of cells
  beyond its +x face, where no ray inside the box reads it. Mitsuba takes a grid's
  maximum as the majorant, so the long shadow rays towards the sun ratio-track (each
  null collision scales their transmittance by 1 - 1 / HOMOGENEOUS_MAJORANT) instead
  of the 0-or-1 estimate of free-flight sampling a `homogeneous` medium gets, with the
  same expected value and less noise per second of rendering; the short shadow rays
  of point and spot lights gain nothing from it (tools/mitsuba/README.md).
- local volumes: each a `cube` shape over the volume's bounding box grown by 2 % (and
  1 cm), `null` BSDF, `exterior` = the global medium, `interior` = a `heterogeneous`
  medium over the same box whose sigma_t grid (LOCAL_GRID cells per axis, centres from
  face to face) holds the global extinction plus the volume's
  density * clamp((1 - m) / edge, 0, 1), m = max(|x|, |y|, |z|) (box) or |p|
  (ellipsoid) in the unit shape space p = (world - center) / half_extents; same albedo
  and phase. The boxes must lie in the medium's box and must not overlap each other
  (Mitsuba follows one medium at a time).
- occluders: `cube` shapes with `exterior` = the global medium and a black BSDF: a
  `conductor` whose specular reflectance is 0. It absorbs everything like a `diffuse`
  of reflectance 0, but being a delta BSDF it asks for no shadow ray at each camera ray
  that hits it (that ray would cost time and carry 0).
- sun: `directional` emitter, irradiance = color, direction = -sun.direction.
  points: `point`, intensity = color. spots: `spot`, intensity = color,
  cutoff_angle = outer_deg, beam_width = inner_deg, to_world = look_at from the
  position along the direction. Mitsuba's spot falls off linearly in angle between
  beam_width and cutoff_angle, volfog's as a smoothstep in cosine between the same
  cones: they differ inside that band only.
  areas: a `rectangle` or `disk` shape (the unit square [-1, 1]^2 or unit disk in the
  xy plane, normal +z) with an `area` emitter of the given radiance, to_world mapping
  x to axis_x * half_x, y to axis_y * half_y and z to axis_x x axis_y (the side it
  emits towards, one-sided), the black BSDF of the occluders and exterior = the global
  medium. The scenes keep them out of view: hide_emitters shows a camera ray that
  meets one as black, and it hides the fog behind it.
- integrator: `volpath` with max_depth 2, which is single scattering: the camera ray
  (depth 0) samples one medium interaction; scattering there makes depth 1 < 2, so the
  emitters are sampled (a shadow ray each, transmittance included); the phase-sampled
  continuation adds nothing, since a second scattering event reaches depth 2 and stops
  before sampling emitters, and no emitter can be hit (delta lights, hide_emitters,
  and surfaces only sample emitters while depth + 1 < max_depth). rr_depth far above
  max_depth: no Russian roulette.
- --mode transmittance: the rgb transmittance exp(-integral of sigma_t) from the eye to
  the first occluder, by a small integrator written here over Mitsuba's scene: its
  camera rays (a `stratified` sampler over the pixel, box filter), ray intersection,
  media, medium boundaries and grids. Along a camera ray the optical depth of each
  homogeneous segment is exact and that of each heterogeneous segment a midpoint sum.
  volpath itself would estimate it by free-flight sampling, a 0-or-1 estimate per path
  (std sqrt(T (1 - T) / spp) per pixel). A camera ray that meets no occluder reads 0
  (the scenes are built so that none does).
"""

import argparse
import glob
import json
import math
import os
import re
import struct
import subprocess
import sys
import time

# Oldest libLLVM known to compile the kernels Dr.Jit 1.5 emits: 15 and 16 abort with
# "Cannot select: fminimum" (the llvm.minimum intrinsic), 19 (Debian 12's libllvm19)
# works; 17 and 18 were not tried.
LLVM_MIN_MAJOR = 19


def find_libllvm():
    """The newest libLLVM shared library the dynamic linker knows (ldconfig -p) or the
    usual folders hold: (major version, path), or None."""
    try:
        listing = subprocess.run(["ldconfig", "-p"], capture_output=True, text=True, check=False).stdout
    except OSError:
        listing = ""
    paths = [line.split("=>")[-1].strip() for line in listing.splitlines() if "libLLVM" in line and "=>" in line]
    for folder in ["/usr/lib/x86_64-linux-gnu", "/usr/lib/aarch64-linux-gnu", "/usr/lib64", "/usr/lib"]:
        paths += glob.glob(os.path.join(folder, "libLLVM*.so*"))
    paths += glob.glob("/usr/lib/llvm-*/lib/libLLVM*.so*")
    found = []
    for path in paths:
        m = re.search(r"libLLVM(?:-|\.so\.)(\d+)", os.path.basename(path))
        if m and os.path.exists(path):
            found.append((int(m.group(1)), path))
    return max(found) if found else None


if "DRJIT_LIBLLVM_PATH" not in os.environ:
    LIBLLVM = find_libllvm()
    if LIBLLVM is None or LIBLLVM[0] < LLVM_MIN_MAJOR:
        HAVE = f"only libLLVM {LIBLLVM[0]} ({LIBLLVM[1]})" if LIBLLVM else "no libLLVM"
        sys.exit(
            f"render.py: Dr.Jit's LLVM back end needs libLLVM {LLVM_MIN_MAJOR} or newer, found {HAVE}; "
            "install it with `apt-get install libllvm19` (or run `cargo xtask tools`), "
            "or name one with DRJIT_LIBLLVM_PATH"
        )
    os.environ["DRJIT_LIBLLVM_PATH"] = LIBLLVM[1]

import drjit as dr  # noqa: E402 (Dr.Jit reads DRJIT_LIBLLVM_PATH when it starts)
import mitsuba as mi  # noqa: E402

# Dr.Jit's LLVM back end: the renderer compiled to vector code over all cores, about
# twice as fast as scalar_rgb here, and the transmittance integrator below needs
# vectorised calls (tools/mitsuba/README.md).
mi.set_variant("llvm_ad_rgb")

# Relative error bound of the trilinear interpolation of the height profile.
HEIGHT_GRID_ERROR = 2e-5
# Fewest and most height cells.
HEIGHT_GRID_MIN = 64
HEIGHT_GRID_MAX = 8192
# Cells per axis of a local volume's grid.
LOCAL_GRID = 128
# Majorant of a homogeneous global medium in radiance renders, in units of its
# extinction (see the mapping above).
HOMOGENEOUS_MAJORANT = 2.0
# Quadrature step of the transmittance integrator in the global height fog: at most
# this many e-folding lengths (1 / falloff) and at most HEIGHT_STEP_MAX m; the midpoint
# rule then errs by about (falloff step)^2 / 24 of the optical depth.
HEIGHT_STEP_FOLDS = 0.05
HEIGHT_STEP_MAX = 0.5
# Most medium boundaries a camera ray crosses before its occluder, and most quadrature
# steps in one segment.
MAX_CROSSINGS = 16
MAX_STEPS = 100000


class SceneError(Exception):
    """A scene the mapping cannot represent."""


def vec3(v):
    return [float(v[0]), float(v[1]), float(v[2])]


def rgb(v):
    return {"type": "rgb", "value": vec3(v)}


def box_transform(lo, hi):
    """to_world of Mitsuba's cube [-1, 1]^3 onto the box [lo, hi]."""
    center = [(a + b) * 0.5 for a, b in zip(lo, hi)]
    half = [(b - a) * 0.5 for a, b in zip(lo, hi)]
    if min(half) <= 0.0:
        raise SceneError(f"empty box {lo} .. {hi}")
    return mi.ScalarTransform4f().translate(center).scale(half)


def lattice(lo, hi, res):
    """A cell-centred grid of `res` = (nx, ny, nz) cells whose centres lie on a lattice
    from `lo` to `hi` (at least 2 per axis): the world positions of the centres (x
    fastest, then y, then z), Mitsuba's tensor shape (z, y, x, channel) and the grid's
    to_world (its box reaches half a spacing beyond [lo, hi])."""
    nx, ny, nz = res
    idx = dr.arange(mi.UInt32, nx * ny * nz)
    ix, iy, iz = idx % nx, (idx // nx) % ny, idx // (nx * ny)

    def axis(i, a, b, n):
        return a + (b - a) * mi.Float(i) / float(n - 1)

    p = mi.Point3f(axis(ix, lo[0], hi[0], nx), axis(iy, lo[1], hi[1], ny), axis(iz, lo[2], hi[2], nz))
    spacing = [(b - a) / (n - 1) for a, b, n in zip(lo, hi, res)]
    corner = [a - 0.5 * h for a, h in zip(lo, spacing)]
    size = [h * n for h, n in zip(spacing, res)]
    to_world = mi.ScalarTransform4f().translate(corner).scale(size)
    return p, (nz, ny, nx, 1), to_world


def global_extinction(medium, y):
    """volfog's global extinction (1/m) at height y: density exp(-falloff (y - base))
    below the top, 0 above."""
    e = float(medium["density"]) * dr.exp(-float(medium["falloff"]) * (y - float(medium["base_height"])))
    return dr.select(y > float(medium["top"]), 0.0, e)


def medium_box(medium):
    lo = vec3(medium["bounds_min"])
    hi = [float(medium["bounds_max_xz"][0]), float(medium["top"]), float(medium["bounds_max_xz"][1])]
    if not all(a < b for a, b in zip(lo, hi)):
        raise SceneError(f"empty medium box {lo} .. {hi}")
    return lo, hi


def grid_medium(medium, data, to_world, transmittance):
    return {
        "type": "heterogeneous",
        "sigma_t": {"type": "gridvolume", "data": data, "to_world": to_world},
        "scale": 1.0,
        "albedo": rgb([0.0, 0.0, 0.0] if transmittance else medium["albedo"]),
        "phase": {"type": "hg", "g": float(medium["phase_g"])},
        "has_spectral_extinction": False,
    }


def global_medium(medium, sunlit, transmittance):
    if medium["density"] < 0.0 or medium["falloff"] < 0.0:
        raise SceneError("the medium needs density >= 0 and falloff >= 0")
    if not -1.0 < medium["phase_g"] < 1.0:
        raise SceneError("the phase function needs -1 < g < 1")
    lo, hi = medium_box(medium)
    density = float(medium["density"])
    falloff = float(medium["falloff"])
    if falloff == 0.0 and (transmittance or not sunlit or HOMOGENEOUS_MAJORANT <= 1.0 or density == 0.0):
        return {
            "type": "homogeneous",
            "sigma_t": density,
            "albedo": rgb([0.0, 0.0, 0.0] if transmittance else medium["albedo"]),
            "phase": {"type": "hg", "g": float(medium["phase_g"])},
        }
    if falloff == 0.0:
        # Centres at lo.x, hi.x and one spacing beyond hi.x (the majorant layer).
        width = hi[0] - lo[0]
        p, shape, to_world = lattice(lo, [hi[0] + width, hi[1], hi[2]], (3, 2, 2))
        sigma = dr.select(p.x > hi[0] + 0.5 * width, HOMOGENEOUS_MAJORANT * density, density)
        return grid_medium(medium, mi.TensorXf(sigma, shape), to_world, transmittance)
    # Spacing h with (falloff h)^2 / 8 <= HEIGHT_GRID_ERROR.
    h = math.sqrt(8.0 * HEIGHT_GRID_ERROR) / falloff
    ny = int(math.ceil((hi[1] - lo[1]) / h)) + 1
    ny = max(HEIGHT_GRID_MIN, min(HEIGHT_GRID_MAX, ny))
    p, shape, to_world = lattice(lo, hi, (2, ny, 2))
    # The top row of centres lies on the top face: take the profile just below it.
    y = dr.minimum(p.y, hi[1] - 1e-4)
    return grid_medium(medium, mi.TensorXf(global_extinction(medium, y), shape), to_world, transmittance)


def volume_box(volume):
    c = vec3(volume["center"])
    r = vec3(volume["half_extents"])
    if min(r) <= 0.0:
        raise SceneError("a local volume needs positive half extents")
    if not 0.0 < volume["edge"] <= 1.0:
        raise SceneError("a local volume needs 0 < edge <= 1")
    pad = [0.02 * a + 0.01 for a in r]
    lo = [ci - ri - pi for ci, ri, pi in zip(c, r, pad)]
    hi = [ci + ri + pi for ci, ri, pi in zip(c, r, pad)]
    return lo, hi


def local_medium(medium, volume, transmittance):
    lo, hi = volume_box(volume)
    p, shape, to_world = lattice(lo, hi, (LOCAL_GRID, LOCAL_GRID, LOCAL_GRID))
    c = vec3(volume["center"])
    r = vec3(volume["half_extents"])
    u = mi.Vector3f((p.x - c[0]) / r[0], (p.y - c[1]) / r[1], (p.z - c[2]) / r[2])
    if volume["shape"] == "box":
        m = dr.maximum(dr.abs(u.x), dr.maximum(dr.abs(u.y), dr.abs(u.z)))
    elif volume["shape"] == "ellipsoid":
        m = dr.norm(u)
    else:
        raise SceneError(f"unknown local volume shape {volume['shape']!r}")
    w = dr.clip((1.0 - m) / float(volume["edge"]), 0.0, 1.0)
    sigma = dr.maximum(global_extinction(medium, p.y) + float(volume["density"]) * w, 0.0)
    return grid_medium(medium, mi.TensorXf(sigma, shape), to_world, transmittance)


def local_step(volume):
    """Half a cell of the volume's grid (m): the transmittance integrator's step there."""
    lo, hi = volume_box(volume)
    return 0.5 * min(b - a for a, b in zip(lo, hi)) / (LOCAL_GRID - 1)


def overlaps(a, b):
    return all(a[0][i] < b[1][i] and b[0][i] < a[1][i] for i in range(3))


def inside(inner, outer):
    return all(outer[0][i] <= inner[0][i] and inner[1][i] <= outer[1][i] for i in range(3))


def look_along(origin, direction):
    up = [0.0, 1.0, 0.0] if abs(direction[1]) < 0.999 * math.sqrt(sum(d * d for d in direction)) else [0.0, 0.0, 1.0]
    target = [o + d for o, d in zip(origin, direction)]
    return mi.ScalarTransform4f().look_at(origin=origin, target=target, up=up)


def build(scene, spp, transmittance):
    """The Mitsuba scene of a TruthScene (see the mapping above)."""
    width, height = (int(v) for v in scene["resolution"])
    if width < 1 or height < 1:
        raise SceneError("empty resolution")
    cam = scene["camera"]
    medium = scene["medium"]
    fog_box = medium_box(medium)
    if not inside((vec3(cam["position"]), vec3(cam["position"])), fog_box):
        raise SceneError("the camera is outside the medium's box (the sensor's medium is the global one)")
    fog = mi.load_dict(global_medium(medium, scene["sun"] is not None, transmittance))
    if transmittance:
        falloff = float(medium["falloff"])
        fog_step = min(HEIGHT_STEP_MAX, HEIGHT_STEP_FOLDS / falloff) if falloff > 0.0 else HEIGHT_STEP_MAX
        steps = [local_step(v) for v in scene["volumes"]]
        integrator = {
            "type": "truth_transmittance",
            "fog_step": fog_step,
            "local_step": min(steps) if steps else fog_step,
        }
        sampler = "stratified"
    else:
        integrator = {"type": "volpath", "max_depth": 2, "rr_depth": 1000, "hide_emitters": True}
        sampler = "independent"
    d = {
        "type": "scene",
        "integrator": integrator,
        "sensor": {
            "type": "perspective",
            "fov_axis": "y",
            "fov": float(cam["fov_y_deg"]),
            "to_world": mi.ScalarTransform4f().look_at(
                origin=vec3(cam["position"]), target=vec3(cam["target"]), up=[0.0, 1.0, 0.0]
            ),
            "medium": fog,
            "film": {
                "type": "hdrfilm",
                "width": width,
                "height": height,
                "pixel_format": "rgb",
                "rfilter": {"type": "box"},
            },
            "sampler": {"type": sampler, "sample_count": spp},
        },
        "fog_box": {
            "type": "cube",
            "to_world": box_transform(*fog_box),
            "bsdf": {"type": "null"},
            "interior": fog,
        },
    }
    boxes = []
    eye = vec3(cam["position"])
    for i, volume in enumerate(scene["volumes"]):
        vb = volume_box(volume)
        if inside((eye, eye), vb):
            raise SceneError(f"the camera is inside local volume {i}'s box (the sensor's medium is the global one)")
        if not inside(vb, fog_box):
            raise SceneError(f"local volume {i} (grown by its margin) reaches outside the medium's box")
        if any(overlaps(vb, other) for other in boxes):
            raise SceneError(f"local volume {i} overlaps another one")
        boxes.append(vb)
        d[f"volume_{i}"] = {
            "type": "cube",
            "to_world": box_transform(*vb),
            "bsdf": {"type": "null"},
            "interior": mi.load_dict(local_medium(medium, volume, transmittance)),
            "exterior": fog,
        }
    black = {"type": "conductor", "specular_reflectance": {"type": "rgb", "value": [0.0, 0.0, 0.0]}}
    for i, occluder in enumerate(scene["occluders"]):
        d[f"occluder_{i}"] = {
            "type": "cube",
            "to_world": box_transform(vec3(occluder["min"]), vec3(occluder["max"])),
            "bsdf": black,
            "exterior": fog,
        }
    if not transmittance:
        sun = scene["sun"]
        if sun is not None:
            d["sun"] = {
                "type": "directional",
                "direction": [-a for a in vec3(sun["direction"])],
                "irradiance": rgb(sun["color"]),
            }
        for i, point in enumerate(scene["points"]):
            d[f"point_{i}"] = {"type": "point", "position": vec3(point["position"]), "intensity": rgb(point["color"])}
        for i, spot in enumerate(scene["spots"]):
            if not 0.0 < spot["inner_deg"] <= spot["outer_deg"] < 90.0:
                raise SceneError(f"spot {i} needs 0 < inner_deg <= outer_deg < 90")
            d[f"spot_{i}"] = {
                "type": "spot",
                "to_world": look_along(vec3(spot["position"]), vec3(spot["direction"])),
                "intensity": rgb(spot["color"]),
                "cutoff_angle": float(spot["outer_deg"]),
                "beam_width": float(spot["inner_deg"]),
            }
        for i, area in enumerate(scene.get("areas", [])):
            d[f"area_{i}"] = area_emitter(area, black, fog)
    return mi.load_dict(d), width, height


def area_emitter(area, bsdf, fog):
    """The Mitsuba shape of a TruthArea: a rectangle or disk with an area emitter."""
    ax, ay = vec3(area["axis_x"]), vec3(area["axis_y"])
    hx, hy = float(area["half_x"]), float(area["half_y"])
    if not (hx > 0.0 and hy > 0.0):
        raise SceneError("an area light needs half_x > 0 and half_y > 0")
    n = [ax[1] * ay[2] - ax[2] * ay[1], ax[2] * ay[0] - ax[0] * ay[2], ax[0] * ay[1] - ax[1] * ay[0]]
    c = vec3(area["center"])
    m = [[ax[r] * hx, ay[r] * hy, n[r], c[r]] for r in range(3)] + [[0.0, 0.0, 0.0, 1.0]]
    shape = {"rectangle": "rectangle", "disk": "disk"}.get(area["shape"])
    if shape is None:
        raise SceneError(f"unknown area light shape {area['shape']}")
    return {
        "type": shape,
        "to_world": mi.ScalarTransform4f(m),
        "bsdf": bsdf,
        "exterior": fog,
        "emitter": {"type": "area", "radiance": rgb(area["radiance"])},
    }


class TransmittanceIntegrator(mi.SamplingIntegrator):
    """exp(-optical depth) from the eye to the first occluder (a surface whose BSDF is
    not null), 0 where the ray meets none. The optical depth of a heterogeneous segment
    is a midpoint sum with steps of at most `fog_step` m in the camera's medium and
    `local_step` m in the others."""

    def __init__(self, props):
        super().__init__(props)
        self.fog_step = props.get("fog_step", HEIGHT_STEP_MAX)
        self.local_step = props.get("local_step", HEIGHT_STEP_MAX)

    @dr.syntax
    def sample(self, scene, sampler, ray, medium=None, active=True):
        ray = mi.Ray3f(ray)
        active = mi.Bool(active)
        fog = mi.MediumPtr(medium)
        medium = mi.MediumPtr(medium)
        tau = mi.Float(0.0)
        hit = mi.Bool(False)
        crossings = mi.UInt32(0)
        while active:
            si = scene.ray_intersect(ray, active)
            length = dr.select(si.is_valid(), si.t, 0.0)
            in_medium = active & (medium != None)  # noqa: E711 (a Dr.Jit pointer test)
            step = dr.select(medium == fog, self.fog_step, self.local_step)
            tau += optical_depth(medium, ray, length, step, in_medium)
            boundary = mi.has_flag(si.bsdf(ray).flags(), mi.BSDFFlags.Null)
            hit |= active & si.is_valid() & ~boundary
            crossings += 1
            active &= si.is_valid() & boundary & (crossings < MAX_CROSSINGS)
            if si.is_medium_transition():
                medium = si.target_medium(ray.d)
            ray = si.spawn_ray(ray.d)
        t = dr.select(hit, dr.exp(-tau), 0.0)
        return mi.Spectrum(t), mi.Bool(True), []


@dr.syntax
def optical_depth(medium, ray, length, step, active):
    """Integral of sigma_t over [0, length] m along the ray in one medium: exact where
    the medium is homogeneous, a midpoint sum with steps of at most `step` m where not."""
    mei = dr.zeros(mi.MediumInteraction3f)
    mei.wavelengths = ray.wavelengths
    mei.time = ray.time
    mei.p = ray.o
    homogeneous = active & medium.is_homogeneous()
    sigma = medium.get_scattering_coefficients(mei, homogeneous)[2][0]
    tau = dr.select(homogeneous, sigma * length, 0.0)
    graded = active & ~homogeneous
    steps = dr.select(graded, mi.UInt32(dr.clip(dr.ceil(length / step), 1.0, MAX_STEPS)), 0)
    dt = length / mi.Float(dr.maximum(steps, 1))
    i = mi.UInt32(0)
    while i < steps:
        mei.p = ray(dt * (mi.Float(i) + 0.5))
        tau += medium.get_scattering_coefficients(mei, i < steps)[2][0] * dt
        i += 1
    return tau


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("scene", help="TruthScene JSON")
    parser.add_argument("output", help="width * height * 3 little-endian float32")
    parser.add_argument("--spp", type=int, required=True, help="samples per pixel")
    parser.add_argument("--seed", type=int, required=True, help="sampler seed")
    parser.add_argument("--mode", choices=["radiance", "transmittance"], required=True)
    args = parser.parse_args()
    if args.spp < 1:
        parser.error("--spp must be at least 1")

    start = time.perf_counter()
    mi.register_integrator("truth_transmittance", lambda props: TransmittanceIntegrator(props))
    with open(args.scene, encoding="utf-8") as f:
        scene = json.load(f)
    try:
        mi_scene, width, height = build(scene, args.spp, args.mode == "transmittance")
    except (SceneError, KeyError, TypeError, ValueError) as e:
        print(f"render.py: bad scene {args.scene}: {e!r}", file=sys.stderr)
        return 2
    image = mi.render(mi_scene, spp=args.spp, seed=args.seed)
    values = list(image.array)
    if len(values) != width * height * 3:
        print(f"render.py: rendered {len(values)} values, expected {width * height * 3}", file=sys.stderr)
        return 1
    with open(args.output, "wb") as f:
        f.write(struct.pack(f"<{len(values)}f", *values))
    elapsed = time.perf_counter() - start
    print(
        f"render.py: {scene.get('name', '?')} {args.mode} {width}x{height} {args.spp} spp in {elapsed:.2f} s",
        file=sys.stderr,
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
