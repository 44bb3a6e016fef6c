//! The march's density samples per step (`FastSettings::substeps`): parts
//! see structure finer than the step that one sample a step folds away,
//! their step integrals are exact, and a bad count is refused.

use glam::Vec3;
use natura_core::Aabb;
use natura_volume::density::Homogeneous;
use natura_volume::phase::CloudPhase;
use natura_volume::transport::{
    Emission, FastRenderer, FastSettings, MAX_SUBSTEPS, MediumParams, Scene, Shadows,
};
use natura_volume::{Density, VolumeError};

/// Slabs across `x`, one every `PERIOD` m, dense (density 1) over their
/// first quarter, inside the box `[−1, 1]³`.
#[derive(Debug)]
struct Stripes;

const PERIOD: f32 = 0.125;
const SIGMA: f32 = 3.0;

impl Density for Stripes {
    fn density(&self, p: Vec3) -> f32 {
        if !self.bounds().contains(p) {
            return 0.0;
        }
        let phase = ((p.x + 1.0) / PERIOD).fract();
        if phase < 0.25 { 1.0 } else { 0.0 }
    }
    fn bounds(&self) -> Aabb {
        Aabb {
            min: Vec3::splat(-1.0),
            max: Vec3::splat(1.0),
        }
    }
    fn bound_in(&self, _region: &Aabb) -> f32 {
        1.0
    }
    fn max_density(&self) -> f32 {
        1.0
    }
}

/// A glowing absorber (albedo 0, emitted radiance 1 per unit of the uniform
/// field): the radiance through it is `1 − T`, the step integrals exact for
/// a density constant over each part.
fn glowing<'a>(stripes: &'a Stripes, glow: &'a Homogeneous) -> Scene<'a> {
    Scene {
        emission: Some(Emission {
            field: glow,
            offset: 0.0,
            colour: Vec3::ONE,
        }),
        ..Scene::new(
            stripes,
            MediumParams {
                extinction: SIGMA,
                albedo: 0.0,
                phase: CloudPhase::Isotropic,
            },
            Vec3::ZERO,
        )
    }
}

fn settings(step: f32, substeps: u32) -> FastSettings {
    FastSettings {
        step,
        shadows: Shadows::Rays(0.05),
        substeps,
        ..FastSettings::default()
    }
}

#[test]
fn parts_see_the_stripes_one_sample_a_step_folds_away() {
    let glow = Homogeneous::new(Stripes.bounds(), 1.0).unwrap();
    let scene = glowing(&Stripes, &glow);
    let (o, d) = (Vec3::new(-3.0, 0.1, 0.2), Vec3::X);
    // A quarter of the 2 m path is dense.
    let t_exact = (-SIGMA * 0.5f32).exp();
    // Steps as long as the stripes' period: every midpoint falls in the
    // empty three quarters, and the march sees nothing.
    let whole = FastRenderer::new(&scene, settings(PERIOD, 1)).unwrap();
    let s = whole.seen(o, d);
    assert_eq!(s.transmittance, 1.0);
    assert_eq!(s.radiance, Vec3::ZERO);
    // Eight parts a step: two of them in the dense quarter, as it is.
    let parts = FastRenderer::new(&scene, settings(PERIOD, 8)).unwrap();
    let s = parts.seen(o, d);
    approx::assert_relative_eq!(s.transmittance, t_exact, max_relative = 1e-4);
    approx::assert_relative_eq!(s.radiance.x, 1.0 - t_exact, max_relative = 1e-4);
    // The same as steps an eighth as long, one sample each.
    let fine = FastRenderer::new(&scene, settings(PERIOD / 8.0, 1)).unwrap();
    let f = fine.seen(o, d);
    approx::assert_relative_eq!(s.transmittance, f.transmittance, max_relative = 1e-4);
    approx::assert_relative_eq!(s.radiance.x, f.radiance.x, max_relative = 1e-4);
}

#[test]
fn parts_of_a_homogeneous_medium_add_up_to_the_whole_step() {
    // Sunlit scattering slab: with the light looked up once a step, parts
    // of equal density integrate to the whole step's exact integral.
    let slab = Homogeneous::new(Stripes.bounds(), 0.6).unwrap();
    let scene = Scene {
        sun: Some(natura_volume::transport::Sun {
            direction: Vec3::new(0.3, 0.2, 1.0).normalize(),
            irradiance: Vec3::splat(2.0),
        }),
        ..Scene::new(
            &slab,
            MediumParams {
                extinction: 2.0,
                albedo: 0.9,
                phase: CloudPhase::HenyeyGreenstein(0.5),
            },
            Vec3::splat(0.2),
        )
    };
    let a = FastRenderer::new(&scene, settings(0.1, 1)).unwrap();
    let b = FastRenderer::new(&scene, settings(0.1, 5)).unwrap();
    for d in [Vec3::X, Vec3::new(1.0, 0.4, -0.3).normalize()] {
        let o = Vec3::new(-3.0, 0.1, 0.2) - d;
        let (sa, sb) = (a.seen(o, d), b.seen(o, d));
        approx::assert_relative_eq!(sa.transmittance, sb.transmittance, max_relative = 1e-4);
        for c in 0..3 {
            approx::assert_relative_eq!(sa.radiance[c], sb.radiance[c], max_relative = 1e-4);
        }
    }
}

#[test]
fn a_bad_count_of_parts_is_refused_by_name() {
    let glow = Homogeneous::new(Stripes.bounds(), 1.0).unwrap();
    let scene = glowing(&Stripes, &glow);
    for n in [0, MAX_SUBSTEPS + 1, u32::MAX] {
        match FastRenderer::new(&scene, settings(0.1, n)) {
            Err(VolumeError::InvalidParameter { name, .. }) => assert_eq!(name, "substeps"),
            other => panic!("{n} parts: {other:?}"),
        }
    }
    assert!(FastRenderer::new(&scene, settings(0.1, MAX_SUBSTEPS)).is_ok());
}
