//! Shared generators for the tracer tests: small height fields of several
//! kinds and rays of every awkward sort.
#![allow(dead_code)]

use glam::Vec3;
use natura_core::{HeightField, Seed};
use natura_trace::Ray;
use proptest::prelude::*;

/// The kinds of field the oracle tests draw from.
#[derive(Clone, Copy, Debug)]
pub enum Kind {
    Uniform,
    Flat,
    Spiky,
    Plateau,
    Smooth,
    Plane,
}

pub fn field(kind: Kind, nx: usize, ny: usize, cell: f32, seed: u64) -> HeightField {
    let s = Seed(seed);
    HeightField::from_fn(nx, ny, cell, |i, j| {
        let (ii, jj) = (i as i64, j as i64);
        let u = s.uniform2(ii, jj) as f32;
        match kind {
            Kind::Uniform => 10.0 * u,
            Kind::Flat => 3.0,
            Kind::Spiky => {
                if u > 0.85 {
                    20.0 * s.uniform2(jj, ii) as f32
                } else {
                    0.0
                }
            }
            Kind::Plateau => (4.0 * u).floor() * 2.5,
            Kind::Smooth => 5.0 * ((i as f32 * 0.4).sin() + (j as f32 * 0.3).cos()) + 0.5 * u,
            Kind::Plane => 0.7 * i as f32 - 0.4 * j as f32 + 2.0,
        }
    })
    .unwrap()
}

pub fn kind() -> impl Strategy<Value = Kind> {
    prop_oneof![
        3 => Just(Kind::Uniform),
        1 => Just(Kind::Flat),
        2 => Just(Kind::Spiky),
        2 => Just(Kind::Plateau),
        2 => Just(Kind::Smooth),
        1 => Just(Kind::Plane),
    ]
}

pub fn any_field() -> impl Strategy<Value = HeightField> {
    (
        kind(),
        2usize..24,
        2usize..24,
        prop_oneof![Just(1.0f32), Just(0.5), Just(2.0), Just(3.7)],
        any::<u64>(),
    )
        .prop_map(|(k, nx, ny, c, s)| field(k, nx, ny, c, s))
}

/// A ray relative to a field, described in grid units so that special cases
/// (grid lines, corners) are exact, then scaled to world space.
pub fn ray_for(hf: &HeightField) -> impl Strategy<Value = Ray> + use<> {
    let (nx, ny) = (hf.nx() as f32, hf.ny() as f32);
    let (lo, hi) = hf.min_max();
    let cell = hf.cell_size();
    let dir = prop_oneof![
        // Random, any direction.
        4 => (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0).prop_map(|(x, y, z)| Vec3::new(x, y, z)),
        // Axis-parallel in x or y, random dz.
        1 => (prop_oneof![Just(1.0f32), Just(-1.0)], -1.0f32..1.0).prop_map(|(s, z)| Vec3::new(s, 0.0, z)),
        1 => (prop_oneof![Just(1.0f32), Just(-1.0)], -1.0f32..1.0).prop_map(|(s, z)| Vec3::new(0.0, s, z)),
        // Vertical, up or down.
        1 => prop_oneof![Just(Vec3::Z), Just(Vec3::NEG_Z)],
        // Exactly diagonal (through cell corners when started on one).
        1 => (prop_oneof![Just(1.0f32), Just(-1.0)], prop_oneof![Just(1.0f32), Just(-1.0)], -0.5f32..0.5)
            .prop_map(|(a, b, z)| Vec3::new(a, b, z)),
        // Grazing: nearly horizontal.
        2 => (-1.0f32..1.0, -1.0f32..1.0, -0.02f32..0.02).prop_map(|(x, y, z)| Vec3::new(x, y, z)),
        // Horizontal.
        1 => (-1.0f32..1.0, -1.0f32..1.0).prop_map(|(x, y)| Vec3::new(x, y, 0.0)),
    ];
    let origin = prop_oneof![
        // Anywhere in and around the box, above and below the surface.
        4 => (-0.5f32..1.5, -0.5f32..1.5, -0.3f32..1.3).prop_map(move |(a, b, c)| {
            Vec3::new(a * (nx - 1.0), b * (ny - 1.0), lo + c * (hi - lo + 1.0))
        }),
        // On a lattice point (grid lines and corners exactly).
        2 => (-2i32..(nx as i32 + 2), -2i32..(ny as i32 + 2), -0.3f32..1.3).prop_map(move |(a, b, c)| {
            Vec3::new(a as f32, b as f32, lo + c * (hi - lo + 1.0))
        }),
        // Far outside.
        1 => (-3.0f32..4.0, -3.0f32..4.0, 0.0f32..3.0).prop_map(move |(a, b, c)| {
            Vec3::new(a * nx, b * ny, hi + 1.0 + c * (hi - lo + 5.0) * 4.0)
        }),
    ];
    (origin, dir).prop_map(move |(o, d)| {
        Ray::new(
            Vec3::new(o.x * cell, o.y * cell, o.z),
            Vec3::new(d.x * cell, d.y * cell, d.z),
        )
    })
}

/// A `[t_min, t_max]` pair: mostly `[0, ∞)`, sometimes finite or negative.
pub fn t_range() -> impl Strategy<Value = (f32, f32)> {
    prop_oneof![
        4 => Just((0.0f32, f32::INFINITY)),
        1 => (0.0f32..5.0, 0.0f32..30.0).prop_map(|(a, b)| (a, a + b)),
        1 => (-20.0f32..0.0).prop_map(|a| (a, f32::INFINITY)),
    ]
}
