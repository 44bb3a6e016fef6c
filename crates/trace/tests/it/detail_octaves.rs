//! `Detail` against the octave loop it had before it called natura-noise's
//! `FootprintFbm`: the same octave order, offsets and `f64` arithmetic, so
//! the same bits for every value, gradient and bound.
//!
//! The old loop took the octave amplitudes `a·r^(−kH)` from the platform's
//! `powf`; natura-noise takes them from `libm::pow`, as every fractal of the
//! crate does (the same on every platform). With `libm::pow` in the oracle
//! every result is bit-identical; with the platform's `powf` they agree to a
//! few units in the last place of the amplitudes.

use glam::DVec2;
use natura_noise::{Field, Perlin, visible_octaves};
use natura_trace::{Detail, DetailParams};

/// The detail octaves as `natura_trace::Detail` computed them before, kept
/// verbatim but for the power function of the amplitudes (`pow`).
struct OldDetail {
    noise: Perlin,
    amp: Vec<f64>,
    freq: Vec<f64>,
    lambda0: f64,
    freq0: f64,
    ln_lac: f64,
    lac: f64,
    lip_noise: f64,
    amp_pre: Vec<f64>,
    lip_pre: Vec<f64>,
    fp_max: Vec<f64>,
    nyquist: Vec<f64>,
}

impl OldDetail {
    fn new(p: &DetailParams, pow: fn(f64, f64) -> f64) -> Self {
        let lac = f64::from(p.lacunarity);
        let n = if p.amplitude_m > 0.0 { p.octaves } else { 0 };
        let lambda0 = f64::from(p.wavelength_m);
        let amp: Vec<f64> = (0..n)
            .map(|k| f64::from(p.amplitude_m) * pow(lac, -f64::from(k) * f64::from(p.h)))
            .collect();
        let freq: Vec<f64> = (0..n).map(|k| lac.powi(k as i32) / lambda0).collect();
        let noise = Perlin::new(p.seed);
        let (mut amp_pre, mut lip_pre, mut fp_max) = (vec![0.0f64], vec![0.0f64], vec![0.0f64]);
        let nyquist = (0..n)
            .map(|k| 0.5 * lambda0 / lac.powi(k as i32) * (1.0 + 1e-9))
            .collect();
        for k in 0..n as usize {
            amp_pre.push(amp_pre[k] + amp[k]);
            lip_pre.push(lip_pre[k] + amp[k] * freq[k]);
            let wmin = 0.5 * lambda0 / lac.powi(k as i32 + 1);
            fp_max.push(fp_max[k].max(amp[k] / wmin));
        }
        Self {
            nyquist,
            amp_pre,
            lip_pre,
            fp_max,
            lip_noise: noise.lipschitz2(),
            noise,
            amp,
            freq,
            lambda0,
            freq0: 1.0 / lambda0,
            ln_lac: lac.ln(),
            lac,
        }
    }

    fn finest_footprint(&self) -> f64 {
        0.5 * self.lambda0 / self.lac.powi(self.amp.len() as i32)
    }

    fn octaves_at(&self, w: f64) -> f64 {
        let n = self.amp.len() as f64;
        if w <= 0.0 {
            return n;
        }
        visible_octaves(w, self.freq0, self.lac).min(n)
    }

    fn point(&self, k: usize, p: DVec2) -> DVec2 {
        let s = (k + 1) as f64;
        p * self.freq[k] + DVec2::new(0.618_034 * s, 0.414_214 * s)
    }

    fn octave(&self, k: usize, n: f64, p: DVec2) -> f64 {
        (n - k as f64).min(1.0) * self.amp[k] * self.noise.eval2(self.point(k, p))
    }

    fn amplitude_between(&self, k0: usize, k1: usize) -> f64 {
        (self.amp_pre[k1] - self.amp_pre[k0]) * self.noise.bound()
    }

    fn lipschitz_first(&self, k: usize) -> f64 {
        self.lip_pre[k] * self.lip_noise
    }

    fn height(&self, p: DVec2, w: f64) -> f64 {
        let n = self.octaves_at(w);
        let mut sum = 0.0;
        for k in 0..n.ceil() as usize {
            let wk = (n - k as f64).min(1.0);
            sum += wk * self.amp[k] * self.noise.eval2(self.point(k, p));
        }
        sum
    }

    fn height_grad(&self, p: DVec2, w: f64) -> (f64, DVec2) {
        let n = self.octaves_at(w);
        let (mut v, mut g) = (0.0, DVec2::ZERO);
        for k in 0..n.ceil() as usize {
            let wk = (n - k as f64).min(1.0) * self.amp[k];
            let (nv, ng) = self.noise.eval_grad2(self.point(k, p));
            v += wk * nv;
            g += wk * self.freq[k] * ng;
        }
        (v, g)
    }

    fn amplitude_bound(&self, w: f64) -> f64 {
        let present = self.nyquist.iter().take_while(|&&f| w < f).count();
        self.amp_pre[present] * self.noise.bound()
    }

    fn lipschitz_bound(&self, w: f64) -> f64 {
        let n = self.octaves_at(w);
        let mut s = 0.0;
        for k in 0..n.ceil() as usize {
            s += (n - k as f64).min(1.0) * self.amp[k] * self.freq[k];
        }
        s * self.lip_noise
    }

    fn footprint_bound_n(&self, w: f64, n: f64) -> f64 {
        if n <= 0.0 {
            return 0.0;
        }
        let top = self.amp.len();
        let kstar = (n.floor() as usize).min(top);
        let mut b = 0.0f64;
        if kstar < top && w > 0.0 {
            b = self.amp[kstar] / w;
        }
        b = b.max(self.fp_max[kstar]);
        b * self.noise.bound() / self.ln_lac
    }
}

/// A fixed-seed uniform stream in `[0, 1)`.
fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = natura_core::mix64(s);
        natura_core::unit_f64(s)
    }
}

/// The landscape's and the detail benchmark's parameters, edge cases, then
/// random ones over the whole range `Detail` accepts.
fn parameter_sets() -> Vec<DetailParams> {
    let base = DetailParams {
        amplitude_m: 2.5,
        h: 0.8,
        lacunarity: 2.0,
        octaves: 9,
        wavelength_m: 10.0,
        seed: 0x5eed,
    };
    let mut v = vec![
        base,
        DetailParams {
            amplitude_m: 2.0,
            seed: 5,
            ..base
        },
        DetailParams {
            lacunarity: 4.0,
            octaves: 24,
            h: 0.0,
            ..base
        },
        DetailParams {
            lacunarity: 16.0,
            octaves: 24,
            h: 2.0,
            ..base
        },
        DetailParams {
            amplitude_m: 0.0,
            ..base
        },
        DetailParams { octaves: 0, ..base },
    ];
    let mut u = uniform(17);
    for i in 0..40 {
        v.push(DetailParams {
            amplitude_m: (10.0 * u()) as f32,
            h: (2.0 * u()) as f32,
            lacunarity: (1.01 + 14.99 * u()) as f32,
            octaves: (25.0 * u()) as u32,
            wavelength_m: (0.5 + 50.0 * u()) as f32,
            seed: i,
        });
    }
    v
}

fn same(a: f64, b: f64, what: &str, p: &DetailParams) {
    assert_eq!(a.to_bits(), b.to_bits(), "{what}: {a} vs {b} for {p:?}");
}

#[test]
fn detail_has_the_bits_of_the_old_octave_loop() {
    let mut u = uniform(3);
    for p in parameter_sets() {
        let new = Detail::new(&p).unwrap();
        let old = OldDetail::new(&p, libm::pow);
        let fbm = new.octaves();
        same(new.finest_footprint(), old.finest_footprint(), "finest", &p);
        same(new.far_footprint(), 0.5 * old.lambda0, "far", &p);
        let n_all = old.amp.len();
        assert_eq!(fbm.octave_count(), n_all);
        for k0 in 0..=n_all {
            same(
                fbm.lipschitz_first(k0),
                old.lipschitz_first(k0),
                "lipschitz_first",
                &p,
            );
            for k1 in k0..=n_all {
                same(
                    fbm.amplitude_between(k0, k1),
                    old.amplitude_between(k0, k1),
                    "amplitude_between",
                    &p,
                );
            }
        }
        let far = new.far_footprint();
        for _ in 0..300 {
            let q = DVec2::new(4000.0 * u() - 500.0, 4000.0 * u() - 500.0);
            // Footprints from far below the finest to beyond the far one,
            // and the point sample.
            let w = if u() < 0.05 {
                0.0
            } else {
                far * 10f64.powf(1.0 - 12.0 * u())
            };
            let n = old.octaves_at(w);
            same(fbm.visible(w), n, "visible", &p);
            same(new.height(q, w), old.height(q, w), "height", &p);
            let ((v, g), (ov, og)) = (new.height_grad(q, w), old.height_grad(q, w));
            same(v, ov, "height_grad value", &p);
            same(g.x, og.x, "gradient x", &p);
            same(g.y, og.y, "gradient y", &p);
            same(new.amplitude_bound(w), old.amplitude_bound(w), "amp", &p);
            same(new.lipschitz_bound(w), old.lipschitz_bound(w), "lip", &p);
            same(
                new.footprint_bound(w),
                old.footprint_bound_n(w, n),
                "footprint",
                &p,
            );
            for k in 0..n.ceil() as usize {
                same(fbm.octave_term(k, n, q), old.octave(k, n, q), "term", &p);
            }
        }
    }
}

#[test]
fn with_the_platform_powf_the_old_loop_agrees_to_rounding() {
    let mut u = uniform(9);
    for p in parameter_sets() {
        let new = Detail::new(&p).unwrap();
        let old = OldDetail::new(&p, f64::powf);
        for (k, &a) in old.amp.iter().enumerate() {
            let b = new.octaves().amplitude(k);
            assert!((a - b).abs() <= 4.0 * f64::EPSILON * a, "{a} {b}");
        }
        let scale = old.amplitude_bound(0.0) + 1e-300;
        for _ in 0..100 {
            let q = DVec2::new(1000.0 * u(), 1000.0 * u());
            let w = new.far_footprint() * 10f64.powf(-6.0 * u());
            let d = (new.height(q, w) - old.height(q, w)).abs();
            assert!(d <= 1e-14 * scale, "{d} for {p:?}");
        }
    }
}
