//! Pixels from samples: the tiles, each pixel's stratified and refined
//! samples, and the pixel filter's weighted mean over them
//! ([`super::filter`]).

use super::*;

/// Tile side with the Gaussian filter, pixels: large enough that the ring
/// of pixels around a tile, whose samples the filter reads and which are
/// traced again for it, adds little (3 % at σ ≤ 0.5, whose ring is one
/// pixel wide; 6 % at 64), and small enough that a 1920 × 1080 frame
/// still has 135 tiles to share between the threads.
const FILTER_TILE: u32 = 128;

/// The samples of one pixel of a tile's traced block: where its base
/// samples are in the block's arrays, and its further ones, if any.
struct Samples {
    /// The top-left pixel and width of the traced block: a tile and the
    /// ring of pixels around it the filter reaches.
    origin: (u32, u32, u32),
    /// Positions in their pixel (`[0, 1)²`) and radiances of every traced
    /// pixel's base samples, `spp` a pixel in row order.
    base: (Vec<Vec2>, Vec<Vec3>),
    /// The same of the further samples of the pixels that take them.
    more: (Vec<Vec2>, Vec<Vec3>),
    /// Per traced pixel, the index in `more` of its first further sample,
    /// or `usize::MAX` where it took none.
    more_at: Vec<usize>,
}

impl Renderer<'_> {
    /// Renders the linear (scene-referred) image in parallel tiles.
    ///
    /// Each pixel takes `spp` stratified samples over its square, whose
    /// positions are random numbers indexed by pixel and sample; a pixel
    /// whose samples disagree takes more, up to the scene's
    /// `adaptive_samples` (the refinement's samples fill the pixel with its
    /// base ones). Each pixel is then the mean of the samples around it
    /// weighted by the scene's pixel filter (`render.filter_sigma_px`):
    /// its own and those of the pixels the filter reaches, each pixel's
    /// samples counted by their mean, so a refined pixel weighs no more
    /// than its neighbours. So the image is
    /// bit-identical for any thread count. The primary rays of a tile and
    /// of the ring of pixels around it the filter reaches (all their base
    /// samples, then the further samples of the pixels that take them)
    /// are traced together with [`Tracer::trace_many`], the mipmap
    /// tracer's lock-step lanes; every pixel equals [`Self::pixel`] bit for
    /// bit.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Core`](crate::RenderError::Core) if the image cannot be allocated, and the
    /// errors of sky and aerial-perspective lookups.
    pub fn render(&self, progress: &dyn Progress) -> Result<Image> {
        self.render_region(0, 0, self.width, self.height, progress)
    }

    /// Renders the `width × height` pixel rectangle of the image whose
    /// top-left pixel is `(x0, y0)`, in parallel tiles: a shard of a frame.
    ///
    /// Every pixel is a function of its position, sample index and seed only
    /// (see [`Self::render`]), so the region equals the same rectangle of the
    /// full image bit for bit, whatever the region and thread count.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Invalid`](crate::RenderError::Invalid) if the
    /// rectangle is empty or reaches outside the image, and the errors of
    /// [`Self::render`].
    pub fn render_region(
        &self,
        x0: u32,
        y0: u32,
        width: u32,
        height: u32,
        progress: &dyn Progress,
    ) -> Result<Image> {
        let inside =
            |o: u32, n: u32, side: u32| n > 0 && o.checked_add(n).is_some_and(|e| e <= side);
        if !inside(x0, width, self.width) || !inside(y0, height, self.height) {
            return Err(crate::RenderError::invalid(
                "region",
                format_args!("{width} × {height} at ({x0}, {y0})"),
                &format!(
                    "a non-empty rectangle inside the {} × {} image",
                    self.width, self.height
                ),
            ));
        }
        let reach = self.filter.reach();
        let grid = natura_trace::render_tiles(
            width,
            height,
            if reach == 0 {
                natura_trace::DEFAULT_TILE
            } else {
                FILTER_TILE
            },
            progress,
            |bx, by, w, h, out| {
                let (bx, by) = (x0 + bx, y0 + by);
                // The tile and the ring of pixels its filter reaches.
                let (ax, ay) = (bx.saturating_sub(reach), by.saturating_sub(reach));
                let aw = (bx + w + reach).min(self.width) - ax;
                let ah = (by + h + reach).min(self.height) - ay;
                let block = self.trace_block(ax, ay, aw, ah);
                for y in by..by + h {
                    for x in bx..bx + w {
                        out.push(self.filtered(x, y, |nx, ny, f| {
                            block.pixel(nx, ny, self.spp as usize, self.adaptive.total(), f);
                        }));
                    }
                }
            },
        )?;
        Ok(Image::from_grid(grid))
    }

    /// The base and further samples of the `w × h` pixels whose top-left
    /// pixel is `(x0, y0)`, their rays traced together. Whether a pixel
    /// takes further samples is [`Self::refines`]'s test of its own base
    /// samples.
    fn trace_block(&self, x0: u32, y0: u32, w: u32, h: u32) -> Samples {
        let n = self.spp as usize;
        let mut epos = Vec::with_capacity((w * h) as usize * n);
        let mut rays = Vec::with_capacity((w * h) as usize * n);
        for y in y0..y0 + h {
            for x in x0..x0 + w {
                for s in 0..self.spp {
                    let p = self.sample_position(x, y, s);
                    epos.push(p);
                    rays.push(self.primary_ray(x, y, p));
                }
            }
        }
        let hits = self.tracer.trace_many(&rays, 0.0, f32::INFINITY);
        let erad: Vec<Vec3> = rays
            .iter()
            .zip(&hits)
            .map(|(ray, hit)| self.radiance_traced(ray, hit.as_ref()))
            .collect();
        // Pixels in row order, as the base samples were traced.
        let mut more_at = vec![usize::MAX; (w * h) as usize];
        let (mut mpos, mut mrays) = (Vec::new(), Vec::new());
        for (i, more) in more_at.iter_mut().enumerate() {
            if self.refines(&erad[i * n..(i + 1) * n]) {
                let (x, y) = (x0 + i as u32 % w, y0 + i as u32 / w);
                *more = mpos.len();
                for s in self.spp..self.adaptive.total() {
                    let p = self.sample_position(x, y, s);
                    mpos.push(p);
                    mrays.push(self.primary_ray(x, y, p));
                }
            }
        }
        let mrad: Vec<Vec3> = if mrays.is_empty() {
            Vec::new()
        } else {
            let hits = self.tracer.trace_many(&mrays, 0.0, f32::INFINITY);
            mrays
                .iter()
                .zip(&hits)
                .map(|(ray, hit)| self.radiance_traced(ray, hit.as_ref()))
                .collect()
        };
        Samples {
            origin: (x0, y0, w),
            base: (epos, erad),
            more: (mpos, mrad),
            more_at,
        }
    }

    /// Whether a pixel whose base samples are `base` takes further ones:
    /// they disagree ([`Adaptive::disagree`]). Under the Gaussian filter
    /// a pixel's value mixes in its neighbours' samples, but a neighbour
    /// whose samples disagree refines itself, and [`PixelFilter::mean`]
    /// counts each pixel by the mean of its own samples, so the test of a
    /// pixel's own samples is enough.
    fn refines(&self, base: &[Vec3]) -> bool {
        self.adaptive.disagree(base)
    }

    /// Pixel `(x, y)` from the samples `visit(nx, ny, f)` hands to `f` (as
    /// `f(position in the pixel, radiance)`, in sample order) for each pixel
    /// `(nx, ny)` the filter reaches from it: the plain mean of its own for
    /// the box, else [`PixelFilter::mean`].
    fn filtered(
        &self,
        x: u32,
        y: u32,
        visit: impl Fn(u32, u32, &mut dyn FnMut(Vec2, Vec3)),
    ) -> Vec3 {
        if self.filter.is_box() {
            let (mut sum, mut count) = (Vec3::ZERO, 0u32);
            visit(x, y, &mut |_, l| {
                sum += l;
                count += 1;
            });
            return sum / count as f32;
        }
        self.filter.mean(x, y, (self.width, self.height), visit)
    }

    /// Pixel `(x, y)` of [`Self::render`]: the filter-weighted mean of the
    /// stratified samples around it (see there).
    #[must_use]
    pub fn pixel(&self, x: u32, y: u32) -> Vec3 {
        self.pixel_samples(x, y).0
    }

    /// [`Self::pixel`] and the number of samples the pixel itself took:
    /// `spp`, or the scene's `adaptive_samples` where its base samples
    /// disagree.
    #[must_use]
    pub fn pixel_samples(&self, x: u32, y: u32) -> (Vec3, u32) {
        let own = std::cell::Cell::new(0);
        let value = self.filtered(x, y, |nx, ny, f| {
            let samples = self.samples_of(nx, ny);
            if (nx, ny) == (x, y) {
                own.set(samples.len() as u32);
            }
            for (p, l) in samples {
                f(p, l);
            }
        });
        (value, own.get())
    }

    /// The samples of pixel `(x, y)`, traced one by one: its base samples,
    /// and where [`Self::refines`] says so its further ones, as `(position
    /// in the pixel, radiance)`.
    fn samples_of(&self, x: u32, y: u32) -> Vec<(Vec2, Vec3)> {
        let sample = |x: u32, y: u32, s: u32| {
            let p = self.sample_position(x, y, s);
            let ray = self.primary_ray(x, y, p);
            let hit = self.tracer.trace(&ray, 0.0, f32::INFINITY);
            (p, self.radiance_traced(&ray, hit.as_ref()))
        };
        let mut all: Vec<(Vec2, Vec3)> = (0..self.spp).map(|s| sample(x, y, s)).collect();
        let base: Vec<Vec3> = all.iter().map(|a| a.1).collect();
        if self.refines(&base) {
            all.extend((self.spp..self.adaptive.total()).map(|s| sample(x, y, s)));
        }
        all
    }

    /// Where sample `s` of pixel `(x, y)` lies in the pixel, `[0, 1)²`
    /// ([`refined_position`] of random numbers indexed by pixel and sample).
    fn sample_position(&self, x: u32, y: u32, s: u32) -> Vec2 {
        let jitter = |s: u32| {
            let h = self.seed.hash(&[i64::from(x), i64::from(y), i64::from(s)]);
            (
                unit_f64(h) as f32,
                unit_f64(mix64(h ^ 0x9E37_79B9_7F4A_7C15)) as f32,
            )
        };
        let shuffle = |k: i64| self.seed.hash(&[i64::from(x), i64::from(y), k]);
        refined_position(s, self.spp, self.adaptive.total(), jitter, shuffle)
    }

    /// The camera ray through position `p` of pixel `(x, y)`, with a unit
    /// direction.
    fn primary_ray(&self, x: u32, y: u32, p: Vec2) -> Ray {
        let ray = self.camera.camera().ray(x, y, p);
        Ray::new(ray.origin, ray.dir.normalize())
    }
}

impl Samples {
    /// Hands the samples of pixel `(x, y)` of the image (a traced pixel),
    /// in order, to `f`: its `n` base samples, then its further ones up to
    /// `total` if it took them.
    fn pixel(&self, x: u32, y: u32, n: usize, total: u32, f: &mut dyn FnMut(Vec2, Vec3)) {
        let (ex, ey, ew) = self.origin;
        let i = ((y - ey) * ew + (x - ex)) as usize;
        for k in i * n..(i + 1) * n {
            f(self.base.0[k], self.base.1[k]);
        }
        let at = self.more_at[i];
        if at != usize::MAX {
            for k in at..at + (total as usize - n) {
                f(self.more.0[k], self.more.1[k]);
            }
        }
    }
}
