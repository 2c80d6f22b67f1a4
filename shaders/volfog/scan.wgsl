// volfog::scan — front-to-back integration of the scattering along a view ray.
//
// Use:      #import volfog::scan::{scan_step, SCAN_START}
// Defines:  VOLFOG_SCAN_WRONSKI_STEP — use Wronski's original step instead of the
//           energy-conserving one (for comparison; it overestimates in-scattering by
//           up to sigma_t * ds / 2 per slice).
// Data:     a medium sample is rgb = sigma_s * L_in (radiance scattered towards the eye
//           per metre, W / (sr m^3)), a = sigma_t (1/m). The accumulator is rgb =
//           in-scattered radiance so far, a = transmittance so far (in [0, 1]).
// References: Wronski 2014, "Solving scattering equation" (AccumulateScattering); the
//           energy-conserving step integrates the constant in-scattering of a slice
//           against its own extinction: integral_0^ds S exp(-sigma_t s) ds
//           = S (1 - exp(-sigma_t ds)) / sigma_t (Hillaire 2015, Frostbite).
#define_import_path volfog::scan

// Accumulator before the first slice: no in-scattering, full transmittance.
const SCAN_START: vec4<f32> = vec4<f32>(0.0, 0.0, 0.0, 1.0);

// Below this optical depth the slice integral uses its series
// ds (1 - tau / 2 + tau^2 / 6), exact to 5e-8 relative.
const SCAN_SERIES_LIMIT: f32 = 1e-2;

// In-scattering of one homogeneous slice of path length ds (m), seen from its front.
fn slice_inscatter(medium: vec4<f32>, ds: f32) -> vec3<f32> {
    return slice_inscatter_through(medium, ds, exp(-max(medium.a, 0.0) * ds));
}

// slice_inscatter given the slice's own transmittance exp(-sigma_t ds), which the scan
// step needs too (one exp per slice).
fn slice_inscatter_through(medium: vec4<f32>, ds: f32, transmittance: f32) -> vec3<f32> {
#ifdef VOLFOG_SCAN_WRONSKI_STEP
    // Wronski 2014: the slice's in-scattering enters unattenuated by its own extinction.
    return medium.rgb * ds;
#else
    let sigma_t = max(medium.a, 0.0);
    let tau = sigma_t * ds;
    if tau < SCAN_SERIES_LIMIT {
        return medium.rgb * (ds * (1.0 - tau * (0.5 - tau * (1.0 / 6.0))));
    }
    return medium.rgb * ((1.0 - transmittance) / sigma_t);
#endif
}

// One step of the scan: adds a slice of medium (rgb = sigma_s * L_in, a = sigma_t)
// and path length ds (m) behind the accumulator acc (rgb = in-scatter, a = T).
fn scan_step(acc: vec4<f32>, medium: vec4<f32>, ds: f32) -> vec4<f32> {
    let transmittance = exp(-max(medium.a, 0.0) * ds);
    return vec4<f32>(acc.rgb + acc.a * slice_inscatter_through(medium, ds, transmittance),
        acc.a * transmittance);
}
