//! Round-trips of every parameter struct through TOML (`--features serde`):
//! values come back identical, and invalid values read from a file are still
//! refused by validation (deserialisation never bypasses it).
#![cfg(feature = "serde")]

use natura_fluid::liquid::LiquidParams;
use natura_fluid::pressure::SolverParams;
use natura_fluid::smoke::SmokeParams;
use natura_fluid::stable::StableParams;
use serde::{Deserialize, Serialize};

#[derive(Debug, PartialEq, Serialize, Deserialize)]
struct Everything {
    liquid: LiquidParams,
    solver: SolverParams,
    smoke: SmokeParams,
    stable: StableParams,
}

#[test]
fn every_params_struct_round_trips_through_toml() {
    let e = Everything {
        liquid: LiquidParams::default(),
        solver: SolverParams::default(),
        smoke: SmokeParams::default(),
        stable: StableParams::default(),
    };
    let text = toml::to_string(&e).unwrap();
    let back: Everything = toml::from_str(&text).unwrap();
    assert_eq!(back, e);

    let mut bad = back;
    bad.liquid.max_cfl = 1e30;
    let text = toml::to_string(&bad).unwrap();
    let again: Everything = toml::from_str(&text).unwrap();
    let err = again.liquid.validate().unwrap_err().to_string();
    assert!(err.contains("max_cfl"), "{err}");
}

/// The smoke's sources and obstacles as a scene file would hold them: the
/// shapes tagged by `kind`, optional fields left out, and an unknown key or
/// kind refused by name.
#[test]
fn sources_obstacles_and_shapes_read_from_toml() {
    use natura_fluid::glam::{Quat, Vec3};
    use natura_fluid::shape::{Obstacle, Shape};
    use natura_fluid::smoke::SmokeSource;

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct Set {
        source: Vec<SmokeSource>,
        obstacle: Vec<Obstacle>,
    }
    let text = r#"
        [[source]]
        shape = { kind = "sphere", centre = [0.5, 0.5, 0.2], radius = 0.1 }
        density = 1.0
        temperature = 330.0
        velocity = [0.0, 0.0, 0.3]

        [[source]]
        shape = { kind = "cuboid", min = [0.1, 0.1, 0.0], max = [0.2, 0.2, 0.1] }
        density = 0.5
        temperature = 300.0

        [[obstacle]]
        shape = { kind = "oriented_box", centre = [0.5, 0.5, 0.6], half = [0.2, 0.1, 0.05], rotation = [0.0, 0.0, 0.38268343, 0.9238795] }
        angular_velocity = [0.0, 0.0, 1.0]

        [[obstacle]]
        shape = { kind = "ellipsoid", centre = [0.3, 0.25, 0.1], radii = [0.22, 0.07, 0.07], rotation = [0.0, 0.0, 0.0, 1.0] }
        velocity = [0.9, 0.0, 0.0]
    "#;
    let set: Set = toml::from_str(text).unwrap();
    assert_eq!(
        set.source[0].shape,
        Shape::Sphere {
            centre: Vec3::new(0.5, 0.5, 0.2),
            radius: 0.1
        }
    );
    assert_eq!(set.source[0].velocity, Some(Vec3::new(0.0, 0.0, 0.3)));
    assert_eq!(set.source[1].velocity, None);
    let o = set.obstacle[0];
    assert_eq!(o.velocity, Vec3::ZERO);
    assert_eq!(o.temperature, None);
    assert_eq!(
        o.shape,
        Shape::OrientedBox {
            centre: Vec3::new(0.5, 0.5, 0.6),
            half: Vec3::new(0.2, 0.1, 0.05),
            rotation: Quat::from_xyzw(0.0, 0.0, 0.382_683_43, 0.923_879_5),
        }
    );
    assert_eq!(
        set.obstacle[1].shape,
        Shape::Ellipsoid {
            centre: Vec3::new(0.3, 0.25, 0.1),
            radii: Vec3::new(0.22, 0.07, 0.07),
            rotation: Quat::IDENTITY,
        }
    );
    assert_eq!(set.obstacle[1].velocity, Vec3::new(0.9, 0.0, 0.0));
    // Written and read back, the same.
    let back: Set = toml::from_str(&toml::to_string(&set).unwrap()).unwrap();
    assert_eq!(back, set);
    // An unknown kind or key is refused naming it.
    let tail = "density = 1.0\ntemperature = 300.0\n";
    for (bad, name) in [
        (
            format!(
                "shape = {{ kind = \"ball\", centre = [0.0, 0.0, 0.0], radius = 1.0 }}\n{tail}"
            ),
            "ball",
        ),
        (
            format!(
                "shape = {{ kind = \"sphere\", centre = [0.0, 0.0, 0.0], radius = 1.0, size = 2.0 }}\n{tail}"
            ),
            "size",
        ),
        (
            format!(
                "shape = {{ kind = \"sphere\", centre = [0.0, 0.0, 0.0], radius = 1.0 }}\n{tail}heat = 1.0\n"
            ),
            "heat",
        ),
    ] {
        let e = toml::from_str::<SmokeSource>(&bad).unwrap_err().to_string();
        assert!(e.contains(name), "{e}");
    }
    // A rotation that is not a unit quaternion is refused by validation.
    let squashed = Shape::OrientedBox {
        centre: Vec3::splat(0.5),
        half: Vec3::splat(0.1),
        rotation: Quat::from_xyzw(0.0, 0.0, 0.0, 2.0),
    };
    let e = squashed.validate().unwrap_err().to_string();
    assert!(e.contains("unit quaternion"), "{e}");
}
