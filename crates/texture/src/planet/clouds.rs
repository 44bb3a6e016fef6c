//! The cloud shell: Musgrave's planetary clouds under a gentle circulation,
//! gathered into belts and wound into storms.

use glam::DVec3;

use crate::air::PlanetClouds;
use crate::error::Result;
use crate::footprint::{Footprint, smoothstep};
use crate::planet::params::CloudLayerParams;

/// A storm: a spiral of cloud round `centre`.
#[derive(Clone, Copy, Debug)]
struct Storm {
    centre: DVec3,
    /// Angular radius, radians.
    radius: f64,
    /// Rotation at the centre, radians (positive: anticlockwise seen from
    /// above, the northern hemisphere's cyclones).
    twist: f64,
}

/// The density of the cloud shell in each direction.
///
/// ```text
/// q       = storms(dir)                          each storm turns the sphere round its
///                                                centre by twist·(1 − r/R)²
/// x       = fBm(q + distortion·V(q)) + offset + belts·cos 6φ + storm_cover·(1 − r/R)²
/// density = smoothstep(0, softness, x)
/// ```
///
/// The fBm and its distortion are Musgrave's planetary clouds
/// ([`PlanetClouds`]; Musgrave 1993, §5.2; Musgrave 1998, "Distortion for
/// Cirrus Clouds and Global Circulation"). Their domain distortion must stay
/// gentle: the map `p ↦ p + s·V(p)` folds wherever `I + s·∇V` is singular,
/// and a fold stretches the fBm into long parallel streaks. With `s` near 1
/// (the shader's default) that happens over much of the sphere; at the
/// default 0.3 the map stays nearly invertible and the clouds keep their
/// billows. The large-scale order the distortion was meant to give comes
/// instead from the circulation: a cover that is highest in the
/// intertropical and mid-latitude belts and lowest under the subtropical
/// highs (`cos 6φ`), and storms whose rotation about their own centre is a
/// shear with no fold (each circle round the centre maps onto itself), in
/// the way Musgrave's `cyclone` twists its domain (Musgrave 1998, same
/// section). The smoothstep gives clouds soft edges a few hundredths of the
/// fBm's range wide.
#[derive(Debug)]
pub struct CloudShell {
    clouds: PlanetClouds,
    params: CloudLayerParams,
    storms: Vec<Storm>,
}

impl CloudShell {
    /// The shell for `params`.
    ///
    /// # Errors
    /// As [`CloudLayerParams::validate`].
    pub fn new(params: CloudLayerParams) -> Result<Self> {
        params.validate()?;
        let clouds = PlanetClouds::new(params.clouds)?;
        let seed = natura_core::Seed(params.clouds.seed).derive("storms");
        let storms = (0..params.storms)
            .map(|i| {
                let k = i64::from(i) * 4;
                let uniform = |j: i64| seed.uniform1(j);
                // Alternate hemispheres; latitudes of the storm tracks,
                // 12°–60°, every fourth a tropical cyclone nearer the equator.
                let north = i % 2 == 0;
                let lat = if i % 4 == 3 {
                    0.21 + 0.15 * uniform(k)
                } else {
                    0.6 + 0.45 * uniform(k)
                };
                let lat = if north { lat } else { -lat };
                let lon = std::f64::consts::TAU * uniform(k + 1);
                let size = 0.6 + 0.8 * uniform(k + 2);
                Storm {
                    centre: super::views::direction(lat, lon),
                    radius: params.storm_radius * size,
                    twist: if north {
                        params.storm_twist
                    } else {
                        -params.storm_twist
                    },
                }
            })
            .collect();
        Ok(Self {
            clouds,
            params,
            storms,
        })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &CloudLayerParams {
        &self.params
    }

    /// The density in `[0, 1]` in the unit direction `dir` for a footprint
    /// `fp` (units of the shell's radius).
    #[must_use]
    pub fn density(&self, dir: DVec3, fp: Footprint) -> f64 {
        let p = &self.params;
        let mut q = dir;
        let mut boost = 0.0;
        for s in &self.storms {
            let c = s.centre.dot(q).clamp(-1.0, 1.0);
            let r = c.acos();
            if r < s.radius {
                let f = 1.0 - r / s.radius;
                let (sin, cos) = (s.twist * f * f).sin_cos();
                // Rodrigues: q turned about the centre.
                q = q * cos + s.centre.cross(q) * sin + s.centre * (s.centre.dot(q) * (1.0 - cos));
                boost += p.storm_cover * f * f;
            }
        }
        let lat = dir.z.clamp(-1.0, 1.0).asin();
        let x = self.clouds.value(q, fp) + p.clouds.offset + p.belts * (6.0 * lat).cos() + boost;
        smoothstep(0.0, p.softness, x)
    }
}
