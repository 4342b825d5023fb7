use anyhow::Result;
use quadsim::{QuadrupedSim, RobotFile};
fn main() -> Result<()> {
    let a: Vec<String> = std::env::args().collect();
    let file = RobotFile::load(&a[1])?;
    let cfg = file.sim_config();
    let mut sim = QuadrupedSim::new(&file.description, cfg)?;
    sim.set_command(400.0)?;
    while sim.time_s() < 14.0 {
        sim.step();
        if let Some(f) = sim.take_frame() {
            if (f.t_s * 20.0).round() as i64 % 5 == 0 {
                let c = sim.camera_pose();
                println!(
                    "{:.2} d {:.3} obs {:?} cam z {:.3}",
                    f.t_s,
                    sim.distance_along_line_m(),
                    f.obs_px,
                    c.translation.z
                );
            }
        }
    }
    Ok(())
}
