//! The lanes' stages compiled for each instruction set, through the one
//! dispatch mechanism of `natura_core::simd` (its `multiversion!`): each
//! stage is a plain loop over lanes, inlined into a `#[target_feature]`
//! function chosen by a [`Simd`] token, where LLVM vectorises it. Every level computes the same
//! values (tested at every supported level).

use natura_core::simd::{self, Simd, SimdLevel};

use super::node::{NodeTable, descend_lanes, event_mask, step};
use super::{CellOut, Exact, LANES, Lanes};
use crate::field::FieldView;
use crate::grid_ray::{SETUP_LANES, SetupLanes, setup_lanes};
use crate::max_mipmap::MipmapTracer;
use crate::ray::{Hit, Ray};
use crate::ray_cell::{HIT_LANES, HitLanes, hit_lanes};

/// The event mask of a lane step: in registers where the level has AVX2
/// (the portable loop over just-stored events stalls on store forwarding).
#[inline(always)]
fn event_mask_at(simd: Simd, events: &[u32; LANES]) -> u32 {
    #[cfg(target_arch = "x86_64")]
    if simd.level() >= SimdLevel::Avx2 {
        #[allow(unsafe_code)]
        // SAFETY: a `Simd` token of level AVX2 or above is only made after
        // the CPU reported AVX2, the feature `event_mask_avx2` needs.
        return unsafe { super::node::event_mask_avx2(events) };
    }
    let _ = simd;
    event_mask(events)
}

simd::multiversion! {
    /// [`step`] at `simd`'s level: returns the events as two lane masks (bit
    /// `l` of the low half: lane `l` is at a cell; of the high half: it left).
    pub(super) fn step_with<'a>(
        simd: Simd,
        s: &'a mut Lanes,
        k: &'a NodeTable<'a>,
        events: &'a mut [u32; LANES],
    ) -> u32 {
        step(s, k, events);
        event_mask_at(simd, events)
    }
}

simd::multiversion! {
    /// The exact cell tests of the parked lanes ([`super::cell::cells`]) at
    /// `simd`'s level.
    pub(super) fn cells_with<'a, const ANY: bool>(
        simd: Simd,
        s: &'a mut Lanes,
        k: &'a NodeTable<'a>,
        x: &'a Exact,
        c: &'a [[f32; LANES]; 4],
        parked: u32,
        o: &'a mut CellOut,
    ) {
        super::cell::cells::<ANY>(s, k, x, c, parked, o);
    }
}

simd::multiversion! {
    /// [`setup_lanes`] at `simd`'s level.
    pub(crate) fn setup_with<'a>(
        simd: Simd,
        f: &'a FieldView<'a>,
        rays: &'a [Ray; SETUP_LANES],
        t_min: f32,
        t_max: f32,
        top: u32,
        s: &'a mut SetupLanes,
    ) {
        setup_lanes(f, rays, t_min, t_max, top, s);
    }
}

simd::multiversion! {
    /// [`descend_lanes`] at `simd`'s level.
    pub(crate) fn descend_with<'a>(
        simd: Simd,
        tr: &'a MipmapTracer<'a>,
        offset: &'a [u32; 32],
        s: &'a mut SetupLanes,
        out: &'a mut [u32; SETUP_LANES],
    ) {
        descend_lanes(tr, offset, s, out);
    }
}

simd::multiversion! {
    /// [`hit_lanes`] at `simd`'s level: the first `n` hits of `s` into
    /// `out[slot[l]]`.
    pub(crate) fn hits_with<'a>(
        simd: Simd,
        f: &'a FieldView<'a>,
        s: &'a HitLanes,
        n: usize,
        out: &'a mut [Option<Hit>],
        slot: &'a [usize; HIT_LANES],
    ) {
        hit_lanes(f, s, n, |l, h| out[slot[l]] = Some(h));
    }
}
