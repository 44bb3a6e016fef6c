//! "Driving parameters with functions" (Musgrave 2001, "Driving Function
//! Parameters with Functions"): any fractal parameter given by a field
//! evaluated at the same point.

use alloc::sync::Arc;
use glam::{DVec2, DVec3};

use crate::field::Field;
use crate::fractal::{GainConvention, Spectral};
use crate::{
    Fbm, HeteroTerrain, HeteroTerrainParams, HybridMultifractal, HybridParams, RidgedMultifractal,
    RidgedParams,
};

/// A parameter: a constant, or a field evaluated at the point.
#[derive(Clone)]
pub enum Param {
    /// The same value everywhere.
    Const(f64),
    /// The value of a field at the evaluation point.
    Field(Arc<dyn Field>),
}

impl core::fmt::Debug for Param {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Param::Const(v) => write!(f, "Const({v})"),
            Param::Field(_) => write!(f, "Field(..)"),
        }
    }
}

impl Param {
    fn at2(&self, p: DVec2) -> f64 {
        match self {
            Param::Const(v) => *v,
            Param::Field(g) => g.eval2(p),
        }
    }
    fn at3(&self, p: DVec3) -> f64 {
        match self {
            Param::Const(v) => *v,
            Param::Field(g) => g.eval3(p),
        }
    }
    fn bounds(&self) -> f64 {
        match self {
            Param::Const(v) => v.abs(),
            Param::Field(g) => g.bound(),
        }
    }
}

impl From<f64> for Param {
    fn from(v: f64) -> Self {
        Param::Const(v)
    }
}

/// Which fractal a [`Driven`] evaluates, with its extra parameters.
#[derive(Clone, Debug)]
pub enum DrivenKind {
    /// [`Fbm`].
    Fbm,
    /// [`HeteroTerrain`] with field-driven offset and threshold.
    HeteroTerrain {
        /// `offset`.
        offset: Param,
        /// `threshold` (> 0 where evaluated).
        threshold: Param,
    },
    /// [`HybridMultifractal`] with a field-driven offset.
    Hybrid {
        /// `offset`.
        offset: Param,
    },
    /// [`RidgedMultifractal`] with field-driven offset and gain.
    Ridged {
        /// `offset`.
        offset: Param,
        /// `gain`.
        gain: Param,
    },
}

/// A fractal whose `H`, octave count and kind-specific parameters are fields:
/// at each point the parameters are evaluated, validated and the fractal
/// evaluated with them. Plates 2.2-2.3 vary H across the picture (Musgrave
/// 1993, §2.3.2.2); MojoWorld drives "almost any parameter" this way (Musgrave
/// 2001, "Driving Function Parameters with Functions").
///
/// Constant parameters reproduce the plain fractal exactly. Where a driven
/// parameter is invalid at a point (NaN, octaves ≤ 0, …) the value is NaN.
/// Lacunarity and base frequency stay constant (a varying lacunarity would
/// shear the octave lattices apart).
#[derive(Clone, Debug)]
pub struct Driven<B> {
    basis: B,
    /// Spectral exponent H (per point).
    pub h: Param,
    /// Octave count (per point).
    pub octaves: Param,
    /// Constant lacunarity, frequency and gain convention.
    pub spectral: Spectral,
    /// The fractal and its extra parameters.
    pub kind: DrivenKind,
}

impl<B: Field + Clone> Driven<B> {
    /// A driven fractal of `kind` over `basis`; `spectral` supplies the
    /// constant lacunarity/frequency/convention and the default H and octaves.
    ///
    /// # Errors
    /// As [`Spectral::validate`](crate::Spectral::validate).
    pub fn new(basis: B, spectral: Spectral, kind: DrivenKind) -> crate::Result<Self> {
        spectral.validate()?;
        Ok(Self {
            basis,
            h: Param::Const(spectral.h),
            octaves: Param::Const(spectral.octaves),
            spectral,
            kind,
        })
    }

    /// With H given by `h`.
    #[must_use]
    pub fn with_h(mut self, h: impl Into<Param>) -> Self {
        self.h = h.into();
        self
    }

    /// With the octave count given by `octaves`.
    #[must_use]
    pub fn with_octaves(mut self, octaves: impl Into<Param>) -> Self {
        self.octaves = octaves.into();
        self
    }

    fn eval_with(&self, at: impl Fn(&Param) -> f64, eval: impl Fn(&dyn Field) -> f64) -> f64 {
        let s = Spectral {
            h: at(&self.h),
            octaves: at(&self.octaves),
            ..self.spectral
        };
        let b = &self.basis;
        let r: crate::Result<f64> = (|| {
            Ok(match &self.kind {
                DrivenKind::Fbm => eval(&Fbm::new(b, s)?),
                DrivenKind::HeteroTerrain { offset, threshold } => eval(&HeteroTerrain::new(
                    b,
                    HeteroTerrainParams {
                        spectral: s,
                        offset: at(offset),
                        threshold: at(threshold),
                    },
                )?),
                DrivenKind::Hybrid { offset } => eval(&HybridMultifractal::new(
                    b,
                    HybridParams {
                        spectral: s,
                        offset: at(offset),
                    },
                )?),
                DrivenKind::Ridged { offset, gain } => eval(&RidgedMultifractal::new(
                    b,
                    RidgedParams {
                        spectral: s,
                        offset: at(offset),
                        gain: at(gain),
                    },
                )?),
            })
        })();
        r.unwrap_or(f64::NAN)
    }

    /// The fractal with its parameters at their largest magnitudes, for bounds.
    fn worst(&self) -> f64 {
        let oct = self.octaves.bounds().clamp(f64::MIN_POSITIVE, 64.0);
        let h = match (&self.h, self.spectral.convention) {
            // Smallest H (largest amplitudes) the field can produce.
            (Param::Field(g), GainConvention::H | GainConvention::HalfBeta) => -g.bound(),
            (p, _) => p.bounds(),
        };
        let s = Spectral {
            h,
            octaves: oct,
            ..self.spectral
        };
        let b = &self.basis;
        let r: crate::Result<f64> = (|| {
            Ok(match &self.kind {
                DrivenKind::Fbm => Fbm::new(b, s)?.bound(),
                DrivenKind::HeteroTerrain { offset, .. } => HeteroTerrain::new(
                    b,
                    HeteroTerrainParams {
                        spectral: s,
                        offset: offset.bounds(),
                        threshold: 1.0,
                    },
                )?
                .bound(),
                DrivenKind::Hybrid { offset } => HybridMultifractal::new(
                    b,
                    HybridParams {
                        spectral: s,
                        offset: offset.bounds(),
                    },
                )?
                .bound(),
                DrivenKind::Ridged { offset, gain } => RidgedMultifractal::new(
                    b,
                    RidgedParams {
                        spectral: s,
                        offset: offset.bounds(),
                        gain: gain.bounds(),
                    },
                )?
                .bound(),
            })
        })();
        r.unwrap_or(f64::INFINITY)
    }
}

impl<B: Field + Clone> Field for Driven<B> {
    fn eval2(&self, p: DVec2) -> f64 {
        self.eval_with(|q| q.at2(p), |f| f.eval2(p))
    }
    fn eval3(&self, p: DVec3) -> f64 {
        self.eval_with(|q| q.at3(p), |f| f.eval3(p))
    }
    /// A bound from the parameters' extreme values (conservative).
    fn bound(&self) -> f64 {
        self.worst()
    }
    /// Infinite in general: the value depends on the parameter fields through
    /// the octave count and weights, which can change quickly.
    fn lipschitz2(&self) -> f64 {
        f64::INFINITY
    }
    fn lipschitz3(&self) -> f64 {
        f64::INFINITY
    }
}
