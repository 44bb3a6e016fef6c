use super::*;
use crate::turtle::Geometry;
use crate::{Derivation, LSystem, Turtle, TurtleParams};
use std::collections::HashMap;

fn geometry(src: &str, steps: u32, angle: f64) -> Geometry {
    let l = LSystem::parse(src).unwrap();
    let mut d = Derivation::new(&l, 7).unwrap();
    d.derive(steps).unwrap();
    let p = TurtleParams {
        angle_deg: angle,
        width: 0.2,
        ..TurtleParams::default()
    };
    Turtle::new(&l, p).unwrap().interpret(d.string()).unwrap()
}

fn params(r: u32) -> MeshParams {
    MeshParams {
        radial_segments: r,
        ..MeshParams::default()
    }
}

/// Every undirected edge (vertices merged by position) lies on exactly two triangles.
fn closed(m: &PlantMesh, mat: Material) -> bool {
    let key = |i: u32| {
        let p = m.positions[i as usize];
        (
            (p.x * 1e4).round() as i64,
            (p.y * 1e4).round() as i64,
            (p.z * 1e4).round() as i64,
        )
    };
    let mut edges: HashMap<_, u32> = HashMap::new();
    for t in m.triangles(mat) {
        for k in 0..3 {
            let (a, b) = (key(t[k]), key(t[(k + 1) % 3]));
            if a == b {
                continue;
            }
            *edges
                .entry(if a < b { (a, b) } else { (b, a) })
                .or_insert(0) += 1;
        }
    }
    !edges.is_empty() && edges.values().all(|&c| c == 2)
}

#[test]
fn closed_form_counts() {
    for r in [3, 8, 17] {
        let rr = r as usize + 1;
        // One chain of three segments.
        let g = geometry("axiom: FFF", 0, 30.0);
        let m = PlantMesh::from_geometry(&g, &params(r)).unwrap();
        assert_eq!(m.vertex_count(), (3 + 1) * rr + 2 * rr);
        assert_eq!(m.indices.len(), 6 * r as usize * 3 + 6 * r as usize);
        // The main axis F…F continues across the branch: two chains, three segments.
        let g = geometry("axiom: F[+F]F", 0, 30.0);
        let m = PlantMesh::from_geometry(&g, &params(r)).unwrap();
        assert_eq!(m.vertex_count(), (3 + 2) * rr + 2 * 2 * rr);
        assert_eq!(m.indices.len(), 6 * r as usize * 3 + 2 * 6 * r as usize);
        let c = PlantMesh::counts(&g, &params(r)).unwrap();
        assert_eq!(c.bark_vertices + c.leaf_vertices, m.vertex_count());
        assert_eq!(c.bark_indices + c.leaf_indices, m.indices.len());
    }
    // Without caps: (n + c)(R + 1) vertices, 6 R n indices.
    let g = geometry("axiom: F[+F][-F[&F]F]F", 0, 30.0);
    let p = MeshParams {
        caps: false,
        ..params(6)
    };
    let m = PlantMesh::from_geometry(&g, &p).unwrap();
    assert_eq!(m.vertex_count(), (6 + 4) * 7);
    assert_eq!(m.indices.len(), 6 * 6 * 6);
}

#[test]
fn leaf_counts() {
    let p = MeshParams::default();
    let (n, r) = (p.leaf_rows as usize, p.radial_segments as usize);
    let cases: [(&str, usize, usize); 5] = [
        ("~L(1,0.3)", 3 * n - 1, 12 * (n - 1)),
        ("~P(1,0.3)", 3 * n - 1, 12 * (n - 1)),
        ("~K(1)", 5 * (3 * n - 1), 5 * 12 * (n - 1)),
        ("@o(0.5)", r + 1, 3 * r),
        ("@O(0.5)", (r / 2 + 1) * (r + 1), 3 * r * (2 * (r / 2) - 2)),
    ];
    for (s, v, i) in cases {
        let g = geometry(&format!("axiom: {s}"), 0, 30.0);
        for double in [false, true] {
            let p = MeshParams {
                double_sided_leaves: double,
                ..MeshParams::default()
            };
            let m = PlantMesh::from_geometry(&g, &p).unwrap();
            let k = if double { 2 } else { 1 };
            assert_eq!((m.vertex_count(), m.indices.len()), (k * v, k * i), "{s}");
            m.check().unwrap();
        }
    }
    // A polygon of n vertices: n vertices, n − 2 triangles.
    let g = geometry("axiom: {.+F.+F.+F.-F.+F.}", 0, 72.0);
    let m = PlantMesh::from_geometry(&g, &MeshParams::default()).unwrap();
    let nv = g.polygons[0].vertices.len();
    assert_eq!((m.vertex_count(), m.triangle_count()), (nv, nv - 2));
    assert_eq!(
        m.primitives,
        vec![Primitive {
            material: Material::Leaf,
            first: 0,
            count: 3 * (nv as u32 - 2)
        }]
    );
}

#[test]
fn concave_polygon_is_ear_clipped() {
    // An L-shaped hexagon (area 3): the triangles' areas must sum to it.
    let mut g = Geometry::default();
    g.polygons.push(crate::turtle::Polygon {
        vertices: [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]
            .iter()
            .map(|&(x, y)| Vec3::new(x, y, 0.0))
            .collect(),
        colour: 0,
        distance: 0.0,
    });
    let m = PlantMesh::from_geometry(&g, &MeshParams::default()).unwrap();
    let area: f32 = m
        .triangles(Material::Leaf)
        .map(|[a, b, c]| {
            let (a, b, c) = (
                m.positions[a as usize],
                m.positions[b as usize],
                m.positions[c as usize],
            );
            0.5 * (b - a).cross(c - a).z
        })
        .sum();
    assert!((area - 3.0).abs() < 1e-5, "{area}");
}

#[test]
fn bark_is_closed_with_outward_unit_normals() {
    for src in [
        "axiom: F+F&F/F^F-F",
        "axiom: F[+F][-F[&F]F]F",
        "axiom: F+(150)F(0.5)",
    ] {
        let g = geometry(src, 0, 50.0);
        for r in [3, 8] {
            let m = PlantMesh::from_geometry(&g, &params(r)).unwrap();
            m.check().unwrap();
            // Each chain is a closed surface; chains touch only along branch starts.
            let single = geometry(src.split('[').next().unwrap(), 0, 50.0);
            let ms = PlantMesh::from_geometry(&single, &params(r)).unwrap();
            assert!(closed(&ms, Material::Bark), "{src} R={r}");
            // Winding agrees with the normals: each triangle faces where its vertices' normals point.
            for [a, b, c] in m.triangles(Material::Bark) {
                let (pa, pb, pc) = (
                    m.positions[a as usize],
                    m.positions[b as usize],
                    m.positions[c as usize],
                );
                let face = (pb - pa).cross(pc - pa);
                if face.length() < 1e-7 {
                    continue;
                }
                let n = m.normals[a as usize] + m.normals[b as usize] + m.normals[c as usize];
                assert!(face.dot(n) > 0.0, "{src}: triangle {a} {b} {c}");
            }
            for n in &m.normals {
                assert!((n.length() - 1.0).abs() < 1e-5);
            }
        }
    }
    // A reversal starts a new tube: two chains.
    let g = geometry("axiom: F|F", 0, 30.0);
    let m = PlantMesh::from_geometry(&g, &params(4)).unwrap();
    assert_eq!(m.vertex_count(), 2 * (2 + 2) * 5);
    // A straight stem along z: every side normal points away from the axis.
    let g = geometry("axiom: FF", 0, 30.0);
    let m = PlantMesh::from_geometry(&g, &params(8)).unwrap();
    for (p, n) in m.positions.iter().zip(&m.normals) {
        let radial = Vec3::new(p.x, p.y, 0.0);
        if radial.length() > 1e-4 && n.z.abs() < 1e-6 {
            assert!(n.dot(radial.normalize()) > 0.999);
            assert!((radial.length() - 0.1).abs() < 1e-5, "radius = width / 2");
        }
    }
}

#[test]
fn leaves_face_their_normals() {
    let g = geometry(
        "axiom: ~L(1,0.4)/(40)~P(1,0.5)&(30)~K(0.5)@o(0.3)@O(0.2)",
        0,
        30.0,
    );
    let m = PlantMesh::from_geometry(&g, &MeshParams::default()).unwrap();
    for [a, b, c] in m.triangles(Material::Leaf) {
        let (pa, pb, pc) = (
            m.positions[a as usize],
            m.positions[b as usize],
            m.positions[c as usize],
        );
        let face = (pb - pa).cross(pc - pa);
        if face.length() < 1e-7 {
            continue;
        }
        let n = m.normals[a as usize] + m.normals[b as usize] + m.normals[c as usize];
        assert!(face.dot(n) > 0.0);
    }
    let uv_ok = m
        .uvs
        .iter()
        .all(|t| (0.0..=1.0).contains(&t.x) && (0.0..=1.0).contains(&t.y));
    assert!(uv_ok);
}

#[test]
fn wind_grows_along_chains_and_uvs_are_in_range() {
    let g = geometry("axiom: A\nA -> F[+A][-A]FA", 4, 25.0);
    let m = PlantMesh::from_geometry(&g, &params(6)).unwrap();
    let maxd = g.max_distance();
    let (mut lo, mut hi) = (f32::MAX, f32::MIN);
    for (t, w) in m.uvs.iter().zip(&m.wind) {
        lo = lo.min(*w);
        hi = hi.max(*w);
        assert!((0.0..=1.0).contains(&t.x));
        assert!(t.y >= 0.0 && t.y <= maxd * (1.0 + 1e-6) || (0.0..=1.0).contains(&t.y));
    }
    assert_eq!(lo, 0.0, "the trunk base has weight 0");
    assert_eq!(hi, 1.0, "the farthest tip has weight 1");
    // Along one chain (no caps), successive rings never lose weight and v is path length.
    let g = geometry("axiom: F+F-F&F(2)F", 0, 20.0);
    let p = MeshParams {
        caps: false,
        ..params(5)
    };
    let m = PlantMesh::from_geometry(&g, &p).unwrap();
    let rings: Vec<(f32, f32)> = (0..m.vertex_count() / 6)
        .map(|k| (m.wind[6 * k], m.uvs[6 * k].y))
        .collect();
    assert_eq!(rings.len(), 6);
    for w in rings.windows(2) {
        assert!(w[1].0 >= w[0].0);
    }
    let v: Vec<f32> = rings.iter().map(|r| r.1).collect();
    assert_eq!(v, vec![0.0, 1.0, 2.0, 3.0, 5.0, 6.0]);
}

#[test]
fn bad_input_is_an_error() {
    let g = geometry("axiom: F[+F]F~L", 0, 30.0);
    for r in [0, 2, 65] {
        assert!(PlantMesh::from_geometry(&g, &params(r)).is_err());
    }
    let mut b = g.clone();
    b.width0.pop();
    assert!(PlantMesh::from_geometry(&b, &MeshParams::default()).is_err());
    let mut b = g.clone();
    b.prev[0] = 2;
    assert!(PlantMesh::from_geometry(&b, &MeshParams::default()).is_err());
    let mut b = g.clone();
    b.end[1].x = f32::NAN;
    assert!(PlantMesh::from_geometry(&b, &MeshParams::default()).is_err());
    let mut b = g.clone();
    b.width1[1] = -1.0;
    assert!(PlantMesh::from_geometry(&b, &MeshParams::default()).is_err());
    let mut b = g.clone();
    b.surfaces[0].name = 'Q';
    assert!(PlantMesh::from_geometry(&b, &MeshParams::default()).is_err());
    let mut m = PlantMesh::from_geometry(&g, &MeshParams::default()).unwrap();
    m.indices[0] = u32::MAX;
    assert!(m.check().is_err());
}

#[test]
fn empty_geometry_gives_empty_mesh() {
    let m = PlantMesh::from_geometry(&Geometry::default(), &MeshParams::default()).unwrap();
    assert_eq!(
        (m.vertex_count(), m.indices.len(), m.primitives.len()),
        (0, 0, 0)
    );
    assert!(m.bounds().is_none());
}
