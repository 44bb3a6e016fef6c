//! The FFT ocean against its oracles: the straightforward reference, the
//! direct `f64` sum, closed forms, and conservation laws.

use glam::DVec2;
use natura_core::Grid2;
use natura_ocean::reference::Reference;
use natura_ocean::{
    AmplitudeScheme, Dispersion, Frame, FrameField, Ocean, OceanError, OceanParams, Phillips, Seed,
    Spectrum,
};

fn rms(g: &Grid2<f32>) -> f32 {
    let s: f64 = g
        .as_slice()
        .iter()
        .map(|&v| f64::from(v) * f64::from(v))
        .sum();
    (s / g.len() as f64).sqrt() as f32
}

fn max_diff(a: &Grid2<f32>, b: &Grid2<f32>) -> f32 {
    a.as_slice()
        .iter()
        .zip(b.as_slice())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f32::max)
}

fn phillips(v: f64) -> Phillips {
    Phillips {
        wind_speed: v,
        small_wave_length: 0.05,
        wind_direction: 0.4,
        ..Phillips::default()
    }
}

fn small(nx: usize, ny: usize, chop: f64) -> OceanParams {
    OceanParams {
        nx,
        ny,
        lx: 120.0,
        ly: 80.0,
        choppiness: chop,
        ..OceanParams::default()
    }
}

/// A spectrum with energy only inside an annulus: many modes of equal weight,
/// so sample variances converge fast.
#[derive(Debug)]
struct Band(f64, f64);
impl Spectrum for Band {
    fn density(&self, k: DVec2) -> f64 {
        let kk = k.length();
        if kk >= self.0 && kk < self.1 {
            1e-3
        } else {
            0.0
        }
    }
    fn validate(&self) -> natura_ocean::Result<()> {
        Ok(())
    }
}

/// A single wave travelling along +k₀.
#[derive(Debug)]
struct OneMode(DVec2);
impl Spectrum for OneMode {
    fn density(&self, k: DVec2) -> f64 {
        if (k - self.0).length() < 1e-9 * self.0.length() {
            1.0
        } else {
            0.0
        }
    }
    fn validate(&self) -> natura_ocean::Result<()> {
        Ok(())
    }
}

#[test]
fn fast_path_matches_the_one_fft_per_field_reference() {
    for (nx, ny) in [(64, 32), (16, 128), (128, 128)] {
        let ocean = Ocean::new(&small(nx, ny, 0.9), &phillips(9.0), Seed(3)).unwrap();
        let frame = ocean.evaluate(7.25).unwrap();
        let mut r = Reference::new(&ocean).unwrap();
        r.evaluate(7.25).unwrap();
        for f in FrameField::ALL {
            let scale = rms(r.field(f)).max(1e-6);
            let d = max_diff(frame.field(f), r.field(f));
            assert!(
                d <= 2e-5 * scale.max(1.0),
                "{nx}×{ny} {f:?}: diff {d}, rms {scale}"
            );
        }
    }
}

#[test]
fn output_is_real_to_round_off() {
    // Imaginary residue ≤ 1e-5 of the field's RMS, for every field.
    let ocean = Ocean::new(&small(128, 64, 1.2), &phillips(12.0), Seed(11)).unwrap();
    let mut r = Reference::new(&ocean).unwrap();
    for t in [0.0, 3.3, 1000.0] {
        r.evaluate(t).unwrap();
        for f in FrameField::ALL {
            let res = r.imaginary_residue(f);
            assert!(res <= 1e-5, "t={t} {f:?}: residue {res}");
        }
    }
    // Hermitian symmetry of h̃(k, t) holds exactly.
    let (nx, ny) = (128, 64);
    let s = ocean.spectrum_at(2.7);
    for m in 0..ny {
        for n in 0..nx {
            let neg = ((ny - m) % ny) * nx + (nx - n) % nx;
            assert_eq!(s[neg], s[m * nx + n].conj());
        }
    }
}

#[test]
fn fast_path_matches_the_direct_sum_at_grid_points() {
    let p = small(32, 32, 0.7);
    let ocean = Ocean::new(&p, &phillips(7.0), Seed(5)).unwrap();
    let t = 4.5;
    let frame = ocean.evaluate(t).unwrap();
    let c = p.cell_size();
    let scale = |f: FrameField| rms(frame.field(f)).max(1e-3);
    for (i, j) in [(0, 0), (3, 17), (31, 31), (16, 5)] {
        let d = ocean.sample_direct(i as f64 * c.x, j as f64 * c.y, t);
        let at = |f: FrameField| f64::from(frame.field(f)[(i, j)]);
        let tol = |f: FrameField| 2e-5 * f64::from(scale(f));
        assert!((at(FrameField::Height) - d.height).abs() < tol(FrameField::Height));
        assert!((at(FrameField::SlopeX) - d.slope.x).abs() < tol(FrameField::SlopeX));
        assert!((at(FrameField::SlopeY) - d.slope.y).abs() < tol(FrameField::SlopeY));
        assert!((at(FrameField::DispX) - d.displacement.x).abs() < tol(FrameField::DispX));
        assert!((at(FrameField::DispY) - d.displacement.y).abs() < tol(FrameField::DispY));
        assert!((at(FrameField::Jxx) - d.jxx).abs() < 1e-5);
        assert!((at(FrameField::Jyy) - d.jyy).abs() < 1e-5);
        assert!((at(FrameField::Jxy) - d.jxy).abs() < 1e-5);
    }
}

/// The resolution paragraph of Tessendorf 2001, §3.4 swaps N and M in
/// `Δx = Lx/N`, `Δz = Lz/M`; eq. 19 is right. On a patch whose sample
/// counts (64 × 16) and lengths (120 m × 80 m) both differ, the FFT grid
/// matches the direct sum of eq. 19 only if sample (i, j) sits at
/// (i·Lx/N, j·Ly/M): with the swapped spacings it would sit at
/// (i·Lx/M, j·Ly/N), where the surface is different.
#[test]
fn a_non_square_patch_samples_eq_19_at_lx_over_n_and_ly_over_m() {
    let p = small(64, 16, 0.5);
    let ocean = Ocean::new(&p, &phillips(7.0), Seed(12)).unwrap();
    let t = 2.0;
    let frame = ocean.evaluate(t).unwrap();
    let c = p.cell_size();
    assert_eq!((c.x, c.y), (120.0 / 64.0, 80.0 / 16.0));
    let h = frame.field(FrameField::Height);
    let tol = 2e-5 * f64::from(rms(h).max(1e-3));
    let (mut swapped_err, mut n) = (0.0, 0.0);
    for (i, j) in [(0, 0), (5, 3), (63, 15), (40, 9), (17, 12)] {
        let right = ocean.sample_direct(i as f64 * c.x, j as f64 * c.y, t);
        assert!(
            (f64::from(h[(i, j)]) - right.height).abs() < tol,
            "({i}, {j})"
        );
        let swapped = ocean.sample_direct(i as f64 * p.lx / 16.0, j as f64 * p.ly / 64.0, t);
        swapped_err += (f64::from(h[(i, j)]) - swapped.height).abs();
        n += 1.0;
    }
    // Sample (0, 0) agrees under both readings; the rest do not.
    assert!(swapped_err / n > 100.0 * tol, "{}", swapped_err / n);
}

#[test]
fn periodic_in_space() {
    let p = small(32, 16, 0.5);
    let ocean = Ocean::new(&p, &phillips(8.0), Seed(1)).unwrap();
    for (x, y) in [(3.3, 7.1), (100.0, 0.5)] {
        let a = ocean.sample_direct(x, y, 1.0);
        for (dx, dy) in [(p.lx, 0.0), (0.0, p.ly), (-2.0 * p.lx, 3.0 * p.ly)] {
            let b = ocean.sample_direct(x + dx, y + dy, 1.0);
            assert!((a.height - b.height).abs() < 1e-9);
            assert!((a.slope - b.slope).length() < 1e-9);
            assert!((a.displacement - b.displacement).length() < 1e-9);
        }
    }
}

#[test]
fn periodic_in_time_with_quantised_dispersion() {
    let period = 20.0;
    let p = OceanParams {
        loop_period: Some(period),
        ..small(64, 64, 0.8)
    };
    let ocean = Ocean::new(&p, &phillips(10.0), Seed(9)).unwrap();
    let w0 = std::f64::consts::TAU / period;
    for &w in ocean.omega() {
        assert!((w / w0 - (w / w0).round()).abs() < 1e-9);
    }
    let mut a = Frame::new(&ocean).unwrap();
    let mut b = Frame::new(&ocean).unwrap();
    for t in [0.0, 3.7, 19.9] {
        ocean.evaluate_into(t, &mut a).unwrap();
        ocean.evaluate_into(t + period, &mut b).unwrap();
        for f in FrameField::ALL {
            let d = max_diff(a.field(f), b.field(f));
            assert!(d <= 1e-5 * rms(a.field(f)).max(1.0), "{f:?} {d}");
        }
        ocean.evaluate_into(t + 7.0 * period, &mut b).unwrap();
        assert!(max_diff(a.height(), b.height()) <= 1e-5 * rms(a.height()));
    }
    // Without quantisation the surface does not repeat after T.
    let free = Ocean::new(&small(64, 64, 0.8), &phillips(10.0), Seed(9)).unwrap();
    let a = free.evaluate(3.7).unwrap();
    let b = free.evaluate(3.7 + period).unwrap();
    assert!(max_diff(a.height(), b.height()) > 0.1 * rms(a.height()));
}

#[test]
fn mean_is_zero_and_parseval_holds() {
    let ocean = Ocean::new(&small(64, 64, 1.0), &phillips(10.0), Seed(21)).unwrap();
    for t in [0.0, 2.0, 55.5] {
        let frame = ocean.evaluate(t).unwrap();
        for f in [
            FrameField::Height,
            FrameField::SlopeX,
            FrameField::SlopeY,
            FrameField::DispX,
            FrameField::DispY,
        ] {
            let mean = frame.field(f).mean();
            assert!(
                mean.abs() < 1e-6 * f64::from(rms(frame.field(f))),
                "{f:?} mean {mean}"
            );
        }
        // (1/NM) Σ h² = Σ |h̃(k,t)|² for the unnormalised sum of eq. 19.
        let spec: f64 = ocean.spectrum_at(t).iter().map(|c| c.norm_sqr()).sum();
        let var = frame.height_variance();
        assert!((var / spec - 1.0).abs() < 1e-5, "{var} vs {spec}");
    }
}

#[test]
fn sample_variance_matches_the_spectrum_sum() {
    // E[(1/NM) Σ h²] = Σ_k P(k) Δk² (the factor-2 erratum fixed), within 1%.
    let band = Band(0.2, 1.2);
    for scheme in [
        AmplitudeScheme::ComplexGaussian,
        AmplitudeScheme::GaussianUniformPhase,
    ] {
        let p = OceanParams {
            amplitudes: scheme,
            ..small(32, 32, 0.0)
        };
        let seeds = 200;
        let mut sum = 0.0;
        let mut expected = 0.0;
        for s in 0..seeds {
            let ocean = Ocean::new(&p, &band, Seed(s)).unwrap();
            expected = ocean.expected_variance(&band);
            sum += ocean.evaluate(1.7).unwrap().height_variance();
        }
        let got = sum / seeds as f64;
        assert!(
            (got / expected - 1.0).abs() < 0.01,
            "{scheme:?}: {got} vs {expected}"
        );
    }
}

#[test]
fn amplitudes_have_the_documented_statistics() {
    let band = Band(0.2, 1.2);
    let p = small(32, 32, 0.0);
    let cell = std::f64::consts::TAU.powi(2) / (p.lx * p.ly);
    let (mut re, mut im, mut re2, mut im2, mut count) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for s in 0..100 {
        let ocean = Ocean::new(&p, &band, Seed(s)).unwrap();
        for (i, h) in ocean.h0().iter().enumerate() {
            let k = ocean.wave_vector(i % p.nx, i / p.nx);
            let pk = band.density(k);
            if pk == 0.0 || i % p.nx == p.nx / 2 || i / p.nx == p.ny / 2 {
                continue;
            }
            let z = *h / (0.5 * pk * cell).sqrt();
            re += z.re;
            im += z.im;
            re2 += z.re * z.re;
            im2 += z.im * z.im;
            count += 1.0;
        }
    }
    // Notes eq. 25: Re and Im of h̃₀/√(½PΔk²) each have mean 0 and variance ½.
    assert!(count > 10_000.0);
    assert!((re / count).abs() < 0.02 && (im / count).abs() < 0.02);
    assert!((re2 / count - 0.5).abs() < 0.02, "{}", re2 / count);
    assert!((im2 / count - 0.5).abs() < 0.02, "{}", im2 / count);
}

#[test]
fn slope_matches_central_differences_on_a_smooth_field() {
    // Band-limit to k Δx ≤ 0.25 so the central difference is accurate to
    // ~(kΔx)²/6 ≈ 1%; the FFT slope is exact.
    let p = OceanParams {
        nx: 128,
        ny: 128,
        lx: 128.0,
        ly: 128.0,
        k_max: 0.25,
        choppiness: 0.6,
        ..OceanParams::default()
    };
    let ocean = Ocean::new(&p, &phillips(6.0), Seed(4)).unwrap();
    let f = ocean.evaluate(2.0).unwrap();
    let (n, m) = (128usize, 128usize);
    let h = f.height();
    let (dx, dy) = (f.disp_x(), f.disp_y());
    let mut worst = [0.0f32; 5];
    for j in 0..m {
        for i in 0..n {
            let (ip, im) = ((i + 1) % n, (i + n - 1) % n);
            let (jp, jm) = ((j + 1) % m, (j + m - 1) % m);
            let cdx = |g: &Grid2<f32>| (g[(ip, j)] - g[(im, j)]) / 2.0;
            let cdy = |g: &Grid2<f32>| (g[(i, jp)] - g[(i, jm)]) / 2.0;
            worst[0] = worst[0].max((cdx(h) - f.slope_x()[(i, j)]).abs());
            worst[1] = worst[1].max((cdy(h) - f.slope_y()[(i, j)]).abs());
            worst[2] = worst[2].max((1.0 + cdx(dx) - f.jxx()[(i, j)]).abs());
            worst[3] = worst[3].max((1.0 + cdy(dy) - f.jyy()[(i, j)]).abs());
            worst[4] = worst[4].max((cdy(dx) - f.jxy()[(i, j)]).abs());
        }
    }
    let scale = [
        rms(f.slope_x()),
        rms(f.slope_y()),
        rms(&f.jxx().map(|v| v - 1.0)),
        rms(&f.jyy().map(|v| v - 1.0)),
        rms(f.jxy()),
    ];
    for (w, s) in worst.iter().zip(scale) {
        assert!(*w < 0.03 * s, "{worst:?} vs {scale:?}");
    }
    // The symmetric term is the same from either side: ∂d_x/∂y = ∂d_y/∂x.
    let mut asym = 0.0f32;
    for j in 0..m {
        for i in 0..n {
            let a = (dx[(i, (j + 1) % m)] - dx[(i, (j + m - 1) % m)]) / 2.0;
            let b = (dy[((i + 1) % n, j)] - dy[((i + n - 1) % n, j)]) / 2.0;
            asym = asym.max((a - b).abs());
        }
    }
    assert!(asym < 0.03 * scale[4]);
}

#[test]
fn no_chop_means_identity_jacobian() {
    let ocean = Ocean::new(&small(64, 32, 0.0), &phillips(15.0), Seed(2)).unwrap();
    let f = ocean.evaluate(12.0).unwrap();
    assert!(f.jxx().as_slice().iter().all(|&v| v == 1.0));
    assert!(f.jyy().as_slice().iter().all(|&v| v == 1.0));
    assert!(f.jxy().as_slice().iter().all(|&v| v == 0.0));
    assert!(f.disp_x().as_slice().iter().all(|&v| v == 0.0));
    assert!(f.disp_y().as_slice().iter().all(|&v| v == 0.0));
    assert!(f.jacobian_grid().as_slice().iter().all(|&v| v == 1.0));
    let e = f.eigen(5, 7);
    assert_eq!((e.j_minus, e.j_plus), (1.0, 1.0));
}

#[test]
fn a_single_mode_travels_at_its_phase_speed() {
    let cases = [
        (Dispersion::Deep { g: 9.8 }, 64.0),
        (Dispersion::FiniteDepth { g: 9.8, depth: 1.5 }, 64.0),
        (
            Dispersion::Capillary {
                g: 9.8,
                capillary_length: natura_ocean::dispersion::CAPILLARY_LENGTH_WATER,
            },
            0.064,
        ),
    ];
    for (disp, l) in cases {
        let n = 64;
        let dxm = l / n as f64;
        let k0 = DVec2::new(std::f64::consts::TAU * 4.0 / l, 0.0);
        let p = OceanParams {
            nx: n,
            ny: 16,
            lx: l,
            ly: l / 4.0,
            dispersion: disp,
            ..OceanParams::default()
        };
        let ocean = Ocean::new(&p, &OneMode(k0), Seed(1)).unwrap();
        let c = disp.omega(k0.x) / k0.x;
        // Pick t so the wave moves exactly 5 cells.
        let shift = 5;
        let t = shift as f64 * dxm / c;
        let a = ocean.evaluate(0.0).unwrap();
        let b = ocean.evaluate(t).unwrap();
        let s = rms(a.height());
        assert!(s > 0.0);
        for j in 0..16 {
            for i in 0..n {
                // Travelling along +x̂: h(x, t) = h(x − c t, 0).
                let want = a.height()[((i + n - shift) % n, j)];
                let got = b.height()[(i, j)];
                assert!((want - got).abs() < 1e-4 * s, "{disp:?}: {want} vs {got}");
            }
        }
    }
}

#[test]
fn choppy_single_mode_sharpens_crests_and_folds_there() {
    let n = 64;
    let l = 64.0;
    let k = std::f64::consts::TAU * 2.0 / l;
    let k0 = DVec2::new(k, 0.0);
    for chop in [0.5, 3.0] {
        let p = OceanParams {
            nx: n,
            ny: 16,
            lx: l,
            ly: 16.0,
            choppiness: chop,
            ..OceanParams::default()
        };
        let ocean = Ocean::new(&p, &OneMode(k0), Seed(8)).unwrap();
        let f = ocean.evaluate(0.0).unwrap();
        let h = f.height();
        let amp = (0..n).map(|i| h[(i, 0)].abs()).fold(0.0f32, f32::max);
        let (mut j_crest, mut j_trough) = (f32::MAX, f32::MIN);
        for i in 0..n {
            let hv = h[(i, 3)];
            let j = f.jacobian(i, 3);
            // J = 1 − λ A k cos(phase): h / A is that cosine.
            let want = 1.0 - (chop * k) as f32 * hv;
            assert!((j - want).abs() < 1e-4, "{j} vs {want}");
            if hv > 0.99 * amp {
                j_crest = j_crest.min(j);
            }
            if hv < -0.99 * amp {
                j_trough = j_trough.max(j);
            }
            assert_eq!(f.is_folded(i, 3), f.eigen(i, 3).j_minus < 0.0);
        }
        // Crests are compressed (J < 1), troughs stretched.
        assert!(j_crest < 1.0 && j_trough > 1.0);
        let folds = (chop * f64::from(amp) * k) > 1.0;
        assert_eq!(j_crest < 0.0, folds, "λAk = {}", chop * f64::from(amp) * k);
    }
}

#[test]
fn deterministic_across_runs_orders_and_thread_counts() {
    let p = small(128, 64, 1.0);
    let s = phillips(11.0);
    let ocean = Ocean::new(&p, &s, Seed(77)).unwrap();
    let again = Ocean::new(&p, &s, Seed(77)).unwrap();
    assert_eq!(ocean.h0(), again.h0());
    let other = Ocean::new(&p, &s, Seed(78)).unwrap();
    assert_ne!(ocean.h0(), other.h0());
    let run = |threads: usize, times: &[f64]| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut f = Frame::new(&ocean).unwrap();
            for &t in times {
                ocean.evaluate_into(t, &mut f).unwrap();
            }
            f
        })
    };
    let a = run(1, &[3.0]);
    let b = run(2, &[100.0, 3.0]);
    let c = run(2, &[3.0]);
    for f in FrameField::ALL {
        assert_eq!(a.field(f), b.field(f), "{f:?}");
        assert_eq!(a.field(f), c.field(f), "{f:?}");
    }
}

#[test]
fn coarse_waves_survive_a_change_of_resolution() {
    let s = phillips(9.0);
    let a = Ocean::new(&small(32, 32, 0.0), &s, Seed(4)).unwrap();
    let b = Ocean::new(&small(64, 64, 0.0), &s, Seed(4)).unwrap();
    for m in 0..8usize {
        for n in 0..8usize {
            assert_eq!(a.h0()[m * 32 + n], b.h0()[m * 64 + n]);
        }
    }
}

#[test]
fn bad_input_is_refused_with_typed_errors() {
    let s = phillips(10.0);
    for (nx, ny) in [
        (0, 64),
        (64, 0),
        (15, 64),
        (64, 24),
        (8, 64),
        (4096, 64),
        (64, 100),
    ] {
        let p = OceanParams {
            nx,
            ny,
            ..OceanParams::default()
        };
        assert!(matches!(
            Ocean::new(&p, &s, Seed(1)),
            Err(OceanError::InvalidSize { .. })
        ));
    }
    let bad = [
        OceanParams {
            lx: 0.0,
            ..small(16, 16, 0.0)
        },
        OceanParams {
            ly: f64::NAN,
            ..small(16, 16, 0.0)
        },
        OceanParams {
            choppiness: -1.0,
            ..small(16, 16, 0.0)
        },
        OceanParams {
            loop_period: Some(0.0),
            ..small(16, 16, 0.0)
        },
        OceanParams {
            dispersion: Dispersion::FiniteDepth { g: 9.8, depth: 0.0 },
            ..small(16, 16, 0.0)
        },
        OceanParams {
            dispersion: Dispersion::FiniteDepth {
                g: 9.8,
                depth: -3.0,
            },
            ..small(16, 16, 0.0)
        },
        OceanParams {
            k_min: 2.0,
            k_max: 1.0,
            ..small(16, 16, 0.0)
        },
    ];
    for p in bad {
        assert!(
            matches!(
                Ocean::new(&p, &s, Seed(1)),
                Err(OceanError::InvalidParameter { .. })
            ),
            "{p:?}"
        );
    }
    let neg_wind = Phillips {
        wind_speed: -5.0,
        ..Phillips::default()
    };
    assert!(matches!(
        Ocean::new(&small(16, 16, 0.0), &neg_wind, Seed(1)),
        Err(OceanError::InvalidParameter {
            name: "wind_speed",
            ..
        })
    ));
    #[derive(Debug)]
    struct Nan;
    impl Spectrum for Nan {
        fn density(&self, _: DVec2) -> f64 {
            f64::NAN
        }
        fn validate(&self) -> natura_ocean::Result<()> {
            Ok(())
        }
    }
    assert!(matches!(
        Ocean::new(&small(16, 16, 0.0), &Nan, Seed(1)),
        Err(OceanError::BadSpectrum { .. })
    ));
    let ocean = Ocean::new(&small(32, 16, 0.0), &s, Seed(1)).unwrap();
    let mut f = Frame::new(&ocean).unwrap();
    assert!(ocean.evaluate_into(f64::NAN, &mut f).is_err());
    let other = Ocean::new(&small(16, 32, 0.0), &s, Seed(1)).unwrap();
    assert!(matches!(
        other.evaluate_into(0.0, &mut f),
        Err(OceanError::SizeMismatch { .. })
    ));
}
