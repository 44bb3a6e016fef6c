//! natura-ocean with natura-core: EXR maps read
//! back with core's reader, a foam-carrying surface sampled at world
//! positions, and the optics helpers a renderer uses.

use glam::{Vec2, Vec3};
use natura_core::io::exr::read_exr;
use natura_ocean::optics::{WaterShader, critical_angle, fresnel_reflectance};
use natura_ocean::{
    Cascade, Directional, Foam, FoamParams, Jonswap, Ocean, OceanParams, Seed, Surface,
    WaterSurface, export::FrameSequence,
};

fn params() -> OceanParams {
    OceanParams {
        nx: 64,
        ny: 64,
        lx: 80.0,
        ly: 80.0,
        choppiness: 1.2,
        loop_period: Some(10.0),
        ..OceanParams::default()
    }
}

#[test]
fn a_looping_sequence_round_trips_through_exr() {
    let spectrum = Directional::new(Jonswap::default(), 0.5);
    let ocean = Ocean::new(&params(), &spectrum, Seed(3)).unwrap();
    let dir = std::env::temp_dir().join(format!("natura-ocean-it-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut seq = FrameSequence::new(&dir, "wave").unwrap();
    let mut frame = ocean.evaluate(0.0).unwrap();
    let mut foam = Foam::for_frame(&frame, FoamParams::default()).unwrap();
    for i in 0..3 {
        ocean.evaluate_into(i as f64 * 2.5, &mut frame).unwrap();
        foam.update(&frame).unwrap();
        seq.write_maps(&frame, Some(&foam)).unwrap();
    }
    let last = read_exr(&seq.written()[2]).unwrap();
    assert_eq!(last.channel("height").unwrap(), frame.height().as_slice());
    assert_eq!(last.channel("foam").unwrap(), foam.coverage().as_slice());
    // The loop closes: t = 10 s is t = 0 again.
    let first = read_exr(&seq.written()[0]).unwrap();
    ocean.evaluate_into(10.0, &mut frame).unwrap();
    let h0 = first.channel("height").unwrap();
    let rms = (h0.iter().map(|v| v * v).sum::<f32>() / h0.len() as f32).sqrt();
    for (a, b) in h0.iter().zip(frame.height().as_slice()) {
        assert!((a - b).abs() < 1e-5 * rms.max(1e-3));
    }
}

#[test]
fn a_renderer_can_sample_and_shade_a_cascade() {
    let spectrum = Directional::new(Jonswap::default(), 0.0);
    let cascade = Cascade::new(&params(), &[300.0, 41.0], &spectrum, Seed(9)).unwrap();
    let mut frames = cascade.frame().unwrap();
    cascade.evaluate_into(4.0, &mut frames).unwrap();
    let surfaces = frames.surfaces(None).unwrap();
    let shader = WaterShader::default();
    for p in [Vec2::new(0.0, 0.0), Vec2::new(1234.5, -77.0)] {
        let n = surfaces.normal_at(p);
        assert!((n.length() - 1.0).abs() < 1e-5 && n.z > 0.0);
        let c = shader.shade(Vec3::new(0.0, 0.8, -0.6), n, 100.0, None);
        assert!(c.is_finite() && c.min_element() >= 0.0);
        // Tiles with the product of the periods' common multiple: here each
        // surface repeats with its own period.
        let one = Surface::new(&frames.frames()[0], None).unwrap();
        assert!((one.height_at(p) - one.height_at(p + Vec2::new(300.0, 0.0))).abs() < 1e-3);
    }
    assert!((fresnel_reflectance(1.0, 1.0, 4.0 / 3.0) - 0.0204).abs() < 1e-4);
    assert!((90.0 - critical_angle(4.0 / 3.0, 1.0).unwrap().to_degrees() - 41.4).abs() < 0.02);
}
