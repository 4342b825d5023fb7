/// A box quadruped in MJCF: `{base}` is the base body's extra elements,
/// `{leg}` each thigh's, `{compiler}` the compiler's attributes.
fn quadruped(compiler: &str, base: &str, leg: &str) -> String {
    let legs: String = [("fl", 0.15, 0.08), ("fr", 0.15, -0.08), ("hl", -0.15, 0.08), ("hr", -0.15, -0.08)]
        .iter()
        .map(|(n, x, y)| {
            format!(
                r#"<body name="{n}_hip" pos="{x} {y} 0"><joint name="{n}_abd" axis="1 0 0" range="-45 45"/>
                <geom type="sphere" size="0.02" mass="0.1"/>
                <body name="{n}_thigh"><joint name="{n}_hip" axis="0 1 0" range="-90 90"/>{leg}
                <geom type="capsule" fromto="0 0 0 0 0 -0.1" size="0.01" mass="0.2"/>
                <body name="{n}_shank" pos="0 0 -0.1"><joint name="{n}_knee" axis="0 1 0" range="-150 0"/>
                <geom type="capsule" fromto="0 0 0 0 0 -0.1" size="0.01" mass="0.1"/>
                <geom name="{n}_foot" type="sphere" pos="0 0 -0.1" size="0.015" mass="0.02"/>
                </body></body></body>"#
            )
        })
        .collect();
    format!(
        r#"<mujoco model="boxy"><compiler {compiler}/>
        <worldbody><body name="base" pos="0 0 0.3"><freejoint/>
        <geom type="box" size="0.2 0.1 0.05" density="500"/>{base}
        {legs}</body></worldbody></mujoco>"#
    )
}
