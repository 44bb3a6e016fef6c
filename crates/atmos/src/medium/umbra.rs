//! The atmospheric umbra: the planet's shadow cylinder switches the
//! atmosphere to night parameters (Musgrave 1993, §4.1.6.5, Musgrave 1993, plate 4.5).

use glam::DVec3;

use super::{Attenuation, Medium};
use crate::Dir3;
use crate::error::{Result, finite3, positive};

/// A day medium and a night medium, switched on the planet's umbra: the
/// half-infinite cylinder of radius `R + ε` behind the planet, with its axis
/// through the centre along the light direction (Musgrave 1993, §4.1.6.5).
///
/// Segments are split exactly where they cross the cylinder, and the pieces
/// are composited front to back, so an object in the shadow is seen through
/// the night atmosphere and a distant one through day, night and day again.
///
/// **Pitfall** (Musgrave 1993, §4.1.6.5, Plate 4.5): the cylinder radius must exceed the planet
/// radius by more than the renderer's ray-offset epsilon, or rays re-spawned at
/// the cylinder start inside the planet and draw a bright terminator line;
/// [`Umbra::new`] therefore takes `epsilon > 0` explicitly. The penumbra is
/// ignored, as in the source.
#[derive(Clone, Copy, Debug)]
pub struct Umbra<D, N> {
    day: D,
    night: N,
    centre: DVec3,
    planet_radius: f64,
    radius: f64,
    to_light: Dir3,
}

impl<D: Medium, N: Medium> Umbra<D, N> {
    /// The umbra of a planet at `centre` of radius `planet_radius`, lit from
    /// `to_light` (towards the light source), with cylinder radius
    /// `planet_radius + epsilon`.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) for a non-finite centre or a non-positive radius or
    /// `epsilon`.
    pub fn new(
        day: D,
        night: N,
        centre: DVec3,
        planet_radius: f64,
        epsilon: f64,
        to_light: Dir3,
    ) -> Result<Self> {
        finite3("centre", centre)?;
        positive("planet_radius", planet_radius)?;
        positive("epsilon", epsilon)?;
        Ok(Self {
            day,
            night,
            centre,
            planet_radius,
            radius: planet_radius + epsilon,
            to_light,
        })
    }

    /// Whether `p` lies in the umbra (night side, inside the cylinder).
    #[must_use]
    pub fn in_shadow(&self, p: DVec3) -> bool {
        let q = p - self.centre;
        let l = self.to_light.get();
        let s = q.dot(l);
        s < 0.0 && (q - s * l).length_squared() < self.radius * self.radius
    }

    /// Distance to the (opaque) planet along the ray, if it is hit.
    fn ground_hit(&self, origin: DVec3, v: DVec3) -> Option<f64> {
        let q = origin - self.centre;
        let c = q.length_squared() - self.planet_radius * self.planet_radius;
        let b = q.dot(v);
        if c < -1e-12 * self.planet_radius * self.planet_radius {
            return Some(0.0);
        }
        let c = c.max(0.0);
        let disc = b * b - c;
        (b < 0.0 && disc >= 0.0).then(|| c / (-b + disc.sqrt()))
    }

    /// The parameter interval `[t0, t1] ⊂ [0, t_max]` of `a + t·v` inside the umbra.
    fn shadow_interval(&self, a: DVec3, v: DVec3, t_max: f64) -> Option<(f64, f64)> {
        let l = self.to_light.get();
        let q = a - self.centre;
        let (mut t0, mut t1) = (0.0f64, t_max);
        // Half-space (q + t v)·l < 0.
        let (sq, sv) = (q.dot(l), v.dot(l));
        if sv == 0.0 {
            if sq >= 0.0 {
                return None;
            }
        } else {
            let t = -sq / sv;
            if sv > 0.0 {
                t1 = t1.min(t);
            } else {
                t0 = t0.max(t);
            }
        }
        // Infinite cylinder |perp(q + t v)|² < ρ².
        let wq = q - sq * l;
        let wv = v - sv * l;
        let aa = wv.length_squared();
        let bb = wq.dot(wv);
        let cc = wq.length_squared() - self.radius * self.radius;
        if aa == 0.0 {
            if cc >= 0.0 {
                return None;
            }
        } else {
            let disc = bb * bb - aa * cc;
            if disc <= 0.0 {
                return None;
            }
            let sq_d = disc.sqrt();
            // Stable roots of aa t² + 2 bb t + cc.
            let qq = -(bb + bb.signum() * sq_d);
            let (r1, r2) = if qq == 0.0 {
                (-sq_d / aa, sq_d / aa)
            } else {
                let x = qq / aa;
                let y = cc / qq;
                (x.min(y), x.max(y))
            };
            t0 = t0.max(r1);
            t1 = t1.min(r2);
        }
        (t0 < t1).then_some((t0, t1))
    }
}

impl<D: Medium, N: Medium> Medium for Umbra<D, N> {
    fn optical_depth(&self, a: DVec3, b: DVec3) -> DVec3 {
        let v = b - a;
        match self.shadow_interval(a, v, 1.0) {
            None => self.day.optical_depth(a, b),
            Some((t0, t1)) => {
                let (p0, p1) = (a + v * t0, a + v * t1);
                self.day.optical_depth(a, p0)
                    + self.night.optical_depth(p0, p1)
                    + self.day.optical_depth(p1, b)
            }
        }
    }

    fn optical_depth_to_infinity(&self, origin: DVec3, dir: Dir3) -> DVec3 {
        let v = dir.get();
        if let Some(t) = self.ground_hit(origin, v) {
            return self.optical_depth(origin, origin + v * t);
        }
        match self.shadow_interval(origin, v, f64::INFINITY) {
            None => self.day.optical_depth_to_infinity(origin, dir),
            Some((t0, t1)) => {
                let p0 = origin + v * t0;
                let near = self.day.optical_depth(origin, p0);
                if t1.is_finite() {
                    let p1 = origin + v * t1;
                    near + self.night.optical_depth(p0, p1)
                        + self.day.optical_depth_to_infinity(p1, dir)
                } else {
                    near + self.night.optical_depth_to_infinity(p0, dir)
                }
            }
        }
    }

    fn attenuation(&self, a: DVec3, b: DVec3) -> Attenuation {
        let v = b - a;
        match self.shadow_interval(a, v, 1.0) {
            None => self.day.attenuation(a, b),
            Some((t0, t1)) => {
                let (p0, p1) = (a + v * t0, a + v * t1);
                self.day
                    .attenuation(a, p0)
                    .then(self.night.attenuation(p0, p1))
                    .then(self.day.attenuation(p1, b))
            }
        }
    }

    fn attenuation_to_infinity(&self, origin: DVec3, dir: Dir3) -> Attenuation {
        let v = dir.get();
        if let Some(t) = self.ground_hit(origin, v) {
            return self.attenuation(origin, origin + v * t);
        }
        match self.shadow_interval(origin, v, f64::INFINITY) {
            None => self.day.attenuation_to_infinity(origin, dir),
            Some((t0, t1)) => {
                let p0 = origin + v * t0;
                let near = self.day.attenuation(origin, p0);
                if t1.is_finite() {
                    let p1 = origin + v * t1;
                    near.then(self.night.attenuation(p0, p1))
                        .then(self.day.attenuation_to_infinity(p1, dir))
                } else {
                    near.then(self.night.attenuation_to_infinity(p0, dir))
                }
            }
        }
    }
}
