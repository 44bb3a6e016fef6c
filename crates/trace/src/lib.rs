//! # natura-trace
//!
//! Ray tracing of height fields: Musgrave's grid tracing, maximum mipmaps,
//! and the cameras (pinhole, orthographic, panoramic) and tile-parallel image
//! driver that turn them into pictures.
//!
//! * [`GridTracer`]: Musgrave's grid tracing (Musgrave 1993,
//!   ch. 3; Musgrave et al. 1989, §5): a DDA over every cell the ray's
//!   projection crosses, a two-sided z-span cull per cell, and two exact
//!   watertight ray–triangle tests per surviving cell. The reference.
//! * [`MipmapTracer`] over a [`MaxMipmap`]: the min/max quadtree of Tevs,
//!   Ihrke & Seidel (2008) — the `m = 2` case of the source's "n² tree"
//!   (Musgrave 1993, §3.5) — which skips empty space at the coarsest level the
//!   ray allows. The fast path, with the same hits.
//! * [`DetailTracer`] over a [`DetailSurface`]: the field plus procedural
//!   detail octaves ([`Detail`], natura-noise's `FootprintFbm`) down to each
//!   ray's pixel [`RayCone`] — Musgrave's procedural level of detail
//!   (Musgrave 1993, §6.3). The pyramid widened by the detail's amplitude
//!   bound skips empty space, a Lipschitz-bounded march closed by
//!   regula falsi finds the hit in a cell (Hart 1996's sphere-tracing step), and where the
//!   footprint outgrows the cell the plain [`MipmapTracer`] takes over.
//! * [`brute_force`]: every triangle, for tests; [`detail_brute_force`]: a
//!   fine fixed-step march of the detailed surface, for tests.
//! * Cameras implementing [`Camera`]: natura-core's [`PinholeCamera`],
//!   [`OrthographicCamera`] and the panoramic virtual screens of the
//!   dissertation's appendix B ([`PanoramicCamera`], cylindrical or
//!   spherical, optionally stereo), re-exported here; this crate adds their
//!   jittered samples and lane-wise ray generation ([`Camera::rays_into`]).
//! * [`render`] / [`render_camera`] / [`trace_image`]: deterministic
//!   tile-parallel batch tracing with progress reporting; [`trace_image`]
//!   traces each tile's rays together through the batch path.
//!
//! ## The surface
//!
//! Sample `(i, j)` of a [`natura_core::HeightField`] sits at world
//! `(i·cell, j·cell, h[i, j])` (z up, metres). Each square cell is split into
//! two triangles along its anti-diagonal `u + v = 1`, the diagonal Musgrave
//! uses ("from top left to bottom right", Musgrave 1993, §3.3.2); see
//! [`Triangle`]. Hits are exact intersections with this piecewise-planar
//! surface; [`surface_height`] evaluates it.
//!
//! ## Exactness
//!
//! Each triangle is tested with Woop, Benthin & Wald's watertight algorithm
//! (JCGT 2013): shared corners and edges are computed identically for every
//! cell, so no ray slips through a crack, and [`brute_force`] over all
//! triangles with the same test is the oracle the tracers are tested against
//! (same hit, `t` within 1e-4 relative). The traversal and the exact test
//! round independently, so where a ray passes within a rounding bound of a
//! cell edge or corner the tracers also test the cells across it, and every
//! z cull is widened by the ray's altitude rounding bound: no cull or
//! traversal decision can lose a hit the exact test would find, and every
//! reported hit is an exact hit of some triangle.
//!
//! ## Performance
//!
//! [`MipmapTracer`] needs about `N/3` bytes for `N` samples (one third of the
//! `f32` field, which it borrows) and takes O(log N)-like steps per ray where
//! [`GridTracer`] takes O(√N); figures against the plain DDA and parry3d are
//! in `docs/performance.md`. Both are `Sync`: share one tracer across threads.
//!
//! Trace rays in batches where you can: [`MipmapTracer::trace_many`] and
//! [`MipmapTracer::occluded_many`] (also through [`Tracer::trace_many`], and
//! [`trace_image`] for whole images) walk 16 rays in lock step without
//! data-dependent branches, vectorised with AVX-512 or AVX2 where the CPU has
//! them (detected at run time; portable code otherwise); the ray set-up, the
//! exact cell tests and the hit records run in lanes of 16 too, and
//! [`trace_image`] generates each tile's primary rays 16 at a time
//! ([`Camera::rays_into`]). Runs of 128 rays that share one origin (a
//! camera tile's primary rays) first walk the pyramid once as a packet: a
//! conservative bound over all their rays proves a stretch of empty space
//! they cross together above the surface, and each ray's own walk starts
//! after it. They return exactly the hits of one call per ray, in less
//! time; figures in `docs/performance.md`.
//!
//! ## Errata corrected
//!
//! * The printed triangle clip `x + y ≤ cellxmax + cellymax`
//!   (Musgrave 1993, §3.3.2) accepts the whole cell; the triangle is `u + v ≤ 1`.
//! * The cull `min(z_near, z_far) ≤ max(corners)` (eq. 3.1, Musgrave 1993, §3.2) holds
//!   only for rays from above; we test the ray's z-span against the cell's
//!   `[min, max]` in both directions.
//! * The panorama code interpolates its vertical table with the horizontal
//!   one (`horizdir` for `vertdir`, Musgrave 1993, §8.6); see [`PanoramicCamera`].
//!
//! ```
//! use natura_trace::glam::Vec3;
//! use natura_trace::{HeightField, MipmapTracer, Ray, Tracer};
//!
//! let hf = HeightField::from_fn(65, 65, 2.0, |i, j| ((i * j) % 7) as f32)?;
//! let tracer = MipmapTracer::new(&hf)?;
//! let ray = Ray::new(Vec3::new(20.0, 30.0, 100.0), Vec3::new(0.1, 0.2, -1.0));
//! let hit = tracer.trace(&ray, 0.0, f32::INFINITY).expect("a downward ray over the field hits");
//! assert!((hit.point.z - natura_trace::surface_height(&hf, hit.point.x, hit.point.y).unwrap()).abs() < 1e-3);
//! assert!(tracer.occluded(&ray, 0.0, hit.t + 1e-3));
//! # Ok::<(), natura_trace::TraceError>(())
//! ```
// `unsafe` is denied crate-wide; the only exceptions are the calls that
// natura-simd's `multiversion!` writes into the `#[target_feature]` lane
// kernels (`lockstep/kernels.rs`), one float-to-int truncation of a value
// clamped to cell coordinates (`float.rs`), and the AVX2 event mask of the
// lane step (`lockstep/node.rs`: two unaligned loads of 16 `u32`, called only
// under a token that proves AVX2).
#![deny(unsafe_code)]

mod batch;
mod brute;
mod camera;
mod dda;
mod detail;
mod detail_tracer;
mod error;
mod field;
mod float;
mod frustum;
mod grid_ray;
mod leaf;
mod lockstep;
mod max_mipmap;
mod ray;
mod ray_cell;
mod step;
mod surface;
mod tracer;

pub use batch::{DEFAULT_TILE, RenderOptions, render, render_camera, render_tiles, trace_image};
pub use brute::{brute_force, detail_brute_force};
pub use camera::{Camera, RAY_LANES};
pub use dda::{CellVisit, CellWalk, GridTracer};
pub use detail::{Detail, DetailParams, DetailSurface, MAX_DETAIL_OCTAVES, RayCone};
pub use detail_tracer::DetailTracer;
pub use error::{Result, TraceError};
pub use field::MAX_SAMPLES_PER_AXIS;
/// The vector types of the API, so users need no `glam` dependency of their own.
pub use glam;
pub use max_mipmap::{MaxMipmap, MipmapTracer};
/// The height field every tracer works on.
pub use natura_core::HeightField;
/// The cameras (natura-core's): pinhole, orthographic and panoramic maps from
/// pixels to rays and back.
pub use natura_core::camera::{
    Eye, MAX_RESOLUTION, OrthographicCamera, PanoramicCamera, PinholeCamera, Projection, Stereo,
};
pub use ray::{Hit, Ray, TraceStats, Triangle};
pub use surface::surface_height;
pub use tracer::Tracer;
