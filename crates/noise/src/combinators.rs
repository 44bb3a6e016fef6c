//! Combinators that reshape a field: ridged, absolute value, scaling of the
//! domain and of the range.

use glam::{DVec2, DVec3};

use crate::field::Field;
use crate::fractal::fbm::sign;
use crate::lattice_math::{Simd, run};

/// The ridged basis `1 − |N|` (Musgrave 1993, §2.3.2.5.3; Musgrave 2001,
/// "Perlin") (range `[1 − B, 1]`, so `[0, 1]` for a unit basis; exactly 1 on
/// gradient noise's lattice).
///
/// "Taking the absolute value … introduces discontinuities in the derivative,
/// which create ridges at all scales" (Musgrave 1993, §2.3.2.5.3). Its mean is
/// positive, which breaks MojoWorld's basis rule (C) (Musgrave 2001, "The Basis
/// Function"); fBm of it is "Slickrock",
/// [`HeteroTerrain`](crate::HeteroTerrain) over it is "Hell" (Musgrave 2001,
/// "Perlin"; Musgrave 1993, Plate 2.9).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Ridged<B>(pub B);

impl<B: Field> Field for Ridged<B> {
    fn eval2(&self, p: DVec2) -> f64 {
        1.0 - self.0.eval2(p).abs()
    }
    fn eval3(&self, p: DVec3) -> f64 {
        1.0 - self.0.eval3(p).abs()
    }
    fn eval_grad2(&self, p: DVec2) -> (f64, DVec2) {
        let (v, g) = self.0.eval_grad2(p);
        (1.0 - v.abs(), -g * sign(v))
    }
    fn eval_grad3(&self, p: DVec3) -> (f64, DVec3) {
        let (v, g) = self.0.eval_grad3(p);
        (1.0 - v.abs(), -g * sign(v))
    }
    fn bound(&self) -> f64 {
        1.0f64.max((1.0 - self.0.bound()).abs())
    }
    fn lipschitz2(&self) -> f64 {
        self.0.lipschitz2()
    }
    fn lipschitz3(&self) -> f64 {
        self.0.lipschitz3()
    }
    fn fill_row2_with(&self, simd: Simd, origin: DVec2, step: f64, out: &mut [f32]) {
        self.0.fill_row2_with(simd, origin, step, out);
        run(
            simd,
            #[inline(always)]
            || out.iter_mut().for_each(|v| *v = 1.0 - v.abs()),
        );
    }
    fn fill_row3_with(&self, simd: Simd, origin: DVec3, step: f64, out: &mut [f32]) {
        self.0.fill_row3_with(simd, origin, step, out);
        run(
            simd,
            #[inline(always)]
            || out.iter_mut().for_each(|v| *v = 1.0 - v.abs()),
        );
    }
}

/// `|N|`, the "turbulence" basis (range `[0, B]`; creased on the zero set of `N`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Abs<B>(pub B);

impl<B: Field> Field for Abs<B> {
    fn eval2(&self, p: DVec2) -> f64 {
        self.0.eval2(p).abs()
    }
    fn eval3(&self, p: DVec3) -> f64 {
        self.0.eval3(p).abs()
    }
    fn eval_grad2(&self, p: DVec2) -> (f64, DVec2) {
        let (v, g) = self.0.eval_grad2(p);
        (v.abs(), g * sign(v))
    }
    fn eval_grad3(&self, p: DVec3) -> (f64, DVec3) {
        let (v, g) = self.0.eval_grad3(p);
        (v.abs(), g * sign(v))
    }
    fn bound(&self) -> f64 {
        self.0.bound()
    }
    fn lipschitz2(&self) -> f64 {
        self.0.lipschitz2()
    }
    fn lipschitz3(&self) -> f64 {
        self.0.lipschitz3()
    }
    fn fill_row2_with(&self, simd: Simd, origin: DVec2, step: f64, out: &mut [f32]) {
        self.0.fill_row2_with(simd, origin, step, out);
        run(
            simd,
            #[inline(always)]
            || out.iter_mut().for_each(|v| *v = v.abs()),
        );
    }
    fn fill_row3_with(&self, simd: Simd, origin: DVec3, step: f64, out: &mut [f32]) {
        self.0.fill_row3_with(simd, origin, step, out);
        run(
            simd,
            #[inline(always)]
            || out.iter_mut().for_each(|v| *v = v.abs()),
        );
    }
}

/// `amplitude·N(frequency·p + offset) + bias`: rescales a field's domain and
/// range. An `offset` misregisters lattices (the sources' `+0.5`, `+3.33`,
/// Musgrave 1998, "A Variety of fBm").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform<B> {
    /// The field transformed.
    pub field: B,
    /// Multiplies the point (cycles per unit).
    pub frequency: f64,
    /// Added to the scaled point.
    pub offset: DVec3,
    /// Multiplies the value.
    pub amplitude: f64,
    /// Added to the value.
    pub bias: f64,
}

impl<B: Field> Transform<B> {
    /// The identity transform of `field`.
    pub fn new(field: B) -> Self {
        Self {
            field,
            frequency: 1.0,
            offset: DVec3::ZERO,
            amplitude: 1.0,
            bias: 0.0,
        }
    }

    /// With domain frequency `f`.
    #[must_use]
    pub fn with_frequency(mut self, f: f64) -> Self {
        self.frequency = f;
        self
    }

    /// With domain offset `o` (2-D evaluation uses its x and y).
    #[must_use]
    pub fn with_offset(mut self, o: DVec3) -> Self {
        self.offset = o;
        self
    }

    /// With value scale `a` and bias `b`.
    #[must_use]
    pub fn with_range(mut self, a: f64, b: f64) -> Self {
        self.amplitude = a;
        self.bias = b;
        self
    }
}

impl<B: Field> Field for Transform<B> {
    fn eval2(&self, p: DVec2) -> f64 {
        self.amplitude
            * self
                .field
                .eval2(p * self.frequency + self.offset.truncate())
            + self.bias
    }
    fn eval3(&self, p: DVec3) -> f64 {
        self.amplitude * self.field.eval3(p * self.frequency + self.offset) + self.bias
    }
    fn eval_grad2(&self, p: DVec2) -> (f64, DVec2) {
        let (v, g) = self
            .field
            .eval_grad2(p * self.frequency + self.offset.truncate());
        (
            self.amplitude * v + self.bias,
            g * (self.amplitude * self.frequency),
        )
    }
    fn eval_grad3(&self, p: DVec3) -> (f64, DVec3) {
        let (v, g) = self.field.eval_grad3(p * self.frequency + self.offset);
        (
            self.amplitude * v + self.bias,
            g * (self.amplitude * self.frequency),
        )
    }
    fn bound(&self) -> f64 {
        self.amplitude.abs() * self.field.bound() + self.bias.abs()
    }
    fn lipschitz2(&self) -> f64 {
        (self.amplitude * self.frequency).abs() * self.field.lipschitz2()
    }
    fn lipschitz3(&self) -> f64 {
        (self.amplitude * self.frequency).abs() * self.field.lipschitz3()
    }
    fn fill_row2_with(&self, simd: Simd, origin: DVec2, step: f64, out: &mut [f32]) {
        let o = origin * self.frequency + self.offset.truncate();
        self.field
            .fill_row2_with(simd, o, step * self.frequency, out);
        let (a, b) = (self.amplitude as f32, self.bias as f32);
        run(
            simd,
            #[inline(always)]
            || out.iter_mut().for_each(|v| *v = a * *v + b),
        );
    }
    fn fill_row3_with(&self, simd: Simd, origin: DVec3, step: f64, out: &mut [f32]) {
        let o = origin * self.frequency + self.offset;
        self.field
            .fill_row3_with(simd, o, step * self.frequency, out);
        let (a, b) = (self.amplitude as f32, self.bias as f32);
        run(
            simd,
            #[inline(always)]
            || out.iter_mut().for_each(|v| *v = a * *v + b),
        );
    }
}
