//! Writes the upstream fixture (see Cargo.toml): one line per physics step,
//! `x y z qx qy qz qw`, each number as Rust prints an f64 (it reads back to
//! the same bits).

include!("../../../crates/quadsim/tests/common/track.rs");

fn main() -> std::io::Result<()> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../crates/quadsim/tests/fixtures/upstream_track.txt");
    let mut text = String::from(
        "# The ERS-7's torso after each 4 ms step (0.5 s standing, 1.2 s at 300, 0.8 s at -200),\n\
         # stepped by rapier3d 0.36.1 as published: x y z (m) qx qy qz qw.\n\
         # Written by tools/upstream-fixture.\n",
    );
    for pose in torso_track() {
        let cells: Vec<String> = pose.iter().map(f64::to_string).collect();
        text.push_str(&cells.join(" "));
        text.push('\n');
    }
    std::fs::write(&path, text)?;
    println!("wrote {}", path.display());
    Ok(())
}
