//! Linear RGB colour on `glam::Vec3`: sRGB transfer, luminance, exposure,
//! tone mapping and false-colour ramps for scalar fields.
//!
//! Colours are **linear** Rec.709/sRGB primaries unless a name says `srgb`.

use glam::Vec3;

/// Encodes one linear channel with the sRGB transfer function (IEC 61966-2-1).
///
/// Negative input maps to negative output (odd extension), so encode/decode
/// round-trip every finite value.
#[inline]
#[must_use]
pub fn srgb_encode(linear: f32) -> f32 {
    let a = linear.abs();
    let e = if a <= 0.003_130_8 {
        12.92 * a
    } else {
        1.055 * a.powf(1.0 / 2.4) - 0.055
    };
    e.copysign(linear)
}

/// Decodes one sRGB-encoded channel to linear (inverse of [`srgb_encode`]).
#[inline]
#[must_use]
pub fn srgb_decode(encoded: f32) -> f32 {
    let a = encoded.abs();
    let l = if a <= 0.040_45 {
        a / 12.92
    } else {
        ((a + 0.055) / 1.055).powf(2.4)
    };
    l.copysign(encoded)
}

/// [`srgb_encode`] on each channel.
#[inline]
#[must_use]
pub fn srgb_encode_rgb(c: Vec3) -> Vec3 {
    Vec3::new(srgb_encode(c.x), srgb_encode(c.y), srgb_encode(c.z))
}

/// [`srgb_decode`] on each channel.
#[inline]
#[must_use]
pub fn srgb_decode_rgb(c: Vec3) -> Vec3 {
    Vec3::new(srgb_decode(c.x), srgb_decode(c.y), srgb_decode(c.z))
}

/// Encodes a linear colour as 8-bit sRGB, clipping to `[0, 1]` first and
/// rounding to nearest.
#[inline]
#[must_use]
pub fn to_srgb8(c: Vec3) -> [u8; 3] {
    let q = |v: f32| (srgb_encode(v.clamp(0.0, 1.0)) * 255.0 + 0.5) as u8;
    [q(c.x), q(c.y), q(c.z)]
}

/// Decodes 8-bit sRGB to linear.
#[inline]
#[must_use]
pub fn from_srgb8(c: [u8; 3]) -> Vec3 {
    srgb_decode_rgb(Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32) / 255.0)
}

/// Rec.709 relative luminance Y of a linear colour.
#[inline]
#[must_use]
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// Scales a linear colour by `2^ev` (photographic exposure in stops).
#[inline]
#[must_use]
pub fn exposure(c: Vec3, ev: f32) -> Vec3 {
    c * ev.exp2()
}

/// A tone-mapping operator from scene-referred linear radiance to
/// display-referred linear values in `[0, 1]`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum ToneMap {
    /// No curve: values are clipped to `[0, 1]`.
    Clip,
    /// Reinhard's `c / (1 + c)` per channel.
    Reinhard,
    /// The filmic ACES fit of Narkowicz (2015), `x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14)`:
    /// a toe, a long shoulder and gentle desaturation of highlights. The default.
    #[default]
    AcesFilmic,
    /// Hable's "Uncharted 2" filmic curve with white point 11.2.
    Hable,
}

impl ToneMap {
    /// Applies the operator to a linear colour; the result is in `[0, 1]`.
    /// NaN channels stay NaN so a bug upstream stays visible.
    #[must_use]
    pub fn apply(self, c: Vec3) -> Vec3 {
        let f = |x: f32| -> f32 {
            if x.is_nan() {
                return x;
            }
            let x = x.max(0.0);
            let y = match self {
                ToneMap::Clip => x,
                ToneMap::Reinhard => x / (1.0 + x),
                ToneMap::AcesFilmic => (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14),
                ToneMap::Hable => hable(x * 2.0) / hable(11.2),
            };
            y.clamp(0.0, 1.0)
        };
        Vec3::new(f(c.x), f(c.y), f(c.z))
    }
}

#[inline]
fn hable(x: f32) -> f32 {
    let (a, b, c, d, e, f) = (0.15, 0.50, 0.10, 0.20, 0.02, 0.30);
    ((x * (a * x + c * b) + d * e) / (x * (a * x + b) + d * f)) - e / f
}

/// A false-colour ramp mapping a scalar in `[0, 1]` to a linear colour.
///
/// Viridis, magma, terrain and coolwarm are sampled from matplotlib's
/// definitions (17 control points each, interpolated in sRGB space so the
/// ramps look as they do there).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Ramp {
    /// Perceptually uniform blue–green–yellow (good default for any field).
    #[default]
    Viridis,
    /// Perceptually uniform black–purple–orange–white.
    Magma,
    /// Blue sea, green lowland, brown hills, white peaks.
    Terrain,
    /// Diverging blue–white–red, for signed fields centred on the middle.
    Coolwarm,
    /// Black to white.
    Grey,
}

const VIRIDIS: [[f32; 3]; 17] = [
    [0.267, 0.0049, 0.3294],
    [0.2823, 0.095, 0.4173],
    [0.2788, 0.1755, 0.4834],
    [0.259, 0.2515, 0.5247],
    [0.2297, 0.3224, 0.5457],
    [0.1994, 0.3876, 0.5546],
    [0.1727, 0.4488, 0.5579],
    [0.149, 0.5081, 0.5572],
    [0.1276, 0.5669, 0.5506],
    [0.1206, 0.6258, 0.5335],
    [0.1579, 0.6838, 0.5017],
    [0.2461, 0.7389, 0.452],
    [0.3692, 0.7889, 0.3829],
    [0.516, 0.8312, 0.2943],
    [0.6785, 0.8637, 0.1895],
    [0.8456, 0.8873, 0.0997],
    [0.9932, 0.9062, 0.1439],
];
const MAGMA: [[f32; 3]; 17] = [
    [0.0015, 0.0005, 0.0139],
    [0.0396, 0.0311, 0.1335],
    [0.1131, 0.0655, 0.2768],
    [0.2117, 0.062, 0.4186],
    [0.3167, 0.0717, 0.4854],
    [0.4147, 0.1104, 0.5047],
    [0.5128, 0.1482, 0.5076],
    [0.6136, 0.1818, 0.4985],
    [0.7164, 0.215, 0.4753],
    [0.8169, 0.2559, 0.4365],
    [0.9043, 0.3196, 0.3881],
    [0.9609, 0.4183, 0.3596],
    [0.9867, 0.5356, 0.3822],
    [0.9961, 0.6537, 0.4462],
    [0.9969, 0.7696, 0.5349],
    [0.9924, 0.8843, 0.6401],
    [0.9871, 0.9914, 0.7495],
];
const TERRAIN: [[f32; 3]; 17] = [
    [0.2, 0.2, 0.6],
    [0.1163, 0.3673, 0.7673],
    [0.0327, 0.5346, 0.9346],
    [0.0, 0.6765, 0.7706],
    [0.0039, 0.8008, 0.4008],
    [0.2549, 0.851, 0.451],
    [0.5059, 0.9012, 0.5012],
    [0.7569, 0.9514, 0.5514],
    [0.9961, 0.995, 0.5979],
    [0.8706, 0.8344, 0.5301],
    [0.7451, 0.6737, 0.4624],
    [0.6196, 0.5131, 0.3946],
    [0.5059, 0.3675, 0.3379],
    [0.6314, 0.5282, 0.506],
    [0.7569, 0.6888, 0.6742],
    [0.8824, 0.8494, 0.8424],
    [1.0, 1.0, 1.0],
];
const COOLWARM: [[f32; 3]; 17] = [
    [0.2298, 0.2987, 0.7537],
    [0.3042, 0.4069, 0.8453],
    [0.3837, 0.5102, 0.9178],
    [0.4677, 0.6056, 0.9685],
    [0.5543, 0.6901, 0.9955],
    [0.6408, 0.7608, 0.9978],
    [0.724, 0.8149, 0.9757],
    [0.8006, 0.8504, 0.93],
    [0.8674, 0.8644, 0.8626],
    [0.9256, 0.8255, 0.7711],
    [0.9595, 0.767, 0.6741],
    [0.9697, 0.6905, 0.5751],
    [0.9567, 0.598, 0.4773],
    [0.9214, 0.4914, 0.3834],
    [0.8654, 0.3711, 0.2958],
    [0.7906, 0.2314, 0.2162],
    [0.7057, 0.0156, 0.1502],
];

impl Ramp {
    /// Every ramp, for galleries and tests.
    pub const ALL: [Ramp; 5] = [
        Ramp::Viridis,
        Ramp::Magma,
        Ramp::Terrain,
        Ramp::Coolwarm,
        Ramp::Grey,
    ];

    /// Returns the linear colour at `t`. `t` is clamped to `[0, 1]` (a display
    /// mapping, not a parameter); NaN maps to magenta so missing data stands out.
    #[must_use]
    pub fn eval(self, t: f32) -> Vec3 {
        if t.is_nan() {
            return Vec3::new(1.0, 0.0, 1.0);
        }
        let t = t.clamp(0.0, 1.0);
        let table = match self {
            Ramp::Grey => return Vec3::splat(srgb_decode(t)),
            Ramp::Viridis => &VIRIDIS,
            Ramp::Magma => &MAGMA,
            Ramp::Terrain => &TERRAIN,
            Ramp::Coolwarm => &COOLWARM,
        };
        let x = t * (table.len() - 1) as f32;
        let i = (x as usize).min(table.len() - 2);
        let f = x - i as f32;
        let a = Vec3::from(table[i]);
        let b = Vec3::from(table[i + 1]);
        srgb_decode_rgb(a.lerp(b, f))
    }

    /// Maps `value` from `[lo, hi]` onto the ramp.
    #[must_use]
    pub fn map(self, value: f32, lo: f32, hi: f32) -> Vec3 {
        let span = hi - lo;
        let t = if span > 0.0 { (value - lo) / span } else { 0.5 };
        self.eval(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn srgb_known_values() {
        assert_eq!(srgb_encode(0.0), 0.0);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-6);
        // 18 % grey encodes to about 0.4613 (118/255).
        assert!((srgb_encode(0.18) - 0.4613).abs() < 1e-3);
        assert_eq!(to_srgb8(Vec3::new(0.0, 1.0, 0.2159)), [0, 255, 128]);
        assert_eq!(to_srgb8(Vec3::splat(7.0)), [255; 3]);
    }

    proptest! {
        #[test]
        fn srgb_round_trip(x in -2.0f32..4.0) {
            let back = srgb_decode(srgb_encode(x));
            prop_assert!((back - x).abs() <= 2e-6 * (1.0 + x.abs()), "{} -> {}", x, back);
        }

        #[test]
        fn srgb8_round_trip(r in any::<u8>(), g in any::<u8>(), b in any::<u8>()) {
            prop_assert_eq!(to_srgb8(from_srgb8([r, g, b])), [r, g, b]);
        }

        #[test]
        fn tone_maps_are_monotone_and_bounded(a in 0.0f32..100.0, d in 0.0f32..10.0) {
            for op in [ToneMap::Clip, ToneMap::Reinhard, ToneMap::AcesFilmic, ToneMap::Hable] {
                let lo = op.apply(Vec3::splat(a)).x;
                let hi = op.apply(Vec3::splat(a + d)).x;
                prop_assert!((0.0..=1.0).contains(&lo) && hi >= lo - 1e-6, "{:?} {} {}", op, lo, hi);
            }
        }
    }

    #[test]
    fn luminance_and_exposure() {
        assert!((luminance(Vec3::ONE) - 1.0).abs() < 1e-6);
        assert!(luminance(Vec3::Y) > luminance(Vec3::X) && luminance(Vec3::X) > luminance(Vec3::Z));
        assert_eq!(exposure(Vec3::ONE, 1.0), Vec3::splat(2.0));
        assert_eq!(exposure(Vec3::ONE, -2.0), Vec3::splat(0.25));
        assert!(ToneMap::AcesFilmic.apply(Vec3::splat(f32::NAN)).x.is_nan());
    }

    #[test]
    fn ramps_hit_their_endpoints_and_viridis_brightens() {
        let v0 = Ramp::Viridis.eval(0.0);
        let v1 = Ramp::Viridis.eval(1.0);
        assert!(
            (srgb_encode_rgb(v0) - Vec3::from(VIRIDIS[0]))
                .abs()
                .max_element()
                < 1e-5
        );
        assert!(
            (srgb_encode_rgb(v1) - Vec3::from(VIRIDIS[16]))
                .abs()
                .max_element()
                < 1e-5
        );
        let mut last = -1.0;
        for i in 0..=64 {
            let y = luminance(Ramp::Viridis.eval(i as f32 / 64.0));
            assert!(y > last, "viridis luminance must increase");
            last = y;
        }
        assert_eq!(Ramp::Grey.eval(1.0), Vec3::ONE);
        assert_eq!(Ramp::Magma.eval(f32::NAN), Vec3::new(1.0, 0.0, 1.0));
        assert_eq!(Ramp::Grey.map(5.0, 0.0, 10.0), Ramp::Grey.eval(0.5));
    }
}
