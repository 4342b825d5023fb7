/// The torso's position after standing 0.5 s and walking 2 s at 300.
fn walked(d: &RobotDescription) -> [f64; 3] {
    let mut sim = QuadrupedSim::new(d, SimConfig::default()).expect("a world");
    sim.advance(0.5);
    sim.set_command(300.0).expect("finite");
    sim.advance(2.0);
    assert!(sim.is_upright());
    sim.torso().position_m
}
