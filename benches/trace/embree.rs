//! Embree 3 as a peer of the height-field tracer, in the same process.
//!
//! Built only with the facade's `embree-peer` feature, which links the
//! system's Embree 3 (Debian and Ubuntu: `apt install libembree-dev`):
//!
//! ```text
//! cargo bench --bench trace --features embree-peer -- embree
//! ```
//!
//! The field becomes a triangle mesh with natura's split of each cell (the
//! diagonal from `(i + 1, j)` to `(i, j + 1)`), so both libraries trace the
//! same surface and their hits can be compared ray by ray. Embree builds its
//! BVH with its default (medium) quality; its memory is what its device
//! reports through the memory monitor, the vertex and index buffers
//! included. Embree traces single rays (`rtcIntersect1`) and packets of 8
//! (`rtcIntersect8`, 4 × 2 pixels, the packet width of its AVX2 and AVX-512
//! kernels' 8-wide BVH); natura traces through `trace_image` (32 × 32 tiles,
//! its batch path). Every contender makes its rays from the same camera
//! inside the timed loop and writes one `t` per pixel, on every core.

#![allow(unsafe_code)]

use std::ffi::{c_char, c_void};
use std::hint::black_box;
use std::sync::atomic::{AtomicIsize, Ordering};
use std::time::{Duration, Instant};

use criterion::{Criterion, Throughput};
use natura::core::glam::{Vec2, Vec3};
use natura::core::{HeightField, NoProgress};
use natura::trace::{Camera, MipmapTracer, PinholeCamera, RenderOptions, trace_image};
use rayon::prelude::*;

const INVALID_ID: u32 = u32::MAX;
const GEOMETRY_TRIANGLE: u32 = 0;
const BUFFER_INDEX: u32 = 0;
const BUFFER_VERTEX: u32 = 1;
const FORMAT_UINT3: u32 = 0x5003;
const FORMAT_FLOAT3: u32 = 0x9003;
const CONTEXT_COHERENT: u32 = 1;

#[repr(C)]
struct IntersectContext {
    flags: u32,
    filter: *const c_void,
    inst_id: [u32; 1],
}

impl IntersectContext {
    /// `rtcInitIntersectContext` (an inline function of the C header).
    fn new(flags: u32) -> Self {
        Self {
            flags,
            filter: std::ptr::null(),
            inst_id: [INVALID_ID],
        }
    }
}

#[repr(C, align(16))]
struct Ray1 {
    org: [f32; 3],
    tnear: f32,
    dir: [f32; 3],
    time: f32,
    tfar: f32,
    mask: u32,
    id: u32,
    flags: u32,
}

#[repr(C, align(16))]
struct Hit1 {
    ng: [f32; 3],
    u: f32,
    v: f32,
    prim_id: u32,
    geom_id: u32,
    inst_id: [u32; 1],
}

#[repr(C)]
struct RayHit1 {
    ray: Ray1,
    hit: Hit1,
}

#[repr(C, align(32))]
struct Ray8 {
    org_x: [f32; 8],
    org_y: [f32; 8],
    org_z: [f32; 8],
    tnear: [f32; 8],
    dir_x: [f32; 8],
    dir_y: [f32; 8],
    dir_z: [f32; 8],
    time: [f32; 8],
    tfar: [f32; 8],
    mask: [u32; 8],
    id: [u32; 8],
    flags: [u32; 8],
}

#[repr(C, align(32))]
struct Hit8 {
    ng_x: [f32; 8],
    ng_y: [f32; 8],
    ng_z: [f32; 8],
    u: [f32; 8],
    v: [f32; 8],
    prim_id: [u32; 8],
    geom_id: [u32; 8],
    inst_id: [[u32; 8]; 1],
}

#[repr(C)]
struct RayHit8 {
    ray: Ray8,
    hit: Hit8,
}

type MemoryMonitor = extern "C" fn(*mut c_void, isize, bool) -> bool;

#[link(name = "embree3")]
unsafe extern "C" {
    fn rtcNewDevice(config: *const c_char) -> *mut c_void;
    fn rtcReleaseDevice(device: *mut c_void);
    fn rtcGetDeviceError(device: *mut c_void) -> i32;
    fn rtcSetDeviceMemoryMonitorFunction(
        device: *mut c_void,
        monitor: Option<MemoryMonitor>,
        user: *mut c_void,
    );
    fn rtcNewScene(device: *mut c_void) -> *mut c_void;
    fn rtcReleaseScene(scene: *mut c_void);
    fn rtcCommitScene(scene: *mut c_void);
    fn rtcNewGeometry(device: *mut c_void, kind: u32) -> *mut c_void;
    fn rtcReleaseGeometry(geometry: *mut c_void);
    fn rtcCommitGeometry(geometry: *mut c_void);
    fn rtcAttachGeometry(scene: *mut c_void, geometry: *mut c_void) -> u32;
    fn rtcSetNewGeometryBuffer(
        geometry: *mut c_void,
        kind: u32,
        slot: u32,
        format: u32,
        stride: usize,
        count: usize,
    ) -> *mut c_void;
    fn rtcIntersect1(scene: *mut c_void, context: *mut IntersectContext, rayhit: *mut RayHit1);
    fn rtcIntersect8(
        valid: *const i32,
        scene: *mut c_void,
        context: *mut IntersectContext,
        rayhit: *mut RayHit8,
    );
}

/// Bytes the Embree device holds now, and the most it held.
static HELD: AtomicIsize = AtomicIsize::new(0);
static PEAK: AtomicIsize = AtomicIsize::new(0);

extern "C" fn monitor(_: *mut c_void, bytes: isize, _post: bool) -> bool {
    let now = HELD.fetch_add(bytes, Ordering::Relaxed) + bytes;
    PEAK.fetch_max(now, Ordering::Relaxed);
    true
}

/// An Embree device and scene holding the field as a triangle mesh.
struct Scene {
    device: *mut c_void,
    scene: *mut c_void,
}

// SAFETY: Embree's committed scenes may be traced from any number of threads
// at once (its API documentation: "thread-safe ... after commit").
unsafe impl Sync for Scene {}

impl Scene {
    /// The field's triangles (natura's diagonal) in a committed scene, with
    /// the time its BVH took to build.
    fn new(hf: &HeightField) -> (Self, Duration) {
        let (nx, ny) = (hf.nx(), hf.ny());
        let cell = hf.cell_size();
        let h = hf.heights();
        // SAFETY: the calls follow Embree 3's API (rtcore_*.h): buffers are
        // filled through the pointers it returns, sized as requested, before
        // the geometry is committed.
        unsafe {
            let device = rtcNewDevice(std::ptr::null());
            assert!(!device.is_null(), "Embree: no device");
            rtcSetDeviceMemoryMonitorFunction(device, Some(monitor), std::ptr::null_mut());
            let scene = rtcNewScene(device);
            let geometry = rtcNewGeometry(device, GEOMETRY_TRIANGLE);
            let vertices =
                rtcSetNewGeometryBuffer(geometry, BUFFER_VERTEX, 0, FORMAT_FLOAT3, 12, nx * ny)
                    .cast::<[f32; 3]>();
            let vertices = std::slice::from_raw_parts_mut(vertices, nx * ny);
            for j in 0..ny {
                for i in 0..nx {
                    vertices[j * nx + i] = [i as f32 * cell, j as f32 * cell, h[(i, j)]];
                }
            }
            let cells = (nx - 1) * (ny - 1);
            let index =
                rtcSetNewGeometryBuffer(geometry, BUFFER_INDEX, 0, FORMAT_UINT3, 12, 2 * cells)
                    .cast::<[u32; 3]>();
            let index = std::slice::from_raw_parts_mut(index, 2 * cells);
            for j in 0..ny - 1 {
                for i in 0..nx - 1 {
                    let v = |a: usize, b: usize| ((j + b) * nx + i + a) as u32;
                    let c = j * (nx - 1) + i;
                    // natura's lower and upper triangles of the cell.
                    index[2 * c] = [v(0, 0), v(1, 0), v(0, 1)];
                    index[2 * c + 1] = [v(1, 0), v(1, 1), v(0, 1)];
                }
            }
            rtcCommitGeometry(geometry);
            rtcAttachGeometry(scene, geometry);
            rtcReleaseGeometry(geometry);
            let t0 = Instant::now();
            rtcCommitScene(scene);
            let build = t0.elapsed();
            assert_eq!(rtcGetDeviceError(device), 0, "Embree: scene build failed");
            (Self { device, scene }, build)
        }
    }

    /// `t` of the first hit of `dir` from `org` (∞ if none), one ray.
    fn intersect1(&self, org: Vec3, dir: Vec3) -> f32 {
        let mut rh = RayHit1 {
            ray: Ray1 {
                org: org.to_array(),
                tnear: 0.0,
                dir: dir.to_array(),
                time: 0.0,
                tfar: f32::INFINITY,
                mask: u32::MAX,
                id: 0,
                flags: 0,
            },
            hit: Hit1 {
                ng: [0.0; 3],
                u: 0.0,
                v: 0.0,
                prim_id: INVALID_ID,
                geom_id: INVALID_ID,
                inst_id: [INVALID_ID],
            },
        };
        let mut context = IntersectContext::new(0);
        // SAFETY: a committed scene and a ray-hit record laid out as the C header's.
        unsafe { rtcIntersect1(self.scene, &mut context, &mut rh) };
        if rh.hit.geom_id == INVALID_ID {
            f32::INFINITY
        } else {
            rh.ray.tfar
        }
    }

    /// `t` of the first hits of 8 rays from `org` along `dirs` (∞ if none).
    fn intersect8(&self, org: Vec3, dirs: &[Vec3; 8]) -> [f32; 8] {
        let mut rh = RayHit8 {
            ray: Ray8 {
                org_x: [org.x; 8],
                org_y: [org.y; 8],
                org_z: [org.z; 8],
                tnear: [0.0; 8],
                dir_x: dirs.map(|d| d.x),
                dir_y: dirs.map(|d| d.y),
                dir_z: dirs.map(|d| d.z),
                time: [0.0; 8],
                tfar: [f32::INFINITY; 8],
                mask: [u32::MAX; 8],
                id: [0; 8],
                flags: [0; 8],
            },
            hit: Hit8 {
                ng_x: [0.0; 8],
                ng_y: [0.0; 8],
                ng_z: [0.0; 8],
                u: [0.0; 8],
                v: [0.0; 8],
                prim_id: [INVALID_ID; 8],
                geom_id: [INVALID_ID; 8],
                inst_id: [[INVALID_ID; 8]],
            },
        };
        let valid = [-1i32; 8];
        let mut context = IntersectContext::new(CONTEXT_COHERENT);
        // SAFETY: as `intersect1`, with the packet's 32-byte alignment kept
        // by the record's type.
        unsafe { rtcIntersect8(valid.as_ptr(), self.scene, &mut context, &mut rh) };
        std::array::from_fn(|k| {
            if rh.hit.geom_id[k] == INVALID_ID {
                f32::INFINITY
            } else {
                rh.ray.tfar[k]
            }
        })
    }
}

impl Drop for Scene {
    fn drop(&mut self) {
        // SAFETY: the handles were made by `new` and are released once.
        unsafe {
            rtcReleaseScene(self.scene);
            rtcReleaseDevice(self.device);
        }
    }
}

/// Every pixel's `t` through Embree's 8-ray packets (4 × 2 pixels), rows
/// of packets shared among the cores.
fn frame_packets(scene: &Scene, cam: &PinholeCamera, out: &mut [f32]) {
    let w = cam.resolution().x as usize;
    out.par_chunks_mut(2 * w)
        .enumerate()
        .for_each(|(band, rows)| {
            let y0 = 2 * band as u32;
            for x0 in (0..w as u32).step_by(4) {
                let mut org = Vec3::ZERO;
                let dirs: [Vec3; 8] = std::array::from_fn(|k| {
                    let r = cam.ray(x0 + (k % 4) as u32, y0 + (k / 4) as u32, Vec2::splat(0.5));
                    org = r.origin;
                    r.dir
                });
                let t = scene.intersect8(org, &dirs);
                for (k, t) in t.into_iter().enumerate() {
                    rows[(k / 4) * w + x0 as usize + k % 4] = t;
                }
            }
        });
}

/// Every pixel's `t` through Embree's single-ray call.
fn frame_single(scene: &Scene, cam: &PinholeCamera, out: &mut [f32]) {
    let w = cam.resolution().x as usize;
    out.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        for (x, t) in row.iter_mut().enumerate() {
            let r = cam.ray(x as u32, y as u32, Vec2::splat(0.5));
            *t = scene.intersect1(r.origin, r.dir);
        }
    });
}

/// Every pixel's `t` through natura's batch path.
fn frame_natura(mip: &MipmapTracer<'_>, cam: &PinholeCamera) -> Vec<f32> {
    let image = trace_image(mip, cam, &RenderOptions::default(), &NoProgress, |_, h| {
        Vec3::splat(h.map_or(f32::INFINITY, |h| h.t))
    })
    .unwrap();
    image.pixels().as_slice().iter().map(|p| p.x).collect()
}

/// Median of `runs` wall times of each contender, taken in turn.
fn interleaved(runs: usize, contenders: &mut [(&str, &mut dyn FnMut())]) -> Vec<f64> {
    let mut times = vec![Vec::new(); contenders.len()];
    for _ in 0..runs {
        for (k, (_, f)) in contenders.iter_mut().enumerate() {
            let t0 = Instant::now();
            f();
            times[k].push(t0.elapsed().as_secs_f64());
        }
    }
    times
        .into_iter()
        .map(|mut t| {
            t.sort_by(f64::total_cmp);
            t[t.len() / 2]
        })
        .collect()
}

/// The Embree comparison on the grazing and top-down views of `hf`.
pub fn compare(c: &mut Criterion, hf: &HeightField, views: &[(&str, PinholeCamera)]) {
    let threads = rayon::current_num_threads();
    let mip = MipmapTracer::new(hf).unwrap();
    let (scene, build) = Scene::new(hf);
    let (held, peak) = (
        HELD.load(Ordering::Relaxed) as f64,
        PEAK.load(Ordering::Relaxed) as f64,
    );
    let cells = (hf.nx() - 1) * (hf.ny() - 1);
    let buffers = (hf.nx() * hf.ny() * 12 + 2 * cells * 12) as f64;
    let field = (hf.nx() * hf.ny() * 4) as f64;
    eprintln!(
        "[trace] embree: {} triangles, BVH built in {:.2} s ({threads} threads); the device holds {:.0} MB (peak {:.0} MB): vertex and index buffers {:.0} MB, the rest {:.0} MB; natura: the field {:.1} MB and its max-mipmap {:.1} MB; Embree / natura = {:.0}× (acceleration alone), {:.0}× (all)",
        2 * cells,
        build.as_secs_f64(),
        held / 1e6,
        peak / 1e6,
        buffers / 1e6,
        (held - buffers) / 1e6,
        field / 1e6,
        mip.memory_bytes() as f64 / 1e6,
        (held - buffers) / mip.memory_bytes() as f64,
        held / (field + mip.memory_bytes() as f64),
    );
    for (view, cam) in views {
        let r = cam.resolution();
        let n = (r.x * r.y) as usize;
        // Agreement, ray by ray: hit or miss alike, `t` within 1e-4 relative.
        let ours = frame_natura(&mip, cam);
        let mut packets = vec![0.0f32; n];
        frame_packets(&scene, cam, &mut packets);
        let mut single = vec![0.0f32; n];
        frame_single(&scene, cam, &mut single);
        let agree = |theirs: &[f32]| {
            ours.iter()
                .zip(theirs)
                .filter(|&(&a, &b)| {
                    (a.is_infinite() && b.is_infinite()) || (a - b).abs() <= 1e-4 * a.max(1.0)
                })
                .count() as f64
                / n as f64
        };
        eprintln!(
            "[trace] embree {view}: natura agrees with Embree's packets on {:.4}% of rays, with its single rays on {:.4}% (hit or miss, t within 1e-4 relative); {:.1}% hit",
            100.0 * agree(&packets),
            100.0 * agree(&single),
            100.0 * ours.iter().filter(|t| t.is_finite()).count() as f64 / n as f64,
        );
        let times = interleaved(
            7,
            &mut [
                ("natura trace_image", &mut || {
                    black_box(frame_natura(&mip, cam));
                }),
                ("embree rtcIntersect8", &mut || {
                    frame_packets(&scene, cam, black_box(&mut packets))
                }),
                ("embree rtcIntersect1", &mut || {
                    frame_single(&scene, cam, black_box(&mut single))
                }),
            ],
        );
        eprintln!(
            "[trace] embree {view} ({threads} threads, median of 7 interleaved frames): natura {:.1} M rays/s, Embree packets of 8 {:.1} M rays/s, Embree single rays {:.1} M rays/s; natura / packets = {:.2}, natura / single = {:.2}",
            n as f64 / times[0] / 1e6,
            n as f64 / times[1] / 1e6,
            n as f64 / times[2] / 1e6,
            times[1] / times[0],
            times[2] / times[0],
        );
        let mut g = c.benchmark_group(format!("embree_{view}_1920x1080_{threads}threads"));
        g.sample_size(10);
        g.warm_up_time(Duration::from_millis(500));
        g.measurement_time(Duration::from_secs(4));
        g.throughput(Throughput::Elements(n as u64));
        g.bench_function("natura_trace_image", |b| {
            b.iter(|| black_box(frame_natura(&mip, cam)))
        });
        g.bench_function("embree_packets8", |b| {
            b.iter(|| frame_packets(&scene, cam, black_box(&mut packets)))
        });
        g.bench_function("embree_single", |b| {
            b.iter(|| frame_single(&scene, cam, black_box(&mut single)))
        });
        g.finish();
    }
}
