//! OpenVDB round trips through the independent `vdb-rs` reader and through
//! natura's own, and corrupt or truncated files.

use glam::Vec3;
use natura_core::Grid3;
use natura_volume::cloud::{CloudParams, cloud, nine_sphere_cumulus};
use natura_volume::grid::GridDensity;
use natura_volume::vdb::{decode_vdb, encode_vdb, read_vdb, write_vdb};
use natura_volume::{Density, VolumeError};
use std::collections::HashMap;
use vdb_rs::{Map, VdbReader};

fn sample_grid() -> GridDensity {
    // Sparse content crossing leaf (8) and internal-node (128) boundaries.
    let g = Grid3::from_fn(150, 20, 17, |i, j, k| {
        let v = ((i * 7 + j * 13 + k * 3) % 11) as f32 * 0.125;
        if (i / 9 + j / 5 + k) % 3 == 0 { 0.0 } else { v }
    })
    .unwrap();
    GridDensity::new(g, Vec3::new(-3.5, 2.0, 0.25), 0.2).unwrap()
}

#[test]
fn vdb_rs_reads_back_identical_voxels_and_transform() {
    let dir = std::env::temp_dir().join(format!("natura-vdb-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("grids.vdb");
    let density = sample_grid();
    let c = cloud(nine_sphere_cumulus(), CloudParams::cumulus(), 3).unwrap();
    let temperature = GridDensity::bake(&c, 0.5).unwrap();
    write_vdb(
        &path,
        &[("density", &density), ("temperature", &temperature)],
    )
    .unwrap();

    let f = std::io::BufReader::new(std::fs::File::open(&path).unwrap());
    let mut reader = VdbReader::new(f).unwrap();
    let mut names = reader.available_grids();
    names.sort();
    assert_eq!(names, ["density", "temperature"]);
    for (name, g) in [("density", &density), ("temperature", &temperature)] {
        let grid = reader.read_grid::<f32>(name).unwrap();
        match grid.transform {
            Map::ScaleTranslateMap {
                translation,
                voxel_size,
                ..
            } => {
                // vdb-rs uses its own glam version: compare as arrays.
                let t = (g.origin() + Vec3::splat(0.5 * g.cell())).as_dvec3();
                let tr = glam::DVec3::from_array(translation.to_array());
                let vs = glam::DVec3::from_array(voxel_size.to_array());
                assert!((tr - t).abs().max_element() < 1e-6, "{tr} vs {t}");
                assert!(
                    (vs - glam::DVec3::splat(f64::from(g.cell())))
                        .abs()
                        .max_element()
                        < 1e-9
                );
            }
            other => panic!("unexpected transform {other:?}"),
        }
        let mut seen = HashMap::new();
        for (pos, v, _) in grid.iter() {
            seen.insert([pos.x as usize, pos.y as usize, pos.z as usize], v);
        }
        let (nx, ny, nz) = g.grid().dims();
        let mut nonzero = 0;
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    let v = g.grid()[(x, y, z)];
                    if v != 0.0 {
                        nonzero += 1;
                        assert_eq!(
                            seen.get(&[x, y, z]).map(|f| f.to_bits()),
                            Some(v.to_bits()),
                            "{name} ({x}, {y}, {z})"
                        );
                    }
                }
            }
        }
        assert_eq!(
            seen.len(),
            nonzero,
            "{name}: only the non-zero voxels are active"
        );
    }
    // natura's own reader gives back the same field.
    let back = read_vdb(&path).unwrap();
    assert_eq!(back.len(), 2);
    assert_eq!(back[0].name, "density");
    let d = &back[0].density;
    let (nx, ny, nz) = density.grid().dims();
    for (x, y, z) in [(0, 0, 0), (5, 7, 3), (149, 19, 16), (77, 10, 8)] {
        let p = density.origin() + (Vec3::new(x as f32, y as f32, z as f32) + 0.5) * density.cell();
        assert!(
            (d.density(p) - density.density(p)).abs() < 1e-5,
            "({x}, {y}, {z})"
        );
    }
    assert!(nx > 0 && ny > 0 && nz > 0);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn truncated_and_corrupt_files_are_errors_never_panics() {
    let small = GridDensity::new(
        Grid3::from_fn(10, 9, 3, |i, j, k| (i + j + k) as f32 * 0.1).unwrap(),
        Vec3::ZERO,
        1.0,
    )
    .unwrap();
    let bytes = encode_vdb(&[("density", &small)]).unwrap();
    assert!(decode_vdb(&bytes).is_ok());
    // Every byte of the headers, metadata and transform, then a stride through
    // the node value arrays (which are most of the file) and the tail.
    let positions: Vec<usize> = (0..bytes.len())
        .filter(|&i| i < 1024 || i % 97 == 0 || i + 2200 > bytes.len())
        .collect();
    // Every truncation is an error.
    for &n in &positions {
        assert!(
            matches!(
                decode_vdb(&bytes[..n]),
                Err(VolumeError::Vdb(_)) | Err(VolumeError::Core(_))
            ),
            "cut at {n}"
        );
    }
    // Single-byte corruptions anywhere: Ok or a typed error, never a panic.
    let mut state = 0x2545_F491u32;
    for &i in &positions {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        let mut b = bytes.clone();
        b[i] ^= (state as u8) | 1;
        let _ = decode_vdb(&b);
        let mut b = bytes.clone();
        b[i] = 0xFF;
        let _ = decode_vdb(&b);
    }
    assert!(matches!(
        decode_vdb(b"not a vdb file at all"),
        Err(VolumeError::Vdb(_))
    ));
    assert!(decode_vdb(&[]).is_err());
    assert!(encode_vdb(&[]).is_err());
    assert!(encode_vdb(&[("", &small)]).is_err());
    assert!(encode_vdb(&[("a", &small), ("a", &small)]).is_err());
    assert!(read_vdb("/nonexistent/natura.vdb").is_err());
}

#[test]
fn raw_and_exr_slices() {
    let dir = std::env::temp_dir().join(format!("natura-slices-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let g = sample_grid();
    natura_volume::export::write_raw(dir.join("d.raw"), &g).unwrap();
    let raw = std::fs::read(dir.join("d.raw")).unwrap();
    assert_eq!(raw.len(), g.grid().len() * 4);
    assert_eq!(
        f32::from_le_bytes(raw[4..8].try_into().unwrap()),
        g.grid().as_slice()[1]
    );
    natura_volume::export::write_exr_slice(dir.join("s.exr"), &g, 4).unwrap();
    let img = natura_core::Image::load_exr(dir.join("s.exr")).unwrap();
    let (nx, ny, _) = g.grid().dims();
    assert_eq!((img.width(), img.height()), (nx, ny));
    assert_eq!(img.get(3, ny - 1 - 2).unwrap().x, g.grid()[(3, 2, 4)]);
    assert!(natura_volume::export::slice_z(&g, 999).is_err());
    std::fs::remove_dir_all(&dir).ok();
}
