//! Plate 4.7 of `figures_musgrave`: a diffusion-limited aggregate
//! (natura-terrain's `dla`) seen through natura-atmos's radial fog as a
//! depth cue, with no light source: the spheres keep one dark colour and
//! the semi-luminous fog, thicker towards the cluster's far side, tells
//! near from far.

use natura::atmos::Medium;
use natura::atmos::medium::RadialAtmosphere;
use natura::core::Image;
use natura::core::glam::DVec3;
use natura::terrain::Seed;
use natura::terrain::synth::dla;

use crate::common::Exit;

type R<T> = Result<T, Exit>;

/// Pl. 4.7: `particles` sites as spheres of radius 0.6 lattice units,
/// drawn as depth-tested sphere splats seen from outside the cluster, each
/// pixel blended towards the fog by the radial fog between the eye and
/// the sphere (or to infinity where no sphere is).
pub(crate) fn dla_picture(seed: u64, quick: bool) -> R<Image> {
    let sites = dla(if quick { 800 } else { 12_000 }, Seed(seed))?;
    let pts: Vec<DVec3> = sites.iter().map(|p| p.as_dvec3()).collect();
    let centre = pts.iter().sum::<DVec3>() / pts.len() as f64;
    let extent = pts.iter().map(|p| p.distance(centre)).fold(1.0, f64::max);
    // The fog: a Gaussian ball about the cluster (a radial atmosphere with a
    // small core), pale blue, its central column about 3 optical depths.
    let fog = RadialAtmosphere::new(
        DVec3::new(0.9, 1.0, 1.15) * 1.7 / extent,
        DVec3::new(0.55, 0.65, 0.85),
        centre,
        extent / 100.0,
        50.0 * extent,
    )?;
    let n = if quick { 200 } else { 900 };
    let eye = centre + DVec3::new(0.3, -1.0, 0.35).normalize() * 3.2 * extent;
    let f = (centre - eye).normalize();
    let right = f.cross(DVec3::Z).normalize();
    let up = right.cross(f);
    let focal = 1.0 / (22f64.to_radians()).tan();
    let half = n as f64 / 2.0;
    // Splat the spheres: the nearest surface point's distance per pixel.
    let mut depth = vec![f64::INFINITY; n * n];
    let r = 0.6;
    for &p in &pts {
        let v = p - eye;
        let z = v.dot(f);
        if z <= r {
            continue;
        }
        let (sx, sy) = (v.dot(right) / z * focal, v.dot(up) / z * focal);
        let pr = r / z * focal * half;
        let (cx, cy) = (half + sx * half, half - sy * half);
        let (x0, x1) = (
            (cx - pr).floor().max(0.0) as usize,
            ((cx + pr).ceil() as usize).min(n),
        );
        let (y0, y1) = (
            (cy - pr).floor().max(0.0) as usize,
            ((cy + pr).ceil() as usize).min(n),
        );
        for y in y0..y1 {
            for x in x0..x1 {
                let (dx, dy) = ((x as f64 + 0.5 - cx) / pr, (y as f64 + 0.5 - cy) / pr);
                let q = dx * dx + dy * dy;
                if q < 1.0 {
                    let d = z - r * (1.0 - q).sqrt();
                    let k = y * n + x;
                    depth[k] = depth[k].min(d);
                }
            }
        }
    }
    let body = DVec3::new(0.05, 0.04, 0.08);
    Ok(Image::from_fn(n, n, |x, y| {
        let (u, v) = (
            (x as f64 + 0.5 - half) / half,
            (half - (y as f64 + 0.5)) / half,
        );
        let d = (f * focal + right * u + up * v).normalize();
        let z = depth[y * n + x];
        let c = if z.is_finite() {
            // The splat's depth is along the view axis: back to the ray.
            fog.composite(eye, eye + d * (z / d.dot(f)), body)
        } else {
            fog.attenuation(eye, eye + d * 8.0 * extent)
                .apply(DVec3::ZERO)
        };
        c.as_vec3()
    })?)
}
