use super::*;
use glam::Vec3;

/// A trunk of radius 0.2 m from the ground to 3 m, with a branch leaving it
/// at 2 m along +y.
fn tree() -> Geometry {
    let mut g = Geometry::default();
    for (a, b, w) in [
        (Vec3::ZERO, Vec3::new(0.0, 0.0, 3.0), 0.4f32),
        (Vec3::new(0.0, 0.0, 2.0), Vec3::new(0.0, 2.0, 3.0), 0.2),
    ] {
        g.start.push(a);
        g.end.push(b);
        g.up.push(Vec3::X);
        g.width0.push(w);
        g.width1.push(w);
        g.dist0.push(0.0);
        g.dist1.push(1.0);
        g.colour.push(0);
        g.prev.push(u32::MAX);
    }
    g
}

/// Distance of `p` from the test tree's bark (its two capsules).
fn from_bark(p: Vec3) -> f32 {
    let capsule = |a: Vec3, b: Vec3, r: f32| {
        let s = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
        (p - (a + (b - a) * s)).length() - r
    };
    capsule(Vec3::ZERO, Vec3::new(0.0, 0.0, 3.0), 0.2).min(capsule(
        Vec3::new(0.0, 0.0, 2.0),
        Vec3::new(0.0, 2.0, 3.0),
        0.1,
    ))
}

/// A seed 2 cm from the trunk, 30° round from +x (off the cubes' faces).
const SEED: [f64; 3] = [0.19, 0.11, 0.05];

fn grow(p: &ClimberParams) -> (Run, Support, Geometry) {
    let (run, env) = climber(p, &tree()).unwrap();
    let g = run.geometry().unwrap();
    (run, env, g)
}

#[test]
fn the_climber_follows_the_bark_upwards() {
    let p = ClimberParams {
        start: SEED,
        steps: 120,
        ..ClimberParams::default()
    };
    let (_, _, g) = grow(&p);
    assert!(g.segment_count() > 100, "{}", g.segment_count());
    // Every segment stays on the bark: within 8 cm of it, never inside.
    for &e in &g.end {
        let d = from_bark(e);
        assert!((-0.005..0.08).contains(&d), "{e} is {d} m from the bark");
    }
    // It climbs: the highest point is well above the start, and the stems
    // wind
    let top = g.end.iter().map(|e| e.z).fold(0.0f32, f32::max);
    assert!(top > 1.5, "top {top}");
    // round it: below the branch they cover at least 120° of the trunk
    // (four 30° sectors).
    let mut sectors = [false; 12];
    for e in g.end.iter().filter(|e| e.z < 1.9) {
        let a = e.y.atan2(e.x).to_degrees().rem_euclid(360.0);
        sectors[(a / 30.0) as usize % 12] = true;
    }
    let covered = sectors.iter().filter(|&&s| s).count();
    assert!(covered >= 4, "{covered} sectors");
    // Leaves on the way.
    assert!(g.surfaces.len() >= g.segment_count());
}

#[test]
fn crowding_stops_the_apices() {
    // No cube holds more segments than the crowding allows, and a tighter
    // limit stops more apices and grows fewer segments.
    let count = |crowding: u32| {
        let p = ClimberParams {
            start: SEED,
            steps: 150,
            crowding,
            ..ClimberParams::default()
        };
        let (_, env, g) = grow(&p);
        let mut cubes: HashMap<[i64; 3], u32> = HashMap::new();
        for s in &g.start {
            let k = (s.as_dvec3() / p.cell).floor().as_i64vec3().to_array();
            *cubes.entry(k).or_default() += 1;
        }
        let most = cubes.values().copied().max().unwrap_or(0);
        (g.segment_count(), env.crowded, most)
    };
    let (loose, tight) = (count(40), count(6));
    assert!(tight.2 <= 6 && loose.2 <= 40, "{loose:?} {tight:?}");
    assert!(tight.1 > 0 && tight.0 < loose.0 / 2, "{loose:?} {tight:?}");
}

#[test]
fn without_bark_the_seed_dies() {
    let p = ClimberParams {
        start: [5.0, 5.0, 0.0],
        steps: 20,
        ..ClimberParams::default()
    };
    let (_, env, g) = grow(&p);
    assert_eq!(g.segment_count(), 0);
    assert_eq!(env.unsupported, 1);
}

#[test]
fn bad_input_is_named() {
    let e = climber(&ClimberParams::default(), &Geometry::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("tree"), "{e}");
    for (name, p) in [
        (
            "ClimberParams::step",
            ClimberParams {
                step: 0.0,
                ..ClimberParams::default()
            },
        ),
        (
            "ClimberParams::start",
            ClimberParams {
                start: [f64::NAN, 0.0, 0.0],
                ..ClimberParams::default()
            },
        ),
        (
            "ClimberParams::crowding",
            ClimberParams {
                crowding: 0,
                ..ClimberParams::default()
            },
        ),
    ] {
        let e = climber(&p, &tree()).unwrap_err().to_string();
        assert!(e.contains(name), "{name}: {e}");
    }
}
