//! OpenVDB export and import of float grids (density, temperature).
//!
//! The file layout follows the public OpenVDB format (Museth 2013, §3 "The
//! VDB data structure" for the tree: a root table of 32³ internal nodes of 16³
//! internal nodes of 8³ leaves; and the OpenVDB library's `io` module for the
//! byte layout): the archive header (magic, file version 224, library
//! version, a UUID), file metadata, then per grid its descriptor, compression
//! flags, metadata, transform, tree topology and leaf buffers. Grids are
//! written uncompressed, with only the leaves that hold a non-zero voxel
//! (zero is the background and is inactive), as `Tree_float_5_4_3` fog
//! volumes whose transform places voxel `(i, j, k)` at its centre,
//! `origin + (i + ½, j + ½, k + ½)·cell`, matching [`GridDensity`].
//!
//! [`decode_vdb`] reads the same subset back (uncompressed float trees,
//! scale-translate transforms, files of format 222–224) and refuses
//! everything else, and every corrupt or truncated file, with
//! [`VolumeError::Vdb`]; it never panics and checks every count against the
//! bytes left before allocating.

use std::collections::BTreeMap;
use std::path::Path;

use glam::{DVec3, Vec3};
use natura_core::Grid3;

use crate::error::{Result, VolumeError};
use crate::grid::GridDensity;

const MAGIC: i64 = 0x5644_4220;
const FILE_VERSION: u32 = 224;
const NODE_MASK_COMPRESSION: u32 = 222;
const GRID_TYPE: &str = "Tree_float_5_4_3";
const COMPRESS_ZIP: u32 = 0x1;
const COMPRESS_ACTIVE_MASK: u32 = 0x2;
const COMPRESS_BLOSC: u32 = 0x4;
/// Per-node value layout tag: no mask, every value stored.
const NO_MASK_AND_ALL_VALS: u8 = 6;

fn err(msg: impl Into<String>) -> VolumeError {
    VolumeError::Vdb(msg.into())
}

// ------------------------------------------------------------------ writer

struct Out(Vec<u8>);

impl Out {
    fn u8(&mut self, v: u8) {
        self.0.push(v);
    }
    fn u32(&mut self, v: u32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn i32(&mut self, v: i32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn u64(&mut self, v: u64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn i64(&mut self, v: i64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn f32(&mut self, v: f32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn dvec3(&mut self, v: DVec3) {
        for c in v.to_array() {
            self.0.extend_from_slice(&c.to_le_bytes());
        }
    }
    fn name(&mut self, s: &str) {
        self.u32(s.len() as u32);
        self.0.extend_from_slice(s.as_bytes());
    }
    fn coord(&mut self, c: [i32; 3]) {
        for v in c {
            self.i32(v);
        }
    }
    fn mask(&mut self, words: &[u64]) {
        for &w in words {
            self.u64(w);
        }
    }
    fn meta_string(&mut self, name: &str, v: &str) {
        self.name(name);
        self.name("string");
        self.name(v);
    }
    fn meta_bool(&mut self, name: &str, v: bool) {
        self.name(name);
        self.name("bool");
        self.u32(1);
        self.u8(u8::from(v));
    }
    fn meta_i64(&mut self, name: &str, v: i64) {
        self.name(name);
        self.name("int64");
        self.u32(8);
        self.i64(v);
    }
    fn meta_vec3i(&mut self, name: &str, v: [i32; 3]) {
        self.name(name);
        self.name("vec3i");
        self.u32(12);
        self.coord(v);
    }
    /// A node's value array, uncompressed: layout tag, then every value.
    fn values(&mut self, v: &[f32]) {
        self.u8(NO_MASK_AND_ALL_VALS);
        for &x in v {
            self.f32(x);
        }
    }
}

/// One leaf: active mask and 512 values, `x`-major (`z` fastest), as OpenVDB stores them.
struct Leaf {
    mask: [u64; 8],
    values: Vec<f32>,
}

type Tree = BTreeMap<[i32; 3], BTreeMap<u32, BTreeMap<u32, Leaf>>>;

/// Index-space bounding box `(min, max)` of the active voxels.
type IndexBox = Option<([i32; 3], [i32; 3])>;

fn build_tree(g: &Grid3<f32>) -> (Tree, IndexBox, i64) {
    let (_, ny, nz) = g.dims();
    let mut tree: Tree = BTreeMap::new();
    let mut bbox: IndexBox = None;
    let mut count = 0i64;
    for z in 0..nz {
        for y in 0..ny {
            for (x, &v) in g.row(y, z).iter().enumerate() {
                if v == 0.0 {
                    continue;
                }
                count += 1;
                let c = [x as i32, y as i32, z as i32];
                bbox = Some(match bbox {
                    None => (c, c),
                    Some((lo, hi)) => (
                        [lo[0].min(c[0]), lo[1].min(c[1]), lo[2].min(c[2])],
                        [hi[0].max(c[0]), hi[1].max(c[1]), hi[2].max(c[2])],
                    ),
                });
                let root = [c[0] & !4095, c[1] & !4095, c[2] & !4095];
                let off5 = ((((c[0] & 4095) >> 7) << 10)
                    | (((c[1] & 4095) >> 7) << 5)
                    | ((c[2] & 4095) >> 7)) as u32;
                let off4 = ((((c[0] & 127) >> 3) << 8)
                    | (((c[1] & 127) >> 3) << 4)
                    | ((c[2] & 127) >> 3)) as u32;
                let off3 = (((c[0] & 7) << 6) | ((c[1] & 7) << 3) | (c[2] & 7)) as usize;
                let leaf = tree
                    .entry(root)
                    .or_default()
                    .entry(off5)
                    .or_default()
                    .entry(off4)
                    .or_insert_with(|| Leaf {
                        mask: [0; 8],
                        values: vec![0.0; 512],
                    });
                leaf.mask[off3 / 64] |= 1 << (off3 % 64);
                leaf.values[off3] = v;
            }
        }
    }
    (tree, bbox, count)
}

fn uuid(bytes: &[u8]) -> String {
    let mut h = 0xCBF2_9CE4_8422_2325u64;
    for &b in bytes {
        h = (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01B3);
    }
    let (a, b) = (
        natura_core::mix64(h),
        natura_core::mix64(h ^ 0x9E37_79B9_7F4A_7C15),
    );
    let s = format!("{a:016x}{b:016x}");
    format!(
        "{}-{}-{}-{}-{}",
        &s[0..8],
        &s[8..12],
        &s[12..16],
        &s[16..20],
        &s[20..32]
    )
}

/// Encodes named float grids as an OpenVDB file in memory.
///
/// # Errors
///
/// [`VolumeError::InvalidParameter`] for no grids, an empty, duplicate or
/// over-long name, or a grid over 2³¹ voxels along an axis.
pub fn encode_vdb(grids: &[(&str, &GridDensity)]) -> Result<Vec<u8>> {
    check_grids(grids)?;
    let mut o = Out(Vec::new());
    o.i64(MAGIC);
    o.u32(FILE_VERSION);
    o.u32(11); // library version the layout follows
    o.u32(0);
    o.u8(1); // has grid offsets
    let id = uuid(
        &grids
            .iter()
            .flat_map(|(n, g)| {
                n.bytes().chain(
                    g.grid()
                        .as_slice()
                        .iter()
                        .take(4096)
                        .flat_map(|v| v.to_le_bytes()),
                )
            })
            .collect::<Vec<u8>>(),
    );
    o.0.extend_from_slice(id.as_bytes());
    // File metadata.
    o.u32(1);
    o.meta_string("creator", "natura");
    o.u32(grids.len() as u32);
    for (name, g) in grids {
        write_grid(&mut o, name, g);
    }
    Ok(o.0)
}

/// Checks [`encode_vdb`]'s grids: at least one, names non-empty, short and
/// unique, sizes within `i32` voxel coordinates.
fn check_grids(grids: &[(&str, &GridDensity)]) -> Result<()> {
    if grids.is_empty() {
        return Err(VolumeError::InvalidParameter {
            name: "grids",
            value: "0".into(),
            expected: "at least one grid",
        });
    }
    for (i, (name, g)) in grids.iter().enumerate() {
        if name.is_empty() || name.len() > 256 || grids[..i].iter().any(|(n, _)| n == name) {
            return Err(VolumeError::InvalidParameter {
                name: "grid name",
                value: (*name).to_string(),
                expected: "non-empty, at most 256 bytes, and unique",
            });
        }
        let (nx, ny, nz) = g.grid().dims();
        if nx.max(ny).max(nz) > i32::MAX as usize {
            return Err(VolumeError::InvalidParameter {
                name: "grid size",
                value: format!("{nx} × {ny} × {nz}"),
                expected: "fewer than 2^31 voxels per axis",
            });
        }
    }
    Ok(())
}

/// Writes one grid: its descriptor, metadata, transform, topology and leaf
/// buffers, then patches the descriptor's three stream offsets.
fn write_grid(o: &mut Out, name: &str, g: &GridDensity) {
    let (tree, bbox, count) = build_tree(g.grid());
    o.name(name);
    o.name(GRID_TYPE);
    o.name(""); // no instance parent
    let offsets_at = o.0.len();
    o.u64(0);
    o.u64(0);
    o.u64(0);
    let grid_pos = o.0.len() as u64;
    o.u32(0); // no compression
    write_grid_metadata(o, name, &tree, bbox, count);
    // Transform: index (i, j, k) → world origin + (ijk + ½)·cell.
    let cell = f64::from(g.cell());
    let t = (g.origin() + Vec3::splat(0.5 * g.cell())).as_dvec3();
    o.name("UniformScaleTranslateMap");
    o.dvec3(t);
    o.dvec3(DVec3::splat(cell));
    o.dvec3(DVec3::splat(cell));
    o.dvec3(DVec3::splat(1.0 / cell));
    o.dvec3(DVec3::splat(1.0 / (cell * cell)));
    o.dvec3(DVec3::splat(0.5 / cell));
    write_topology(o, &tree);
    let block_pos = o.0.len() as u64;
    for leaf in tree
        .values()
        .flat_map(|n5| n5.values())
        .flat_map(|n4| n4.values())
    {
        o.mask(&leaf.mask);
        o.values(&leaf.values);
    }
    let end_pos = o.0.len() as u64;
    for (k, v) in [grid_pos, block_pos, end_pos].into_iter().enumerate() {
        o.0[offsets_at + 8 * k..offsets_at + 8 * k + 8].copy_from_slice(&v.to_le_bytes());
    }
}

/// A grid's metadata, sorted by name as OpenVDB's map keeps it.
fn write_grid_metadata(o: &mut Out, name: &str, tree: &Tree, bbox: IndexBox, count: i64) {
    let n_meta = if bbox.is_some() { 7 } else { 5 };
    o.u32(n_meta);
    o.meta_string("class", "fog volume");
    if let Some((lo, hi)) = bbox {
        o.meta_vec3i("file_bbox_max", hi);
        o.meta_vec3i("file_bbox_min", lo);
    }
    let leaves: usize = tree
        .values()
        .flat_map(|n5| n5.values())
        .map(BTreeMap::len)
        .sum();
    o.meta_i64("file_mem_bytes", (leaves * (512 * 4 + 64)) as i64);
    o.meta_i64("file_voxel_count", count);
    o.meta_bool("is_saved_as_half_float", false);
    o.meta_string("name", name);
}

/// The tree's topology: the root's children, each internal node's child
/// and value masks with its (inactive) tile values, and the leaves' masks.
fn write_topology(o: &mut Out, tree: &Tree) {
    o.u32(1); // buffer count
    o.f32(0.0); // background
    o.u32(0); // tiles
    o.u32(tree.len() as u32);
    for (origin, n5) in tree {
        o.coord(*origin);
        let mut child5 = vec![0u64; 512];
        for &i in n5.keys() {
            child5[i as usize / 64] |= 1 << (i % 64);
        }
        o.mask(&child5);
        o.mask(&[0u64; 512]);
        o.values(&vec![0.0; 32768]);
        for n4 in n5.values() {
            let mut child4 = vec![0u64; 64];
            for &i in n4.keys() {
                child4[i as usize / 64] |= 1 << (i % 64);
            }
            o.mask(&child4);
            o.mask(&[0u64; 64]);
            o.values(&[0.0; 4096]);
            for leaf in n4.values() {
                o.mask(&leaf.mask);
            }
        }
    }
}

/// Writes named float grids (for example `("density", …)`, `("temperature", …)`)
/// to an OpenVDB file, through a temporary name and a rename.
///
/// # Errors
///
/// As [`encode_vdb`]; [`VolumeError::Core`] for an I/O failure.
pub fn write_vdb(path: impl AsRef<Path>, grids: &[(&str, &GridDensity)]) -> Result<()> {
    let bytes = encode_vdb(grids)?;
    natura_core::io::write_bytes_atomic(path, &bytes)?;
    Ok(())
}

// ------------------------------------------------------------------ reader

struct In<'a> {
    b: &'a [u8],
    pos: usize,
}

impl<'a> In<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8]> {
        if n > self.b.len() - self.pos {
            return Err(err(format!(
                "truncated at byte {} (wanted {n} more)",
                self.pos
            )));
        }
        let s = &self.b[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }
    fn arr<const N: usize>(&mut self) -> Result<[u8; N]> {
        let mut a = [0u8; N];
        a.copy_from_slice(self.take(N)?);
        Ok(a)
    }
    fn u8(&mut self) -> Result<u8> {
        Ok(self.take(1)?[0])
    }
    fn u32(&mut self) -> Result<u32> {
        Ok(u32::from_le_bytes(self.arr()?))
    }
    fn i32(&mut self) -> Result<i32> {
        Ok(i32::from_le_bytes(self.arr()?))
    }
    fn u64(&mut self) -> Result<u64> {
        Ok(u64::from_le_bytes(self.arr()?))
    }
    fn i64(&mut self) -> Result<i64> {
        Ok(i64::from_le_bytes(self.arr()?))
    }
    fn f32(&mut self) -> Result<f32> {
        Ok(f32::from_le_bytes(self.arr()?))
    }
    fn dvec3(&mut self) -> Result<DVec3> {
        let mut v = [0.0f64; 3];
        for c in &mut v {
            *c = f64::from_le_bytes(self.arr()?);
        }
        Ok(DVec3::from_array(v))
    }
    fn name(&mut self) -> Result<String> {
        let n = self.u32()? as usize;
        let s = self.take(n)?;
        String::from_utf8(s.to_vec()).map_err(|_| err("a name is not UTF-8"))
    }
    fn seek(&mut self, pos: u64) -> Result<()> {
        if pos > self.b.len() as u64 {
            return Err(err(format!(
                "offset {pos} beyond the end of the file ({} bytes)",
                self.b.len()
            )));
        }
        self.pos = pos as usize;
        Ok(())
    }
    fn mask(&mut self, words: usize) -> Result<Vec<u64>> {
        let raw = self.take(words * 8)?;
        Ok(raw
            .chunks_exact(8)
            .map(|c| u64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
            .collect())
    }
    /// Metadata entries: `(name, type, payload)`.
    fn metadata(&mut self) -> Result<Vec<(String, String, &'a [u8])>> {
        let n = self.u32()? as usize;
        // Each entry takes at least 12 bytes.
        if n > (self.b.len() - self.pos) / 12 {
            return Err(err(format!("{n} metadata entries cannot fit in the file")));
        }
        let mut out = Vec::with_capacity(n);
        for _ in 0..n {
            let name = self.name()?;
            let ty = self.name()?;
            let len = self.u32()? as usize;
            out.push((name, ty, self.take(len)?));
        }
        Ok(out)
    }
    /// A node's value array of `n` values given its active `mask` and the grid's compression flags.
    fn values(&mut self, n: usize, mask: &[u64], compression: u32) -> Result<Vec<f32>> {
        let tag = self.u8()?;
        if tag > 6 {
            return Err(err(format!("invalid node value layout {tag}")));
        }
        let mut inactive = [0.0f32; 2];
        if matches!(tag, 2 | 4 | 5) {
            inactive[0] = self.f32()?;
            if tag == 5 {
                inactive[1] = self.f32()?;
            }
        }
        let selection = if matches!(tag, 3..=5) {
            Some(self.mask(n.div_ceil(64))?)
        } else {
            None
        };
        let masked = compression & COMPRESS_ACTIVE_MASK != 0 && tag != NO_MASK_AND_ALL_VALS;
        let bit = |m: &[u64], i: usize| m[i / 64] >> (i % 64) & 1 == 1;
        let count = if masked {
            (0..n).filter(|&i| bit(mask, i)).count()
        } else {
            n
        };
        let raw = self.take(count * 4)?;
        let stored: Vec<f32> = raw
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        if !masked {
            return Ok(stored);
        }
        let mut it = stored.into_iter();
        Ok((0..n)
            .map(|i| {
                if bit(mask, i) {
                    it.next().unwrap_or(0.0)
                } else if selection.as_ref().is_some_and(|s| bit(s, i)) {
                    inactive[1]
                } else {
                    inactive[0]
                }
            })
            .collect())
    }
}

/// A grid read from a VDB file.
#[derive(Clone, Debug)]
pub struct VdbGrid {
    /// The grid's name.
    pub name: String,
    /// The voxels over the bounding box of the active ones, placed in world space.
    pub density: GridDensity,
}

/// Decodes the float grids of an OpenVDB file (the subset [`encode_vdb`]
/// writes: uncompressed `Tree_float_5_4_3` grids with a uniform
/// scale-translate transform, format versions 222–224).
///
/// # Errors
///
/// [`VolumeError::Vdb`] for a corrupt, truncated or unsupported file;
/// [`VolumeError::BadVoxel`] for a NaN, infinite or negative voxel;
/// [`VolumeError::Core`] for a grid over natura's memory cap.
pub fn decode_vdb(bytes: &[u8]) -> Result<Vec<VdbGrid>> {
    let mut r = In { b: bytes, pos: 0 };
    if r.i64()? != MAGIC {
        return Err(err("not an OpenVDB file (bad magic number)"));
    }
    let version = r.u32()?;
    if !(NODE_MASK_COMPRESSION..=FILE_VERSION).contains(&version) {
        return Err(err(format!(
            "file format {version} is not supported (222 to 224 are)"
        )));
    }
    let _library = (r.u32()?, r.u32()?);
    if r.u8()? != 1 {
        return Err(err("streams without grid offsets are not supported"));
    }
    r.take(36)?; // UUID
    r.metadata()?;
    let n = r.u32()? as usize;
    if n > bytes.len() / 32 {
        return Err(err(format!("{n} grids cannot fit in the file")));
    }
    (0..n).map(|_| decode_grid(&mut r)).collect()
}

/// Decodes the grid whose descriptor starts at `r`'s position, leaving `r`
/// at the grid's end.
fn decode_grid(r: &mut In<'_>) -> Result<VdbGrid> {
    let name = r.name()?;
    let ty = r.name()?;
    let _parent = r.name()?;
    let (grid_pos, block_pos, end_pos) = (r.u64()?, r.u64()?, r.u64()?);
    if ty != GRID_TYPE {
        return Err(err(format!(
            "grid `{name}` has type `{ty}`; only {GRID_TYPE} is supported"
        )));
    }
    r.seek(grid_pos)?;
    let compression = r.u32()?;
    if compression & (COMPRESS_ZIP | COMPRESS_BLOSC) != 0 {
        return Err(err(format!(
            "grid `{name}` is zip or Blosc compressed, which this reader does not support"
        )));
    }
    for (k, t, v) in r.metadata()? {
        if k == "is_saved_as_half_float" && t == "bool" && v.first().is_some_and(|&b| b != 0) {
            return Err(err(format!(
                "grid `{name}` is stored as half floats, which this reader does not support"
            )));
        }
    }
    let (translation, cell) = read_transform(r, &name)?;
    let leaves = read_topology(r, &name, compression)?;
    // Leaf buffers.
    r.seek(block_pos)?;
    let mut voxels: Vec<([i64; 3], f32)> = Vec::new();
    for o3 in &leaves {
        let mask = r.mask(8)?;
        let v = r.values(512, &mask, compression)?;
        for i in (0..512usize).filter(|&i| mask[i / 64] >> (i % 64) & 1 == 1) {
            let c = [
                o3[0] + (i >> 6) as i64,
                o3[1] + ((i >> 3) & 7) as i64,
                o3[2] + (i & 7) as i64,
            ];
            voxels.push((c, v[i]));
        }
    }
    r.seek(end_pos)?;
    Ok(VdbGrid {
        density: dense(&name, &voxels, translation, cell)?,
        name,
    })
}

/// Reads a grid's transform: `(translation, cell)`, refusing any map but a
/// uniform positive scale with an optional translation.
fn read_transform(r: &mut In<'_>, name: &str) -> Result<(DVec3, f64)> {
    let map = r.name()?;
    let (translation, scale) = match map.as_str() {
        "UniformScaleTranslateMap" | "ScaleTranslateMap" => {
            let t = r.dvec3()?;
            let s = r.dvec3()?;
            for _ in 0..4 {
                r.dvec3()?;
            }
            (t, s)
        }
        "UniformScaleMap" | "ScaleMap" => {
            let s = r.dvec3()?;
            for _ in 0..4 {
                r.dvec3()?;
            }
            (DVec3::ZERO, s)
        }
        other => {
            return Err(err(format!(
                "grid `{name}`: transform `{other}` is not supported"
            )));
        }
    };
    let cell = scale.x;
    if !(translation.is_finite()
        && cell.is_finite()
        && cell > 0.0
        && (scale - DVec3::splat(cell)).abs().max_element() <= 1e-9 * cell)
    {
        return Err(err(format!(
            "grid `{name}`: the transform must be a uniform positive scale (got {scale:?})"
        )));
    }
    Ok((translation, cell))
}

/// Reads a grid's topology: the index-space origins of its leaves, in the
/// order their buffers follow.
fn read_topology(r: &mut In<'_>, name: &str, compression: u32) -> Result<Vec<[i64; 3]>> {
    if r.u32()? != 1 {
        return Err(err("multi-buffer trees are not supported"));
    }
    let _background = r.f32()?;
    let (tiles, children) = (r.u32()? as usize, r.u32()? as usize);
    if tiles > 0 {
        return Err(err(format!("grid `{name}`: root tiles are not supported")));
    }
    if children > r.b.len() / 8192 {
        return Err(err(format!(
            "{children} root children cannot fit in the file"
        )));
    }
    let mut leaves = Vec::new();
    for _ in 0..children {
        let o5 = [
            i64::from(r.i32()?),
            i64::from(r.i32()?),
            i64::from(r.i32()?),
        ];
        let child5 = r.mask(512)?;
        let value5 = r.mask(512)?;
        r.values(32768, &value5, compression)?;
        if value5.iter().any(|&w| w != 0) {
            return Err(err(format!(
                "grid `{name}`: active tiles are not supported"
            )));
        }
        for i5 in (0..32768usize).filter(|&i| child5[i / 64] >> (i % 64) & 1 == 1) {
            let o4 = [
                o5[0] + ((i5 >> 10) as i64) * 128,
                o5[1] + (((i5 >> 5) & 31) as i64) * 128,
                o5[2] + ((i5 & 31) as i64) * 128,
            ];
            let child4 = r.mask(64)?;
            let value4 = r.mask(64)?;
            r.values(4096, &value4, compression)?;
            if value4.iter().any(|&w| w != 0) {
                return Err(err(format!(
                    "grid `{name}`: active tiles are not supported"
                )));
            }
            for i4 in (0..4096usize).filter(|&i| child4[i / 64] >> (i % 64) & 1 == 1) {
                let o3 = [
                    o4[0] + ((i4 >> 8) as i64) * 8,
                    o4[1] + (((i4 >> 4) & 15) as i64) * 8,
                    o4[2] + ((i4 & 15) as i64) * 8,
                ];
                r.mask(8)?;
                leaves.push(o3);
            }
        }
    }
    Ok(leaves)
}

/// The dense grid over the bounding box of `voxels`.
fn dense(
    name: &str,
    voxels: &[([i64; 3], f32)],
    translation: DVec3,
    cell: f64,
) -> Result<GridDensity> {
    let (lo, hi) = voxels
        .iter()
        .fold(([i64::MAX; 3], [i64::MIN; 3]), |(lo, hi), (c, _)| {
            (
                [lo[0].min(c[0]), lo[1].min(c[1]), lo[2].min(c[2])],
                [hi[0].max(c[0]), hi[1].max(c[1]), hi[2].max(c[2])],
            )
        });
    let (lo, dims) = if voxels.is_empty() {
        ([0; 3], [1usize; 3])
    } else {
        let d = |k: usize| {
            usize::try_from(hi[k] - lo[k] + 1)
                .map_err(|_| err(format!("grid `{name}`: bad bounding box")))
        };
        (lo, [d(0)?, d(1)?, d(2)?])
    };
    let mut g = Grid3::new(dims[0], dims[1], dims[2], 0.0f32)?;
    for (c, v) in voxels {
        let i = ((c[2] - lo[2]) as usize * dims[1] + (c[1] - lo[1]) as usize) * dims[0]
            + (c[0] - lo[0]) as usize;
        g.as_mut_slice()[i] = *v;
    }
    let origin = translation
        + (DVec3::new(lo[0] as f64, lo[1] as f64, lo[2] as f64) - DVec3::splat(0.5)) * cell;
    GridDensity::new(g, origin.as_vec3(), cell as f32)
}

/// Reads the float grids of an OpenVDB file (see [`decode_vdb`]).
///
/// # Errors
///
/// As [`decode_vdb`]; [`VolumeError::Core`] for an I/O failure or a file over natura's memory cap.
pub fn read_vdb(path: impl AsRef<Path>) -> Result<Vec<VdbGrid>> {
    let bytes = natura_core::io::read_file(path)?;
    decode_vdb(&bytes)
}
