//! Open L-systems: the environment sees exactly the `?E` modules, in string
//! order, with the turtle state, and its replies land in those modules.

use natura_plant::{
    Derivation, Environment, LSystem, Message, PlantError, Reply, Turtle, TurtleParams,
};

#[derive(Default)]
struct Recorder {
    seen: Vec<Vec<Message>>,
}

impl Environment for Recorder {
    fn respond(
        &mut self,
        _step: u32,
        m: &[Message],
        r: &mut Vec<Reply>,
    ) -> natura_plant::Result<()> {
        self.seen.push(m.to_vec());
        for msg in m {
            // Answer every other module with its height.
            if msg.address % 2 == 0 {
                r.push(Reply {
                    address: msg.address,
                    values: vec![msg.state.frame.p.z],
                });
            }
        }
        Ok(())
    }
}

#[test]
fn environment_sees_exactly_the_communication_modules() {
    let src = "ω: A
        A -> F[+F?E(0)B]F?E(1)A
        ?E(x) -> ε
        B -> B";
    let l = LSystem::parse(src).unwrap();
    let t = Turtle::new(&l, TurtleParams::default()).unwrap();
    let mut d = Derivation::new(&l, 0).unwrap();
    let mut env = Recorder::default();
    for _ in 0..4 {
        d.step_open(&t, &mut env).unwrap();
        let s = d.string();
        let e = l.symbol("?E").unwrap();
        let addrs: Vec<usize> = (0..s.len()).filter(|&i| s.symbol(i) == e).collect();
        let got: Vec<usize> = env.seen.last().unwrap().iter().map(|m| m.address).collect();
        // Only the ?E of the newest step exist (older ones were erased).
        assert_eq!(got, addrs);
        assert_eq!(addrs.len(), 2);
        for &a in &addrs {
            if a % 2 == 0 {
                // The reply is the turtle's height at the module.
                let m = env
                    .seen
                    .last()
                    .unwrap()
                    .iter()
                    .find(|m| m.address == a)
                    .unwrap();
                assert_eq!(s.params(a)[0], m.state.frame.p.z);
            }
        }
    }
    // Step 4: the main-axis ?E sits at height 4 + 4 = 8 (two F per step... one F before the
    // bracket and one after), the branch ?E at 7 + cos(90°) = 7.
    let last = env.seen.last().unwrap();
    assert!(
        (last[1].state.frame.p.z - 8.0).abs() < 1e-9,
        "{:?}",
        last[1].state.frame.p
    );
    assert_eq!(last[0].values, vec![0.0]);
    assert_eq!(last[1].values, vec![1.0]);
}

struct Liar;
impl Environment for Liar {
    fn respond(&mut self, _: u32, m: &[Message], r: &mut Vec<Reply>) -> natura_plant::Result<()> {
        r.push(Reply {
            address: m[0].address + 1,
            values: vec![1.0],
        });
        Ok(())
    }
}

struct TooMany;
impl Environment for TooMany {
    fn respond(&mut self, _: u32, m: &[Message], r: &mut Vec<Reply>) -> natura_plant::Result<()> {
        r.push(Reply {
            address: m[0].address,
            values: vec![1.0, 2.0],
        });
        Ok(())
    }
}

#[test]
fn bad_replies_are_typed_errors() {
    let l = LSystem::parse("ω: ?E(0)A").unwrap();
    let t = Turtle::new(&l, TurtleParams::default()).unwrap();
    let mut d = Derivation::new(&l, 0).unwrap();
    assert!(matches!(
        d.communicate(&t, &mut Liar),
        Err(PlantError::Environment { .. })
    ));
    assert!(matches!(
        d.communicate(&t, &mut TooMany),
        Err(PlantError::Environment { .. })
    ));
}
