//! Sphere tracing the displaced planet, and the brute-force march it is
//! checked against.

use glam::DVec3;

use super::{Planet, Surface};
use crate::error::{Result, TextureError, in_range, positive};
use crate::footprint::Footprint;
use crate::planet::height::Relief;
use crate::view::sphere_hits;

/// How closely [`Planet::trace`] approaches the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct TraceSettings {
    /// A ray stops when its gap to the surface is below this fraction of its
    /// footprint (0.25: a quarter pixel).
    pub epsilon: f64,
    /// …or below this many metres, whichever is larger (10⁻⁴).
    pub min_epsilon_m: f64,
    /// Steps after which a ray that has not converged is taken as a hit at
    /// its current point (a ray grazing the surface for a long way; 4096;
    /// at most [`MAX_TRACE_STEPS`]).
    pub max_steps: u32,
    /// Rays a pixel takes along each axis of [`Planet::render`]'s picture
    /// (2: four rays on a regular grid), resolved by the camera's pixel
    /// filter (natura-core's `PixelFilter::camera`, a Gaussian of σ = 0.5
    /// pixel); every ray keeps the pixel's footprint. 1 to 16.
    pub supersample: u32,
}

impl Default for TraceSettings {
    fn default() -> Self {
        Self {
            epsilon: 0.25,
            min_epsilon_m: 1e-4,
            max_steps: 4096,
            supersample: 2,
        }
    }
}

impl TraceSettings {
    /// Checks every field on its own; [`Planet::render`] also checks
    /// `min_epsilon_m` against the scene ([`TraceSettings::validate_for`]).
    ///
    /// # Errors
    /// [`TextureError`] naming the bad field.
    pub fn validate(&self) -> Result<()> {
        in_range("epsilon", self.epsilon, 0.0, 1e6, "must be in [0, 10⁶]")?;
        positive("min_epsilon_m", self.min_epsilon_m)?;
        if !(1..=MAX_TRACE_STEPS).contains(&self.max_steps) {
            return Err(crate::error::invalid(
                "max_steps",
                self.max_steps,
                "must be in 1..=1048576",
            ));
        }
        if !(1..=natura_core::preview::MAX_SUPERSAMPLE).contains(&self.supersample) {
            return Err(crate::error::invalid(
                "supersample",
                self.supersample,
                "must be in 1..=16",
            ));
        }
        Ok(())
    }

    /// [`validate`](Self::validate), and whether the sphere tracer can
    /// resolve `min_epsilon_m` on `planet` seen from `eye`: a gap is
    /// computed from points as far from the centre as the eye or the
    /// outermost surface, to `f64`'s precision of that distance, so the
    /// tolerance must be at least that distance × [`EPSILON_RESOLUTION`]
    /// (64 units in the last place). A finer tolerance could never be met,
    /// and every ray would spend `max_steps` steps. With both bounds, a
    /// ray's work is at most `max_steps` sphere-tracing steps plus 512 of
    /// its shadow ray.
    ///
    /// # Errors
    /// As [`validate`](Self::validate); [`TextureError`]
    /// naming `min_epsilon_m` if it is below the resolution (a smooth planet,
    /// which is not sphere traced, has no such bound).
    pub fn validate_for(&self, planet: &Planet, eye: DVec3) -> Result<()> {
        self.validate()?;
        if planet.relief().is_some() {
            let floor = (eye.length() + planet.max_radius()) * EPSILON_RESOLUTION;
            if floor.is_nan() || self.min_epsilon_m < floor {
                return Err(TextureError::InvalidParameter {
                    name: "min_epsilon_m",
                    value: format!(
                        "{:e} (the planet's outermost radius {} m and the eye {} m from its \
                         centre resolve {floor:e} m)",
                        self.min_epsilon_m,
                        planet.max_radius(),
                        eye.length()
                    ),
                    reason: "must be at least (eye distance + outermost radius) × 2⁻⁴⁶, the \
                             precision to which a gap can be computed",
                });
            }
        }
        Ok(())
    }
}

/// Most sphere-tracing steps per ray ([`TraceSettings::max_steps`]): 2²⁰.
pub const MAX_TRACE_STEPS: u32 = 1 << 20;

/// The finest tolerance per metre of distance from the planet's centre
/// that [`TraceSettings::validate_for`] accepts: 2⁻⁴⁶, 64 units in the last
/// place of an `f64`.
pub const EPSILON_RESOLUTION: f64 = 1.0 / (1u64 << 46) as f64;

/// Where a ray meets the planet's surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    /// Distance along the (unit) ray, metres.
    pub t: f64,
    /// The world point.
    pub point: DVec3,
    /// The footprint there, in texture units of the relief (or of the
    /// unit sphere for a smooth planet).
    pub footprint: Footprint,
    /// The footprint there, metres.
    pub footprint_m: f64,
    /// Sphere-tracing steps taken.
    pub steps: u32,
}

impl Planet {
    /// The footprint, in metres, of a ray at distance `t` with pixel angle `alpha`.
    pub(crate) fn footprint_m(t: f64, alpha: f64) -> f64 {
        t.max(0.0) * alpha
    }

    /// The signed gap `|p| − R − h(p/|p|)` at distance `t` along the ray
    /// from `o` in unit direction `d` (footprint `t·alpha`), metres.
    #[must_use]
    pub fn gap(&self, o: DVec3, d: DVec3, t: f64, alpha: f64) -> f64 {
        let p = o + d * t;
        let r = p.length();
        match &self.surface {
            Surface::Terrain(relief) => {
                let fp = relief.footprint(Self::footprint_m(t, alpha));
                r - self.radius() - relief.height(p / r, fp)
            }
            Surface::Textured(_) => r - self.radius(),
        }
    }

    /// The parameter range `[t_start, t_end]` a ray spends in the shell
    /// holding the surface, and whether `t_end` is where it meets the
    /// sea-level sphere (so the surface is crossed by then).
    fn shell(&self, o: DVec3, d: DVec3) -> Option<(f64, f64, bool)> {
        let (t0, t1) = sphere_hits(o, d, self.max_radius())?;
        if t1 <= 0.0 {
            return None;
        }
        let start = t0.max(0.0);
        match sphere_hits(o, d, self.radius()) {
            Some((a, _)) if a >= start => Some((start, a.min(t1), true)),
            Some((_, b)) if b >= start => Some((start, start, true)),
            _ => Some((start, t1, false)),
        }
    }

    /// Sphere traces (Hart 1996) the ray from `o` in unit direction `d` whose
    /// pixels subtend `pixel_angle` radians: the first point where it meets
    /// the surface, or `None`.
    ///
    /// Each step advances by the gap to the surface divided by a Lipschitz
    /// bound of the gap along the ray, `√(1 + L_h²) + |∂h/∂v|/(t·ln λ)`
    /// (`L_h` the relief's slope bound for the octaves visible at the
    /// current footprint, the second term for the octaves fading out as the
    /// footprint grows along the ray), so no step can cross the surface; a
    /// ray stops when the gap falls below `epsilon` of its footprint. The
    /// surface is the band-limited one the ray's footprint shows at each
    /// distance: detail is summed only down to the pixel.
    #[must_use]
    pub fn trace(
        &self,
        o: DVec3,
        d: DVec3,
        pixel_angle: f64,
        settings: &TraceSettings,
    ) -> Option<SurfaceHit> {
        let relief = match &self.surface {
            Surface::Textured(_) => {
                let (t0, _) = sphere_hits(o, d, self.radius())?;
                return (t0 >= 0.0).then(|| {
                    let m = Self::footprint_m(t0, pixel_angle);
                    SurfaceHit {
                        t: t0,
                        point: o + d * t0,
                        footprint: Footprint::new(m / self.radius()).unwrap_or(Footprint::POINT),
                        footprint_m: m,
                        steps: 0,
                    }
                });
            }
            Surface::Terrain(r) => r,
        };
        let (t, t_end, crosses) = self.shell(o, d)?;
        let lod = |t: f64| {
            let m = Self::footprint_m(t, pixel_angle);
            (relief.footprint(m), m, pixel_angle)
        };
        let eps = |m: f64| (settings.epsilon * m).max(settings.min_epsilon_m);
        let mut no_penumbra = None;
        let (t, steps, met) = self.march(
            relief,
            o,
            d,
            (t, t_end),
            lod,
            eps,
            settings.max_steps,
            &mut no_penumbra,
        );
        (met || crosses).then(|| {
            let (fp, m, _) = lod(t);
            hit(o, d, t, fp, m, steps)
        })
    }

    /// The reference for [`trace`](Self::trace): marches the same ray
    /// through the shell in fixed steps of `step_m` metres, and bisects the
    /// first step over which the gap changes sign (60 halvings). Slow and
    /// obviously right, for tests.
    #[must_use]
    pub fn trace_brute(&self, o: DVec3, d: DVec3, pixel_angle: f64, step_m: f64) -> Option<f64> {
        if let Surface::Textured(_) = &self.surface {
            let (t0, _) = sphere_hits(o, d, self.radius())?;
            return (t0 >= 0.0).then_some(t0);
        }
        let (start, t_end, crosses) = self.shell(o, d)?;
        let g = |t: f64| self.gap(o, d, t, pixel_angle);
        let mut a = start;
        if g(a) <= 0.0 {
            return Some(a);
        }
        while a < t_end {
            let b = (a + step_m).min(t_end);
            if g(b) <= 0.0 {
                let (mut lo, mut hi) = (a, b);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if g(mid) > 0.0 {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                return Some(hi);
            }
            a = b;
        }
        // The sea-level sphere lies on or below the surface, so a ray that
        // reaches it has met the surface by then (rounding aside).
        crosses.then_some(t_end)
    }

    /// How much of the sun the terrain leaves visible from the surface
    /// point `p` (normal `n`, footprint `footprint_m` metres), marching
    /// towards `to_sun` with tolerance `eps` metres: 0 where the ray meets
    /// the terrain, else `smoothstep(0, 1, min gap/(footprint + t·θ_sun))`
    /// over the march beyond four footprints — a penumbra as wide as the
    /// sun's disc seen past the ridge that nearly blocks it (and no less
    /// than the pixel), so a shadow's edge is as soft as the sun makes it
    /// and a pixel the shadow ray barely escapes is not lit as brightly as
    /// open ground.
    ///
    /// The shadow ray's footprint grows with distance by the sun's angular
    /// radius: detail smaller than the penumbra it would cast is not summed.
    pub(crate) fn terrain_visibility(
        &self,
        p: DVec3,
        n: DVec3,
        to_sun: DVec3,
        footprint_m: f64,
        eps: f64,
    ) -> f64 {
        let Surface::Terrain(relief) = &self.surface else {
            return 1.0;
        };
        let o = p + n * (2.0 * eps);
        let Some((_, t_end)) = sphere_hits(o, to_sun, self.max_radius()) else {
            return 1.0;
        };
        let cone = self.params.light.sun_radius;
        let lod = |t: f64| {
            let m = footprint_m + t.max(0.0) * cone;
            (relief.footprint(m), m, cone)
        };
        let mut closest = Some((f64::INFINITY, 4.0 * footprint_m));
        let (_, _, met) = self.march(
            relief,
            o,
            to_sun,
            (0.0, t_end),
            lod,
            |_| 0.5 * eps,
            512,
            &mut closest,
        );
        match closest {
            Some((c, _)) if !met => crate::footprint::smoothstep(0.0, 1.0, c),
            _ => 0.0,
        }
    }

    /// Sphere traces the ray `o + t·d` for `t ∈ [t, t_end]` against the
    /// relief whose footprint at distance `t` is `lod(t) = (texture
    /// footprint, metres, metres per metre of t)`, stopping when the gap
    /// falls below `eps(metres)`. Returns where it stopped, the steps taken
    /// and whether it met the surface (a ray that runs out of steps counts
    /// as meeting it).
    ///
    /// Each step is the gap divided by a Lipschitz bound of the gap along
    /// the ray, `√(1 + L_h²) + |∂h/∂v|·|dv/dt|`: `L_h` the relief's slope
    /// bound for the octaves summed, the second term for the octaves fading
    /// out as the footprint grows along the ray. Far above the surface the
    /// ray steps against upper envelopes — the first few octaves plus a
    /// bound of the rest, whose smaller slope allows longer steps — summing
    /// more octaves only once it is within an envelope's slack of the
    /// surface. Every envelope lies above the surface, so every step is safe.
    /// Over the sea the surface is the flat sphere `R` for as far as the
    /// chaos cannot climb to sea level, so a ray reaching it within that
    /// distance meets it exactly. With `closest = Some((c, from))` it also
    /// keeps in `c` the least ratio of the gap (or a lower bound of it) to
    /// the footprint width over the steps from `t = from` on.
    #[allow(clippy::too_many_arguments)]
    fn march(
        &self,
        relief: &Relief,
        o: DVec3,
        d: DVec3,
        (mut t, t_end): (f64, f64),
        lod: impl Fn(f64) -> (Footprint, f64, f64),
        eps: impl Fn(f64) -> f64,
        max_steps: u32,
        closest: &mut Option<(f64, f64)>,
    ) -> (f64, u32, bool) {
        let radius = self.radius();
        let metres = relief.metres_per_chaos();
        let mut steps = 0u32;
        loop {
            let p = o + d * t;
            let r = p.length();
            let dir = p / r;
            let (fp, width, growth) = lod(t);
            let mut probe = relief.probe(dir, fp);
            let v = probe.visible;
            let tol = eps(width);
            let mut step = None;
            for &m in &ENVELOPES {
                if m as f64 > v.floor() {
                    break;
                }
                let b = probe.partial(m);
                let tail = relief.bump_bound(v) - relief.bump_bound(m as f64);
                let gap = r - radius - relief.height_of(b + tail);
                if gap > (metres * tail).max(tol) {
                    note(closest, t, gap, width);
                    let l = relief.lipschitz_visible(m as f64);
                    step = Some(gap / (1.0 + l * l).sqrt());
                    break;
                }
            }
            let step = match step {
                Some(s) => s,
                None => {
                    let b = probe.full();
                    let gap = r - radius - relief.height_of(b);
                    if gap <= tol || steps >= max_steps {
                        return (t, steps, true);
                    }
                    note(closest, t, gap, width);
                    let l = relief.lipschitz_visible(v);
                    let band = if width > 0.0 {
                        relief.band_slope(v) * growth / (width * relief.ln_lacunarity())
                    } else {
                        0.0
                    };
                    let safe = gap / ((1.0 + l * l).sqrt() + band);
                    let deficit = -relief.chaos_above_sea(b);
                    if deficit > 0.0 {
                        let rate = l + band;
                        let reach = if rate > 0.0 {
                            deficit * metres / rate
                        } else {
                            f64::INFINITY
                        };
                        if let Some((a, _)) = sphere_hits(p, d, radius)
                            && a >= 0.0
                            && a <= reach
                        {
                            return (t + a, steps + 1, true);
                        }
                        safe.max(reach)
                    } else {
                        safe
                    }
                }
            };
            t += step;
            steps += 1;
            if t >= t_end {
                return (t_end, steps, false);
            }
            if steps >= max_steps {
                return (t, steps, true);
            }
        }
    }
}

/// Keeps in `closest = Some((c, from))` the least `gap/width` seen at
/// `t ≥ from`.
fn note(closest: &mut Option<(f64, f64)>, t: f64, gap: f64, width: f64) {
    if let Some((c, from)) = closest
        && t >= *from
        && width > 0.0
    {
        *c = c.min(gap / width);
    }
}

/// Octave counts of the envelopes [`Planet::march`] steps against before it
/// sums every visible octave.
const ENVELOPES: [usize; 5] = [3, 7, 12, 17, 22];

/// The hit at distance `t` along the ray.
fn hit(
    o: DVec3,
    d: DVec3,
    t: f64,
    footprint: Footprint,
    footprint_m: f64,
    steps: u32,
) -> SurfaceHit {
    SurfaceHit {
        t,
        point: o + d * t,
        footprint,
        footprint_m,
        steps,
    }
}
