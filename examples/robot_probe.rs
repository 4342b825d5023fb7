use quadsim::{QuadrupedSim, RobotFile, RobotScale, SimConfig};
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let name = std::env::args().nth(1).unwrap_or("trotter".into());
    let robot = RobotFile::load(&name)?;
    let d = &robot.description;
    let scale = RobotScale::of(d);
    println!("{} mass {:.2} kg leg {:.3} m scale {:?}", robot.name, d.total_mass_kg, d.leg_length_m(), scale);
    for frac in [0.0, 0.25, 0.5, 0.75, 1.0, -0.25, -0.5, -1.0] {
        let command = 300.0 * scale.speed() * frac;
        let mut cfg = SimConfig::for_robot(d);
        cfg.start_distance_m = if command >= 0.0 { 4.2 } else { 1.0 } * scale.length;
        let mut sim = QuadrupedSim::new(d, cfg)?;
        sim.advance(1.0);
        sim.set_command(command)?;
        sim.advance(3.0 * scale.time());
        let (d0, t0) = (sim.distance_along_line_m(), sim.time_s());
        let mut upright = true;
        for _ in 0..40 { sim.advance(0.1 * scale.time()); upright &= sim.is_upright(); }
        let v = (d0 - sim.distance_along_line_m()) / (sim.time_s() - t0) * 1000.0;
        let t = sim.torso();
        println!("command {command:7.1}: v {v:7.1} mm/s upright {upright} lateral {:.3} z {:.3} up {:?}", t.position_m[1], t.position_m[2], t.up);
    }
    Ok(())
}
