//! Plate 4.9 of `figures_musgrave`: a dispersing glass prism on a red and
//! white checkerboard, traced at Musgrave's 13 wavelengths (each with its
//! own index, Cauchy's law), totally reflected rays followed rather than
//! squelched, under the empirical rainbow.

use natura::atmos::Dir3;
use natura::atmos::optics::{Cauchy, RefractiveIndex, fresnel, reflect, refract};
use natura::atmos::rainbow::EmpiricalRainbow;
use natura::atmos::spectrum::{SpectralRgbTable, WavelengthSampler};
use natura::core::Image;
use natura::core::glam::{DVec2, DVec3};
use natura::noise::{Checkerboard, Field};

use crate::common::Exit;
use crate::landscape::supersampled;

type R<T> = Result<T, Exit>;

/// Dense flint glass by Cauchy's law, n(λ) = 1.7 + 14 000 nm²/λ² (about
/// SF10's; the source names no glass): strongly dispersive, as the plate.
pub(crate) fn flint_glass() -> R<Cauchy> {
    Ok(Cauchy::new(1.7, 14_000.0)?)
}

/// A convex body: points p with n·p ≤ d for every face (n, d).
struct Convex {
    faces: Vec<(DVec3, f64)>,
}

impl Convex {
    /// A prism lying along x from −l to l whose cross-section is the
    /// triangle `tri` in (y, z), corners anticlockwise.
    fn prism(tri: [DVec2; 3], l: f64) -> Self {
        let mut faces = vec![(DVec3::X, l), (-DVec3::X, l)];
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let e = b - a;
            let n = DVec3::new(0.0, e.y, -e.x).normalize();
            faces.push((n, n.y * a.x + n.z * a.y));
        }
        Self { faces }
    }

    /// The entry and exit distances along o + t·d and the faces' outward
    /// normals there, if the line crosses the body at t > 0.
    fn hit(&self, o: DVec3, d: DVec3) -> Option<((f64, DVec3), (f64, DVec3))> {
        let (mut t0, mut t1) = ((f64::NEG_INFINITY, DVec3::Z), (f64::INFINITY, DVec3::Z));
        for &(n, dist) in &self.faces {
            let (den, num) = (n.dot(d), dist - n.dot(o));
            if den.abs() < 1e-15 {
                if num < 0.0 {
                    return None;
                }
            } else if den < 0.0 {
                if num / den > t0.0 {
                    t0 = (num / den, n);
                }
            } else if num / den < t1.0 {
                t1 = (num / den, n);
            }
        }
        (t0.0 < t1.0 && t1.0 > 1e-9).then_some((t0, t1))
    }
}

/// The scene of Plate 4.9.
pub(crate) struct PrismScene {
    prism: Convex,
    glass: Cauchy,
    bow: EmpiricalRainbow,
    /// Towards the sun.
    sun: Dir3,
    /// The 13 wavelengths (nm) and their display rgb, summing to white.
    bands: Vec<(f64, DVec3)>,
}

/// The sky behind: the ray tracer's dark-blue background.
const BACKGROUND: DVec3 = DVec3::new(0.02, 0.04, 0.22);

impl PrismScene {
    /// The prism (equilateral, 1.6 m sides, 5 m long, resting on the floor),
    /// the sun low behind the viewer and the empirical bow's 13 colours,
    /// red outermost, from 40° over 6° (the plate's are not empirical and
    /// not given).
    pub(crate) fn new() -> R<Self> {
        let s = 1.6;
        let tri = [
            DVec2::new(-s / 2.0, 0.0),
            DVec2::new(s / 2.0, 0.0),
            DVec2::new(0.0, s * 3f64.sqrt() / 2.0),
        ];
        let table = SpectralRgbTable::linear_musgrave13();
        let sampler = WavelengthSampler::musgrave13();
        let bands = (0..13)
            .map(|k| (sampler.centre(k), table.samples()[k]))
            .collect();
        let (outer, width) = (40f64.to_radians(), 6f64.to_radians());
        Ok(Self {
            prism: Convex::prism(tri, 2.5),
            glass: flint_glass()?,
            bow: EmpiricalRainbow {
                bands: table.samples().iter().rev().copied().collect(),
                cos_start: outer.cos(),
                width_scale: 13.0 / ((outer - width).cos() - outer.cos()),
            },
            sun: Dir3::new(DVec3::new(0.25, -1.0, 0.32))?,
            bands,
        })
    }

    /// The floor's colour at p: red and white squares of 0.5 m.
    fn floor(p: DVec3) -> DVec3 {
        if Checkerboard.eval2(DVec2::new(p.x, p.y) * 2.0) > 0.0 {
            DVec3::new(0.85, 0.85, 0.82)
        } else {
            DVec3::new(0.75, 0.06, 0.04)
        }
    }

    /// The sky along d: the background and, in the bow's cone, its colour.
    fn sky(&self, d: DVec3) -> DVec3 {
        let bow = Dir3::new(d)
            .ok()
            .and_then(|v| self.bow.colour(v, self.sun, 0.0))
            .unwrap_or(DVec3::ZERO);
        // Each band's rgb is a thirteenth of white or so: shown at 6×.
        BACKGROUND + 6.0 * bow
    }

    /// The radiance along o + t·d at index `n` of the glass, `depth`
    /// bounces left; `inside` when the ray travels in the glass.
    fn trace(&self, o: DVec3, d: DVec3, n: f64, depth: u32, inside: bool) -> DVec3 {
        if depth == 0 {
            return DVec3::ZERO;
        }
        let glass = self.prism.hit(o, d);
        let t_floor = if d.z < 0.0 { -o.z / d.z } else { f64::INFINITY };
        let (t, normal, into) = match glass {
            Some(((t0, n0), _)) if !inside && t0 > 1e-9 && t0 < t_floor => (t0, n0, true),
            Some((_, (t1, n1))) if inside => (t1, n1, false),
            _ if inside => return DVec3::ZERO,
            _ if t_floor.is_finite() => return Self::floor(o + d * t_floor),
            _ => return self.sky(d),
        };
        let p = o + d * t;
        let (n1, n2) = if into { (1.0, n) } else { (n, 1.0) };
        let (Ok(dir), Ok(nrm)) = (Dir3::new(d), Dir3::new(normal)) else {
            return DVec3::ZERO;
        };
        let f = fresnel(n1, n2, -d.dot(normal));
        let r = reflect(dir, nrm).get();
        // The reflected ray stays on the side it came from.
        let mut c = self.trace(p + r * 1e-7, r, n, depth - 1, inside) * f.unpolarized();
        if let Some(tr) = refract(dir, nrm, n1 / n2) {
            let tr = tr.get();
            c += self.trace(p + tr * 1e-7, tr, n, depth - 1, !inside) * (1.0 - f.unpolarized());
        }
        c
    }

    /// The pixel's colour along o + t·d: one trace where the ray misses the
    /// prism, else the 13 wavelengths' traces weighted by their rgb.
    pub(crate) fn radiance(&self, o: DVec3, d: DVec3) -> DVec3 {
        if self.prism.hit(o, d).is_none() {
            return self.trace(o, d, 1.0, 8, false);
        }
        self.bands
            .iter()
            .map(|&(l, rgb)| rgb * self.trace(o, d, self.glass.ior(l), 8, false))
            .sum()
    }
}

/// Pl. 4.9: the prism from the front, a little above, the bow in the sky.
pub(crate) fn prism_picture(quick: bool) -> R<Image> {
    let scene = PrismScene::new()?;
    let (w, h) = if quick { (240u32, 160u32) } else { (960, 640) };
    let eye = DVec3::new(-3.6, -5.6, 2.6);
    let target = DVec3::new(0.0, 0.0, 0.7);
    let f = (target - eye).normalize();
    let right = f.cross(DVec3::Z).normalize();
    let up = right.cross(f);
    let tan = (50f64.to_radians() / 2.0).tan();
    // 3 × 3 rays a pixel, resolved by the camera's pixel filter: the
    // checkerboard's squares grow smaller than a pixel toward the horizon.
    let ss = if quick { 1 } else { 3 };
    supersampled(w, h, ss, |px, py| {
        let u = f64::from(px) / f64::from(w) * 2.0 - 1.0;
        let v = 1.0 - f64::from(py) / f64::from(h) * 2.0;
        let d = (f + right * (u * tan * f64::from(w) / f64::from(h)) + up * (v * tan)).normalize();
        scene.radiance(eye, d).as_vec3()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_13_bands_sum_to_white_so_undispersed_light_keeps_its_colour() {
        // Musgrave 1993, §4.2.4.2.1: without jitter the samples sum to white.
        let s = PrismScene::new().unwrap();
        let sum: DVec3 = s.bands.iter().map(|b| b.1).sum();
        assert!((sum - DVec3::ONE).abs().max_element() < 1e-12, "{sum}");
        // A ray that misses the prism sees the floor's own colour.
        let (o, d) = (
            DVec3::new(10.0, -5.0, 1.0),
            DVec3::new(0.0, 0.3, -1.0).normalize(),
        );
        assert!(s.prism.hit(o, d).is_none());
        assert_eq!(
            s.radiance(o, d),
            PrismScene::floor(o + d * (1.0 / d.z.abs()))
        );
    }

    #[test]
    fn the_empirical_bow_is_red_outside_and_violet_inside() {
        let s = PrismScene::new().unwrap();
        let anti = s.sun.reversed().get();
        let side = anti.cross(DVec3::Z).normalize();
        let at = |deg: f64| {
            let a = deg.to_radians();
            Dir3::new(anti * a.cos() + side * a.sin()).unwrap()
        };
        assert_eq!(s.bow.band(at(39.9), s.sun, 0.0), Some(0));
        assert_eq!(s.bow.band(at(34.1), s.sun, 0.0), Some(12));
        assert!(s.bow.band(at(40.1), s.sun, 0.0).is_none());
        let (outer, inner) = (s.bow.bands[0], s.bow.bands[12]);
        assert!(outer.x > outer.y && outer.x > outer.z, "{outer}");
        assert!(inner.z > inner.y, "{inner}");
    }

    #[test]
    fn the_glass_bends_violet_more_than_red() {
        // Minimum deviation of a 60° prism, 2·asin(n/2) − 60°.
        let g = flint_glass().unwrap();
        let dev = |l: f64| 2.0 * (g.ior(l) / 2.0).asin().to_degrees() - 60.0;
        assert!(
            dev(400.0) - dev(700.0) > 3.0,
            "{} {}",
            dev(400.0),
            dev(700.0)
        );
    }
}
