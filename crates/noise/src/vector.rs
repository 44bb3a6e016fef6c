//! Vector-valued noise (`DNoise`, `VecNoise`) and vector fBm (`VfBm`).

use glam::{DVec2, DVec3};

use crate::basis::Fade;
use crate::error::Result;
use crate::field::Field;
use crate::fractal::{Octaves, Spectral};
use crate::{Fbm, Perlin};

/// A deterministic vector field `R³ → R³` (and `R² → R²`), used for domain
/// distortion. Same contract as [`Field`]: pure, `Send + Sync`, NaN in → NaN out.
pub trait VectorField: Send + Sync {
    /// The vector at the 3-D point `p`.
    fn eval3(&self, p: DVec3) -> DVec3;
    /// The vector at the 2-D point `p`.
    fn eval2(&self, p: DVec2) -> DVec2;
    /// A bound on `|V(p)|` (Euclidean norm).
    fn bound(&self) -> f64;
    /// A Lipschitz constant: `|V(p) − V(q)| ≤ L·|p − q|`.
    fn lipschitz(&self) -> f64;
}

/// Fields with a bound on the norm of their Hessian, needed for the
/// Lipschitz constant of their gradient ([`DNoise`]).
pub trait Smooth: Field {
    /// A bound on the spectral norm of the Hessian (3-D; also valid in 2-D).
    fn hessian_bound(&self) -> f64;
}

impl Smooth for Perlin {
    /// A conservative analytic bound: with `f′ ≤ s1`, `|f″| ≤ s2` and 3-D edge
    /// gradients (`|g| = √2`, `|d| ≤ √3`), each Hessian entry is at most
    /// `4·s1²·√6 + 4·s1` off the diagonal and `2·s2·√6 + 4·s1` on it; the
    /// spectral norm is at most 3× the largest entry, times the normaliser.
    fn hessian_bound(&self) -> f64 {
        let (s1, s2) = match self.fade() {
            Fade::Quintic => (1.875, 5.773_502_7),
            Fade::Cubic => (1.5, 6.0),
        };
        let r6 = libm::sqrt(6.0);
        let entry = (4.0 * s1 * s1 * r6).max(2.0 * s2 * r6) + 4.0 * s1;
        3.0 * entry
            / crate::basis::perlin::PERLIN3_SUP_CUBIC.min(crate::basis::perlin::PERLIN3_SUP_QUINTIC)
    }
}

impl<B: Smooth> Smooth for Fbm<B> {
    /// `Σ w_k·f_k²·H_N`.
    fn hessian_bound(&self) -> f64 {
        let o = self.octaves();
        self.basis().hessian_bound()
            * (0..o.count())
                .map(|k| o.weight(k) * (o.frequency(k) * o.frequency(k)))
                .sum::<f64>()
    }
}

/// Perlin's `DNoise`: the gradient of a scalar field as a vector field
/// (Musgrave 1998, "A Variety of fBm"; the dissertation distorts with it,
/// Musgrave 1993, §2.3.2.4 and §5.2).
///
/// Its 2-D form is the 2-D gradient. [`bound`](VectorField::bound) is the
/// field's Lipschitz constant; [`lipschitz`](VectorField::lipschitz) its Hessian bound.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DNoise<B>(pub B);

impl<B: Smooth> VectorField for DNoise<B> {
    fn eval3(&self, p: DVec3) -> DVec3 {
        self.0.eval_grad3(p).1
    }
    fn eval2(&self, p: DVec2) -> DVec2 {
        self.0.eval_grad2(p).1
    }
    fn bound(&self) -> f64 {
        self.0.lipschitz3().max(self.0.lipschitz2())
    }
    fn lipschitz(&self) -> f64 {
        self.0.hessian_bound()
    }
}

/// Musgrave's `VecNoise`: three samples of a scalar field at misregistered
/// points, `(N(p), N(p + 3.33), N(p + 7.77))` with the offset added to every
/// coordinate (Musgrave 1998, "A Variety of fBm"). Not the same as [`DNoise`]
/// (Musgrave 1998, "A Variety of fBm"); the offsets keep the components from
/// sharing lattice zeros (Musgrave 1998, "A Variety of fBm").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VecNoise<B> {
    /// The scalar field sampled.
    pub field: B,
    /// The offsets of the second and third components (`3.33`, `7.77`).
    pub offsets: [f64; 2],
}

impl<B: Field> VecNoise<B> {
    /// `VecNoise` with the source's offsets 3.33 and 7.77.
    pub fn new(field: B) -> Self {
        Self {
            field,
            offsets: [3.33, 7.77],
        }
    }
}

impl<B: Field> VectorField for VecNoise<B> {
    fn eval3(&self, p: DVec3) -> DVec3 {
        let [a, b] = self.offsets;
        DVec3::new(
            self.field.eval3(p),
            self.field.eval3(p + DVec3::splat(a)),
            self.field.eval3(p + DVec3::splat(b)),
        )
    }
    fn eval2(&self, p: DVec2) -> DVec2 {
        let [a, _] = self.offsets;
        DVec2::new(self.field.eval2(p), self.field.eval2(p + DVec2::splat(a)))
    }
    fn bound(&self) -> f64 {
        libm::sqrt(3.0) * self.field.bound()
    }
    fn lipschitz(&self) -> f64 {
        libm::sqrt(3.0) * self.field.lipschitz()
    }
}

/// Vector fBm `Σ_k w_k·V(f_k·p)` (the C `VfBm` of Musgrave 1993, §5.8, and
/// the RenderMan `vfBm` of Musgrave 1998, "Distortion for Cirrus Clouds and
/// Global Circulation"): the spectral sum of a vector field, with the crate's
/// weights and fractional octaves. The sources pass a raw gain ω; use
/// [`GainConvention::Raw`](crate::GainConvention::Raw) to reproduce them
/// (the chapter's cloud shader passes its H in that gain slot).
#[derive(Clone, Debug, PartialEq)]
pub struct VectorFbm<V> {
    field: V,
    oct: Octaves,
}

impl<V: VectorField> VectorFbm<V> {
    /// Vector fBm of `field` (spectral parameters validated).
    ///
    /// # Errors
    /// As [`Spectral::validate`].
    pub fn new(field: V, spectral: Spectral) -> Result<Self> {
        Ok(Self {
            field,
            oct: spectral.octaves_table()?,
        })
    }

    /// The vector field summed.
    pub fn field(&self) -> &V {
        &self.field
    }

    /// The precomputed octave table.
    pub fn octaves(&self) -> &Octaves {
        &self.oct
    }
}

impl<V: VectorField> VectorField for VectorFbm<V> {
    fn eval3(&self, p: DVec3) -> DVec3 {
        let o = &self.oct;
        (0..o.count())
            .map(|k| self.field.eval3(p * o.frequency(k)) * o.weight(k))
            .sum()
    }
    fn eval2(&self, p: DVec2) -> DVec2 {
        let o = &self.oct;
        (0..o.count())
            .map(|k| self.field.eval2(p * o.frequency(k)) * o.weight(k))
            .sum()
    }
    fn bound(&self) -> f64 {
        self.field.bound() * self.oct.weight_sum()
    }
    fn lipschitz(&self) -> f64 {
        self.field.lipschitz() * self.oct.weighted_frequency_sum()
    }
}
