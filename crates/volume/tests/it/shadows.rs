//! Ebert's shadow tables against direct shadow rays: on a cumulus, and in
//! the lit layer of a dense ball.

use glam::Vec3;
use natura_volume::Density;
use natura_volume::cloud::{CloudParams, cloud, nine_sphere_cumulus};
use natura_volume::density::Ball;
use natura_volume::grid::GridDensity;
use natura_volume::transport::ShadowTable;
use natura_volume::transport::shadow::optical_depth_ray;

fn cumulus_grid() -> GridDensity {
    let c = cloud(nine_sphere_cumulus(), CloudParams::cumulus(), 7).unwrap();
    GridDensity::bake(&c, 0.25).unwrap()
}

#[test]
fn shadow_table_agrees_with_shadow_rays() {
    let g = cumulus_grid();
    let sun = Vec3::new(0.5, 0.3, 0.8).normalize();
    let ext = 2.0;
    let b = g.bounds();
    // Stated tolerance, in transmittance: at 64 nodes along the longest axis
    // (node spacing ≈ 1.4 voxels) mean |ΔT| < 0.005 and max < 0.04; at 128
    // nodes mean < 0.002 and max < 0.015.
    for (nodes, mean_tol, max_tol) in [(64usize, 0.005f32, 0.04f32), (128, 0.002, 0.015)] {
        let dims = natura_volume::transport::shadow::table_dims(&b, nodes);
        let table = ShadowTable::build(&g, ext, sun, dims).unwrap();
        let (mut worst, mut sum, mut n) = (0.0f32, 0.0f32, 0);
        let mut s = 12345u32;
        let mut u = || {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            (s >> 8) as f32 / (1 << 24) as f32
        };
        for _ in 0..3000 {
            let p = b.min + (b.max - b.min) * Vec3::new(u(), u(), u());
            if g.density(p) <= 0.0 {
                continue;
            }
            let ray = (-optical_depth_ray(&g, ext, p, sun, 0.02)).exp();
            let tab = table.transmittance(p);
            worst = worst.max((ray - tab).abs());
            sum += (ray - tab).abs();
            n += 1;
        }
        let mean = sum / n as f32;
        eprintln!(
            "shadow table ({nodes} nodes) vs rays: {n} points, mean |ΔT| = {mean:.4}, max |ΔT| = {worst:.4}"
        );
        assert!(
            mean < mean_tol && worst < max_tol,
            "{nodes}: mean {mean}, max {worst}"
        );
    }
}

/// The lit layer of a dense ball (optical thickness 50 across, a cell of a
/// 96-node table half a mean free path): nodes in clear air above the lit
/// surface carry the optical depth on across it, so the table neither
/// darkens the layer (a node there storing 0 would put a positive depth on
/// the surface itself) nor brightens it.
#[test]
fn shadow_table_holds_the_lit_layer_of_a_dense_ball() {
    let ball = Ball::new(Vec3::new(0.1, -0.2, 0.3), 1.0, 1.0).unwrap();
    let ext = 25.0;
    let b = ball.bounds();
    let mut s = 777u32;
    let mut u = || {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        (s >> 8) as f32 / (1 << 24) as f32
    };
    for sun in [
        Vec3::new(0.3, -0.5, 0.8).normalize(),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(-0.7, 0.2, 0.1).normalize(),
    ] {
        let dims = natura_volume::transport::shadow::table_dims(&b, 96);
        let table = ShadowTable::build(&ball, ext, sun, dims).unwrap();
        let (mut bias, mut abs, mut ray_sum, mut n) = (0.0f64, 0.0f64, 0.0f64, 0);
        while n < 4000 {
            let p = b.min + (b.max - b.min) * Vec3::new(u(), u(), u());
            if ball.density(p) <= 0.0 {
                continue;
            }
            let tau = optical_depth_ray(&ball, ext, p, sun, 0.0005);
            if tau > 3.0 {
                continue;
            }
            let (ray, tab) = (f64::from((-tau).exp()), f64::from(table.transmittance(p)));
            bias += tab - ray;
            abs += (tab - ray).abs();
            ray_sum += ray;
            n += 1;
        }
        let (bias, abs) = (bias / ray_sum, abs / ray_sum);
        eprintln!("lit layer, sun {sun:?}: table − rays {bias:+.4} of the light, |Δ| {abs:.4}");
        // Measured: bias +0.009 … +0.015 (the limb, where the depth grows
        // as a square root across the light and a linear blend falls
        // short of it), |Δ| 0.068 … 0.081; with clear nodes storing 0 the
        // bias was −0.019 … −0.025 and |Δ| 0.080 … 0.091.
        assert!(
            (-0.005..0.02).contains(&bias) && abs < 0.085,
            "sun {sun:?}: bias {bias}, |Δ| {abs}"
        );
    }
}
