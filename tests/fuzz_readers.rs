//! A fuzzing harness for every reader of a file a user gives (issue 61): URDFs
//! (the ERS-7's and the trotter's), MJCF (MuJoCo Menagerie's Go2), robot files, scenario files, mesh files
//! (STL), recorded trials (events, truth and dataset.json) and the learner
//! protocol's lines,
//! each fed arbitrary bytes and mutations of the shipped files (bytes flipped,
//! inserted, deleted, the file cut short, numbers made NaN, infinite, negative,
//! zero or huge). No input may panic: each is read or refused with an error.
//! On the stable toolchain (proptest), with a fixed budget of inputs per
//! reader (`FUZZ_CASES`, default 200), printing how many it tried and the
//! slowest (measured and printed, not asserted: the machines are shared).
//! `cargo test --release --test fuzz_readers -- --nocapture` shows the counts.

use std::cell::{Cell, RefCell};
use std::path::Path;
use std::time::{Duration, Instant};

use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

const ERS7_URDF: &str = include_str!("../assets/ers7.urdf");
const TROTTER_URDF: &str = include_str!("../assets/robots/trotter.urdf");
const GO2_MJCF: &str = include_str!("../assets/robots/menagerie/unitree_go2/go2.xml");
const ERS7_FILE: &str = include_str!("../assets/robots/ers7.toml");
const PAPER: &str = include_str!("../assets/scenarios/paper.toml");
const SPECIALS: [&str; 8] = ["NaN", "inf", "-1", "0", "1e308", "1e-300", "-0", ""];

fn cases() -> u32 {
    std::env::var("FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(200)
}

/// One edit of a file: where (a fraction of its length), what, and a byte.
type Edit = (f64, u8, u8);

/// `seed` with `edits` applied: a byte replaced, inserted or deleted, the
/// file cut short, or the number at that place replaced by a special value.
fn mutate(seed: &[u8], edits: &[Edit]) -> Vec<u8> {
    let mut b = seed.to_vec();
    for &(at, kind, byte) in edits {
        let i = ((b.len() as f64) * at) as usize;
        match kind % 5 {
            0 if i < b.len() => b[i] = byte,
            1 => b.insert(i.min(b.len()), byte),
            2 if i < b.len() => {
                b.remove(i);
            }
            3 => b.truncate(i.max(b.len() / 2)),
            4 => {
                let number = |c: u8| c.is_ascii_digit() || b".eE+-".contains(&c);
                let Some(start) = (i..b.len()).find(|&k| b[k].is_ascii_digit()) else {
                    continue;
                };
                let end = (start..b.len()).find(|&k| !number(b[k])).unwrap_or(b.len());
                let special = SPECIALS[usize::from(byte) % SPECIALS.len()];
                b.splice(start..end, special.bytes());
            }
            _ => {}
        }
    }
    b
}

/// Mutations of `seeds`, and arbitrary bytes.
fn inputs(seeds: &'static [&'static str]) -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        4 => (
            0..seeds.len(),
            proptest::collection::vec((0.0f64..1.0, any::<u8>(), any::<u8>()), 1..8)
        )
            .prop_map(move |(k, edits)| mutate(seeds[k].as_bytes(), &edits)),
        1 => proptest::collection::vec(any::<u8>(), 0..512),
    ]
}

/// Feeds `reader` the fuzzer's inputs; it may refuse any, but not panic.
/// Prints how many inputs it tried, how many it refused, and the slowest.
fn fuzz(name: &str, seeds: &'static [&'static str], reader: impl Fn(&[u8]) -> bool) {
    let mut runner = TestRunner::new(Config {
        cases: cases(),
        failure_persistence: None,
        ..Config::default()
    });
    let (tried, refused, slowest) = (Cell::new(0u32), Cell::new(0u32), Cell::new(Duration::ZERO));
    let worst = RefCell::new(Vec::new());
    let result = runner.run(&inputs(seeds), |bytes| {
        let started = Instant::now();
        let accepted = reader(&bytes);
        let took = started.elapsed();
        tried.set(tried.get() + 1);
        refused.set(refused.get() + u32::from(!accepted));
        if took > slowest.get() {
            slowest.set(took);
            *worst.borrow_mut() = bytes;
        }
        Ok(())
    });
    println!(
        "fuzz {name}: {} inputs, {} refused with an error, none panicked; slowest {:.1} ms ({} bytes)",
        tried.get(),
        refused.get(),
        slowest.get().as_secs_f64() * 1e3,
        worst.borrow().len()
    );
    if let Err(e) = result {
        panic!("{name}: {e}");
    }
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn urdfs_never_panic() {
    fuzz("URDF", &[ERS7_URDF, TROTTER_URDF], |b| {
        quadsim::RobotDescription::from_urdf_str(&text(b)).is_ok()
    });
}

#[test]
fn mjcf_files_never_panic() {
    // Read as a robot is: the MJCF into URDF, its legs found, the robot checked.
    let dir = std::env::temp_dir().join(format!("fuzz-mjcf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let file = dir.join("robot.xml");
    fuzz("MJCF", &[GO2_MJCF], |b| {
        std::fs::write(&file, b).expect("write");
        let Ok(model) = quadsim::mjcf::read(&file) else {
            return false;
        };
        let Ok(map) = quadsim::discover::discover(&model.urdf) else {
            return false;
        };
        quadsim::RobotDescription::from_urdf_in(model.urdf, &map, &dir).is_ok()
    });
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn robot_files_never_panic() {
    let dir = std::env::temp_dir().join(format!("fuzz-robot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    std::fs::write(dir.join("ers7.urdf"), ERS7_URDF).expect("urdf");
    let file = dir.join("robot.toml");
    fuzz("robot file", &[ERS7_FILE], |b| {
        let t = text(b).replace("../ers7.urdf", "ers7.urdf");
        std::fs::write(&file, t).expect("write");
        quadsim::RobotFile::from_file(&file).is_ok()
    });
    let _ = std::fs::remove_dir_all(&dir);
}

/// An ASCII STL tetrahedron, 3 cm across: the seed of the mesh fuzzing.
fn tetrahedron_stl() -> String {
    let p = [
        [0.0, 0.0, 0.0],
        [0.03, 0.0, 0.0],
        [0.0, 0.03, 0.0],
        [0.0, 0.0, 0.03],
    ];
    let mut out = String::from("solid t\n");
    for f in [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]] {
        out += "facet normal 0 0 0\nouter loop\n";
        for v in f {
            let [x, y, z] = p[v];
            out += &format!("vertex {x} {y} {z}\n");
        }
        out += "endloop\nendfacet\n";
    }
    out + "endsolid t\n"
}

#[test]
fn mesh_files_never_panic() {
    // The ERS-7 whose torso collides as a mesh: the fuzzed file.
    let dir = std::env::temp_dir().join(format!("fuzz-mesh-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let urdf = ERS7_URDF.replacen(
        r#"<box size="0.20 0.10 0.08"/>"#,
        r#"<mesh filename="torso.stl"/>"#,
        1,
    );
    std::fs::write(dir.join("robot.urdf"), urdf).expect("urdf");
    let seed: &'static str = Box::leak(tetrahedron_stl().into_boxed_str());
    let seeds: &'static [&'static str] = Box::leak(Box::new([seed]));
    let mesh = dir.join("torso.stl");
    fuzz("mesh (STL)", seeds, |b| {
        std::fs::write(&mesh, b).expect("write");
        quadsim::RobotDescription::from_file(dir.join("robot.urdf")).is_ok()
    });
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn scenario_files_never_panic() {
    let paper = testbed::scenario::Scenario::paper().expect("paper");
    fuzz("scenario", &[PAPER], |b| {
        paper.clone().apply_toml("fuzzed.toml", &text(b)).is_ok()
    });
}

#[test]
fn learner_protocol_lines_never_panic() {
    static LINES: [&str; 3] = [
        r#"{"type":"hello","protocol":1,"name":"mine","about":"x","settings":[{"key":"k","default":2,"min":1,"max":3,"integer":true,"doc":"d"}]}"#,
        r#"{"type":"models","action":[0.0,1.0],"sensor":[3000.0,-10.0],"x_a":1.5,"x_s":null}"#,
        r#"{"type":"error","message":"I refuse"}"#,
    ];
    fuzz("protocol line", &LINES, |b| {
        testbed::learners::exec::protocol::parse(&text(b)).is_ok()
    });
}

#[test]
fn recorded_trials_never_panic() {
    // A short recorded trial of the default world, then each of its three
    // files fuzzed in turn.
    let scenario = {
        let mut s = testbed::scenario::Scenario::paper().expect("paper");
        s.set("trial.duration=5").expect("short");
        s
    };
    let cache = Path::new(env!("CARGO_TARGET_TMPDIR")).join("reference-cache");
    let models = testbed::reference::measured_models(&scenario, Some(&cache)).expect("models");
    let recording = testbed::experiment::record(&scenario, &models, 1).expect("recorded");
    let dir = std::env::temp_dir().join(format!("fuzz-dataset-{}", std::process::id()));
    let meta = testbed::dataset::DatasetMeta::new(
        &scenario,
        &models,
        &recording,
        &testbed::provenance::Provenance::current(),
    );
    testbed::dataset::write(&dir, &recording, &meta).expect("written");
    for name in ["events.csv", "truth.csv", "dataset.json"] {
        let path = dir.join(name);
        let original: &'static str = Box::leak(
            std::fs::read_to_string(&path)
                .expect("read")
                .into_boxed_str(),
        );
        let seeds: &'static [&'static str] = Box::leak(Box::new([original]));
        fuzz(&format!("recorded trial's {name}"), seeds, |b| {
            std::fs::write(&path, b).expect("write");
            testbed::dataset::read(&dir).is_ok()
        });
        std::fs::write(&path, original).expect("restore");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
