//! The GPU generations RADV compiles for on its null device, and the named GPUs the
//! time model runs on.

use serde::{Deserialize, Serialize};

/// A chip RADV's null device can stand in for (`RADV_FORCE_FAMILY`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Chip {
    /// Bonaire (GCN2, GFX7): the generation of the Xbox One's GPU.
    Bonaire,
    /// Navi 21 (RDNA2, GFX10.3): the RX 6800 XT.
    Navi21,
    /// GFX11.0.0 (RDNA3): the RX 7900 XTX.
    Gfx1100,
}

impl Chip {
    /// Every chip, oldest first.
    pub const ALL: [Chip; 3] = [Chip::Bonaire, Chip::Navi21, Chip::Gfx1100];

    /// The value of `RADV_FORCE_FAMILY`.
    pub fn family(self) -> &'static str {
        match self {
            Chip::Bonaire => "bonaire",
            Chip::Navi21 => "navi21",
            Chip::Gfx1100 => "gfx1100",
        }
    }

    /// The chip of a `RADV_FORCE_FAMILY` value (case-insensitive).
    pub fn from_family(name: &str) -> Option<Chip> {
        Chip::ALL
            .into_iter()
            .find(|c| c.family().eq_ignore_ascii_case(name))
    }

    /// The architecture, as AMD names it.
    pub fn generation(self) -> &'static str {
        match self {
            Chip::Bonaire => "GCN2 (GFX7)",
            Chip::Navi21 => "RDNA2 (GFX10.3)",
            Chip::Gfx1100 => "RDNA3 (GFX11)",
        }
    }

    /// What the null device calls itself contains this (upper case), e.g. `RADV BONAIRE`.
    pub fn device_name_fragment(self) -> String {
        format!("RADV {}", self.family().to_uppercase())
    }

    /// Whether RADV counts "Subgroups per SIMD" in wave32 units: on GFX10 and later it
    /// reports `waves64 * 64 / 32` for a wave64 shader (Mesa 22.3,
    /// `radv_get_max_waves`), on GCN in waves.
    pub fn counts_wave32_units(self) -> bool {
        !matches!(self, Chip::Bonaire)
    }

    /// SIMDs per compute unit: four SIMD16 on GCN, two SIMD32 on RDNA.
    pub fn simds_per_cu(self) -> u32 {
        match self {
            Chip::Bonaire => 4,
            Chip::Navi21 | Chip::Gfx1100 => 2,
        }
    }

    /// Waves of 64 invocations a SIMD holds at most (GCN: 10; RDNA2 and RDNA3: 16).
    pub fn max_waves64_per_simd(self) -> u32 {
        match self {
            Chip::Bonaire => 10,
            Chip::Navi21 | Chip::Gfx1100 => 16,
        }
    }
}

impl std::fmt::Display for Chip {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.family())
    }
}

/// A named GPU the time model runs on: its shader array, clock and memory.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GpuModel {
    /// Its name.
    pub name: &'static str,
    /// The chip whose compiler statistics stand for it.
    pub chip: Chip,
    /// Compute units.
    pub compute_units: u32,
    /// Shader clock (Hz) the model runs at.
    pub clock_hz: f64,
    /// Memory bandwidth (bytes/s) the memory floor is taken at.
    pub bandwidth_bytes_s: f64,
    /// Caches or on-chip memory that the floor leaves aside.
    pub note: &'static str,
    /// Where the figures come from.
    pub source: &'static str,
}

impl GpuModel {
    /// SIMDs of the whole GPU.
    pub fn simds(&self) -> u32 {
        self.compute_units * self.chip.simds_per_cu()
    }
}

/// Microsoft's Xbox One (2013): 12 GCN compute units at 853 MHz, 68 GB/s of DDR3 and
/// 32 MB of ESRAM; the GPU on which Wronski measured Assassin's Creed IV's fog.
pub const XBOX_ONE: GpuModel = GpuModel {
    name: "Xbox One",
    chip: Chip::Bonaire,
    compute_units: 12,
    clock_hz: 853.0e6,
    bandwidth_bytes_s: 68.0e9,
    note: "DDR3 bandwidth; the 32 MB ESRAM (109 GB/s each way, 204 GB/s peak), where a \
           title would keep the froxel volume, is left out",
    source: "J. Sell and P. O'Connor, \"The Xbox One System on a Chip and Kinect Sensor\", \
             Hot Chips 25 (2013) and IEEE Micro 34(2), 2014: 12 CUs, 853 MHz, \
             68 GB/s DDR3-2133, 32 MB ESRAM at 109 GB/s (204 GB/s peak)",
};

/// AMD Radeon RX 6800 XT (RDNA2, Navi 21): 72 compute units, 2250 MHz boost clock,
/// 512 GB/s of GDDR6 and 128 MB of Infinity Cache.
pub const RX_6800_XT: GpuModel = GpuModel {
    name: "RX 6800 XT",
    chip: Chip::Navi21,
    compute_units: 72,
    clock_hz: 2.25e9,
    bandwidth_bytes_s: 512.0e9,
    note: "GDDR6 bandwidth; the 128 MB Infinity Cache, which holds the whole froxel \
           volume, is left out",
    source: "AMD, Radeon RX 6800 XT product specifications (amd.com): 72 CUs, boost clock \
             up to 2250 MHz, 16 GB GDDR6 on 256 bits at 16 Gbps (512 GB/s), 128 MB \
             Infinity Cache",
};

/// AMD Radeon RX 7900 XTX (RDNA3, Navi 31): 96 compute units, 2500 MHz boost clock,
/// 960 GB/s of GDDR6.
pub const RX_7900_XTX: GpuModel = GpuModel {
    name: "RX 7900 XTX",
    chip: Chip::Gfx1100,
    compute_units: 96,
    clock_hz: 2.5e9,
    bandwidth_bytes_s: 960.0e9,
    note: "GDDR6 bandwidth; the 96 MB Infinity Cache is left out, and so is RDNA3's \
           dual issue (ACO's cycles in Mesa 22.3 count one VALU instruction per cycle)",
    source: "AMD, Radeon RX 7900 XTX product specifications (amd.com): 96 CUs, boost clock \
             up to 2500 MHz, 24 GB GDDR6 on 384 bits at 20 Gbps (960 GB/s), 96 MB \
             Infinity Cache",
};

/// The three models, in chip order.
pub const MODELS: [GpuModel; 3] = [XBOX_ONE, RX_6800_XT, RX_7900_XTX];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn families_round_trip_and_models_match_their_chips() {
        for chip in Chip::ALL {
            assert_eq!(Chip::from_family(chip.family()), Some(chip));
            assert_eq!(Chip::from_family(&chip.family().to_uppercase()), Some(chip));
        }
        assert_eq!(Chip::from_family("tahiti"), None);
        // 12 CUs x 4 SIMD16 on the Xbox One, 2 SIMD32 per CU on RDNA.
        assert_eq!(XBOX_ONE.simds(), 48);
        assert_eq!(RX_6800_XT.simds(), 144);
        assert_eq!(RX_7900_XTX.simds(), 192);
        // Peak FP32 rate from the same figures: 2 flops per FMA, 64 lanes per CU and
        // clock: 1.31 TFLOPS (Xbox One), 20.7 TFLOPS (RX 6800 XT, as AMD states it).
        let tflops = |m: &GpuModel| 2.0 * 64.0 * f64::from(m.compute_units) * m.clock_hz / 1e12;
        assert!((tflops(&XBOX_ONE) - 1.31).abs() < 0.01);
        assert!((tflops(&RX_6800_XT) - 20.74).abs() < 0.01);
    }
}
